// Scene loading: JSON text -> Scene, rejecting anything a user could have meant differently.
//
// Parsing goes through nlohmann's SAX interface rather than json::parse so that duplicate keys and
// number overflow (1e999) are caught with the key path where they occur, and every syntax error gets
// a line and column. The document is then read section by section; each reader lists the keys it
// accepts, so a misspelt key is an error instead of a silently ignored line.
#include "core/scene.hpp"

#include "core/cloth_mesh.hpp"
#include "core/input_file.hpp"
#include "core/memory_stage.hpp"
#include "core/mesh_obstacle.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cfloat>
#include <climits>
#include <cmath>
#include <cstring>
#include <initializer_list>
#include <optional>
#include <sstream>
#include <string_view>

namespace drape {
namespace {

// Ordered, so that "the first unknown key" is the first one in the file, not the first alphabetically.
using Json = nlohmann::ordered_json;

// Scenes need four levels; anything far deeper is not a scene and is refused before it costs memory.
constexpr std::size_t kMaxNesting = 32;

std::string show(double v) {
  std::ostringstream s;
  s.precision(10);
  s << v;
  return s.str();
}

std::string show(const Json& j) {
  std::string s = j.dump(-1, ' ', true, Json::error_handler_t::replace);
  return s.size() <= 40 ? s : s.substr(0, 37) + "...";
}

// A key as it appears in a key path; keys with control or non-ASCII characters are shown escaped and
// quoted, so that a message stays one readable line whatever the file contains.
std::string keyText(const std::string& key) {
  bool plain =
      !key.empty() && std::all_of(key.begin(), key.end(), [](char c) { return c > 0x20 && c < 0x7f && c != '"'; });
  return plain ? key : Json(key).dump(-1, ' ', true, Json::error_handler_t::replace);
}

// 1-based line and column of the character at `index`, counting columns in bytes.
std::string lineAndColumn(const std::string& text, std::size_t index) {
  std::size_t line = 1 + std::count(text.begin(), text.begin() + std::ptrdiff_t(index), '\n');
  std::size_t line_start = text.rfind('\n', index == 0 ? 0 : index - 1);
  line_start = (line_start == std::string::npos || line_start >= index) ? 0 : line_start + 1;
  return "line " + std::to_string(line) + ", column " + std::to_string(index - line_start + 1);
}

// nlohmann reports the number of characters read, which may include the whitespace or end of input
// after the culprit; pointing at the last non-blank character read is what an editor user expects.
std::size_t errorIndex(const std::string& text, std::size_t chars_read) {
  if (text.empty()) return 0;
  std::size_t i = std::min(chars_read == 0 ? 0 : chars_read - 1, text.size() - 1);
  while (i > 0 && std::strchr(" \t\r\n", text[i]) != nullptr)
    --i;
  return i;
}

// nlohmann's message without its "[json.exception.parse_error.101] parse error at ...: " prefix.
std::string errorDetail(const std::string& what) {
  std::string s = what;
  if (!s.empty() && s[0] == '[') {
    std::size_t end = s.find("] ");
    if (end != std::string::npos) s.erase(0, end + 2);
  }
  if (s.rfind("parse error", 0) == 0) {
    std::size_t colon = s.find(": ");
    if (colon != std::string::npos) s.erase(0, colon + 2);
  }
  std::replace(s.begin(), s.end(), '\n', ' ');
  return s;
}

// Builds the document while tracking where it is, so that errors can name the key path.
class DocumentBuilder {
 public:
  DocumentBuilder(const std::string& file, const std::string& text) : file_(file), text_(text) {}

  bool null() { return add(Json(nullptr)); }
  bool boolean(bool v) { return add(v); }
  bool number_integer(Json::number_integer_t v) { return add(v); }
  bool number_unsigned(Json::number_unsigned_t v) { return add(v); }
  bool number_float(Json::number_float_t v, const Json::string_t&) { return add(v); }
  bool string(Json::string_t& v) { return add(std::move(v)); }
  bool binary(Json::binary_t& v) { return add(std::move(v)); }
  bool start_object(std::size_t) { return open(Json::object()); }
  bool start_array(std::size_t) { return open(Json::array()); }
  bool end_object() { return close(); }
  bool end_array() { return close(); }

  bool key(Json::string_t& k) {
    Frame& top = frames_.back();
    top.key = k;
    if (top.node->contains(k)) return fail(pendingPath(), "duplicate key");
    return true;
  }

  bool parse_error(std::size_t chars_read, const std::string&, const Json::exception& e) {
    std::string where = lineAndColumn(text_, errorIndex(text_, chars_read));
    // 406 is number overflow: the text is valid JSON, but the value is not a finite double.
    if (e.id == 406) return fail(pendingPath(), "number too large (" + errorDetail(e.what()) + ", " + where + ")");
    return fail(where, "invalid JSON: " + errorDetail(e.what()));
  }

  Json& document() { return root_; }
  const std::string& error() const { return error_; }

 private:
  struct Frame {
    Json* node;
    std::string key;  // objects: the key whose value is being read
  };

  bool fail(const std::string& where, const std::string& problem) {
    error_ = file_ + ": " + where + ": " + problem;
    return false;
  }

  Json* insert(Json&& v) {
    if (frames_.empty()) {
      root_ = std::move(v);
      return &root_;
    }
    Json& parent = *frames_.back().node;
    if (parent.is_array()) {
      parent.push_back(std::move(v));
      return &parent.back();
    }
    return &(parent[frames_.back().key] = std::move(v));
  }
  bool add(Json v) {
    insert(std::move(v));
    return true;
  }

  bool open(Json empty) {
    if (frames_.size() >= kMaxNesting) {
      return fail(pendingPath(), "nested more than " + std::to_string(kMaxNesting) + " levels deep");
    }
    // Values are only appended to the innermost container, so pointers to outer ones stay valid.
    frames_.push_back({insert(std::move(empty)), {}});
    return true;
  }

  bool close() {
    frames_.pop_back();
    return true;
  }

  // Path of the value about to be added to the innermost container.
  std::string pendingPath() const {
    std::string path;
    for (std::size_t i = 0; i < frames_.size(); ++i) {
      const Frame& f = frames_[i];
      bool inner = i + 1 < frames_.size();  // its child is already in place
      if (f.node->is_array()) {
        path += "[" + std::to_string(f.node->size() - (inner ? 1 : 0)) + "]";
      } else {
        path += (path.empty() ? "" : ".") + keyText(f.key);
      }
    }
    return path.empty() ? "top level" : path;
  }

  const std::string& file_;
  const std::string& text_;
  Json root_;
  std::vector<Frame> frames_;
  std::string error_;
};

std::size_t editDistance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j)
    row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      std::size_t next = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = row[j];
      row[j] = next;
    }
  }
  return row[b.size()];
}

// A value in the document together with its key path, so that every check can say where it failed.
class Node {
 public:
  Node(const std::string& file, const Json& json, std::string path)
      : file_(&file), json_(&json), path_(std::move(path)) {}

  [[noreturn]] void fail(const std::string& problem) const { throw SceneError(*file_ + ": " + path_ + ": " + problem); }

  Node child(const std::string& key) const { return {*file_, json_->at(key), join(key)}; }
  Node element(std::size_t i) const { return {*file_, json_->at(i), path_ + "[" + std::to_string(i) + "]"}; }

  std::optional<Node> find(const char* key) const {
    if (!json_->contains(key)) return std::nullopt;
    return child(key);
  }

  Node require(const char* key) const {
    if (!json_->contains(key)) throw SceneError(*file_ + ": " + join(key) + ": missing required key");
    return child(key);
  }

  // An object whose keys are all in `allowed`.
  void expectObject(std::initializer_list<std::string_view> allowed) const {
    if (!json_->is_object()) fail(std::string("expected an object, got ") + json_->type_name());
    for (const auto& [key, value] : json_->items()) {
      if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) continue;
      std::string problem = "unknown key";
      for (std::string_view candidate : allowed) {
        if (editDistance(key, candidate) <= 2) {
          problem += " (did you mean '" + std::string(candidate) + "'?)";
          break;
        }
      }
      child(key).fail(problem);
    }
  }

  std::size_t arraySize() const {
    if (!json_->is_array()) fail(std::string("expected an array, got ") + json_->type_name());
    return json_->size();
  }

  // The float solvers get every value: one beyond float's range would be infinite there. Only a
  // plane's normal, normalised in double on load, may be larger (`in_float` false).
  double number(bool in_float = true) const {
    if (!json_->is_number()) fail(std::string("expected a number, got ") + json_->type_name());
    double v = json_->get<double>();
    if (!std::isfinite(v)) fail("not a finite number");
    if (in_float && std::fabs(v) > double(FLT_MAX))
      fail("out of float range (got " + show(v) + ", at most " + show(FLT_MAX) + ")");
    return v;
  }

  // Integers may be written as 50 or 50.0 (CS184's loader converts either).
  long long integer() const {
    if (json_->is_number_unsigned()) {
      auto v = json_->get<Json::number_unsigned_t>();
      if (v > static_cast<Json::number_unsigned_t>(LLONG_MAX)) fail("integer out of range");
      return static_cast<long long>(v);
    }
    if (json_->is_number_integer()) return json_->get<Json::number_integer_t>();
    double v = number();
    if (v != std::floor(v)) fail("expected an integer, got " + show(v));
    if (std::fabs(v) > 9.0e18) fail("integer out of range");
    return static_cast<long long>(v);
  }

  std::string text() const {
    if (!json_->is_string()) fail(std::string("expected a string, got ") + json_->type_name());
    return json_->get<std::string>();
  }

  bool boolean() const {
    if (!json_->is_boolean()) fail(std::string("expected true or false, got ") + json_->type_name());
    return json_->get<bool>();
  }

  glm::dvec3 vec3(bool in_float = true) const {
    if (!json_->is_array() || json_->size() != 3) fail("expected [x, y, z], got " + show(*json_));
    return {element(0).number(in_float), element(1).number(in_float), element(2).number(in_float)};
  }

 private:
  std::string join(const std::string& key) const { return (path_.empty() ? "" : path_ + ".") + keyText(key); }

  const std::string* file_;
  const Json* json_;
  std::string path_;
};

// Positive values are divided by (thickness, noise_scale, ...) or multiplied into a divisor, so they must
// stay positive in float: 1e-300 is 0 there, a denormal's reciprocal is infinite.
double positive(const Node& n) {
  double v = n.number();
  if (!(v > 0.0)) n.fail("must be > 0 (got " + show(v) + ")");
  if (v < double(FLT_MIN))
    n.fail("too small: " + show(v) + " is 0 or denormal in float (at least " + show(FLT_MIN) + ")");
  return v;
}

double atLeast(const Node& n, double lo) {
  double v = n.number();
  if (!(v >= lo)) n.fail("must be >= " + show(lo) + " (got " + show(v) + ")");
  return v;
}

double between(const Node& n, double lo, double hi) {
  double v = n.number();
  if (!(v >= lo && v <= hi)) n.fail("must be in [" + show(lo) + ", " + show(hi) + "] (got " + show(v) + ")");
  return v;
}

int integerBetween(const Node& n, long long lo, long long hi) {
  long long v = n.integer();
  if (v < lo) n.fail("must be >= " + std::to_string(lo) + " (got " + std::to_string(v) + ")");
  if (v > hi) n.fail("must be <= " + std::to_string(hi) + " (got " + std::to_string(v) + ")");
  return static_cast<int>(v);
}

int integerAtLeast(const Node& n, long long lo) {
  return integerBetween(n, lo, INT_MAX);
}

std::vector<glm::ivec2> readPins(const Node& n, int W, int H) {
  std::vector<glm::ivec2> pins;
  for (std::size_t i = 0, count = n.arraySize(); i < count; ++i) {
    Node pin = n.element(i);
    if (pin.arraySize() != 2)
      pin.fail("expected [x, y] grid coordinates, got an array of " + std::to_string(pin.arraySize()));
    long long x = pin.element(0).integer();
    long long y = pin.element(1).integer();
    if (x < 0 || x >= W || y < 0 || y >= H) {
      pin.fail("[" + std::to_string(x) + ", " + std::to_string(y) + "] is outside the " + std::to_string(W) + " x " +
               std::to_string(H) + " grid (x in [0, " + std::to_string(W - 1) + "], y in [0, " + std::to_string(H - 1) +
               "])");
    }
    pins.emplace_back(int(x), int(y));
  }
  return pins;
}

// The keys that make a grid; a mesh cloth takes its shape from the mesh instead.
constexpr const char* kGridKeys[] = {"width",       "height", "num_width_points", "num_height_points",
                                     "orientation", "pinned"};

void readGrid(const Node& n, ClothSpec& c) {
  c.width = positive(n.require("width"));
  c.height = positive(n.require("height"));
  c.num_width_points = integerAtLeast(n.require("num_width_points"), 2);
  c.num_height_points = integerAtLeast(n.require("num_height_points"), 2);
  long long points = static_cast<long long>(c.num_width_points) * c.num_height_points;
  if (points > kMaxClothPoints) {
    n.fail("grid too large: " + std::to_string(c.num_width_points) + " x " + std::to_string(c.num_height_points) +
           " = " + std::to_string(points) + " points (at most " + std::to_string(kMaxClothPoints) + ")");
  }
  c.thickness = positive(n.require("thickness"));
  Node orientation = n.require("orientation");
  long long o = orientation.integer();
  if (o != 0 && o != 1) orientation.fail("must be 0 (horizontal) or 1 (vertical), got " + std::to_string(o));
  c.orientation = static_cast<Orientation>(o);
  if (auto v = n.find("pinned")) c.pinned = readPins(*v, c.num_width_points, c.num_height_points);
}

// The mesh file is found relative to the scene file, as a user who keeps the two side by side expects.
void readMesh(const Node& n, ClothSpec& c, const std::string& scene_file) {
  for (const char* key : kGridKeys)
    if (auto v = n.find(key)) v->fail("not used with 'mesh' (a mesh cloth takes its shape from the mesh)");
  Node mesh = n.child("mesh");
  c.mesh_file = mesh.text();
  if (c.mesh_file.empty()) mesh.fail("empty path");
  const std::filesystem::path file = std::filesystem::path(scene_file).parent_path() / c.mesh_file;
  try {
    const MemoryStage stage("reading the cloth mesh " + file.string());
    c.mesh = std::make_shared<const ClothMesh>(
        buildClothMesh(readObj(file, {kMaxClothPoints, " (the most a cloth may have)"})));
  } catch (const MeshError& e) {
    mesh.fail(file.string() + ": " + e.what());
  }
  c.thickness = positive(n.require("thickness"));
}

std::vector<std::uint32_t> readVertexPins(const Node& n, int points) {
  std::vector<std::uint32_t> pins;
  for (std::size_t i = 0, count = n.arraySize(); i < count; ++i) {
    Node pin = n.element(i);
    long long v = pin.integer();
    if (v < 0 || v >= points)
      pin.fail(std::to_string(v) + " is not a point of this cloth (0 to " + std::to_string(points - 1) + ")");
    pins.push_back(std::uint32_t(v));
  }
  return pins;
}

void readPinBox(const Node& n, ClothSpec& c) {
  if (n.arraySize() != 2)
    n.fail("expected [[x0, y0, z0], [x1, y1, z1]], got " + std::to_string(n.arraySize()) + " corners");
  c.pin_box_min = n.element(0).vec3();
  c.pin_box_max = n.element(1).vec3();
  for (int k = 0; k < 3; ++k)
    if (!(c.pin_box_min[k] <= c.pin_box_max[k])) n.element(1).fail("each coordinate must be >= the first corner's");
  c.has_pin_box = true;
}

ClothSpec readCloth(const Node& n, const std::string& scene_file) {
  n.expectObject({"width", "height", "num_width_points", "num_height_points", "thickness", "orientation", "pinned",
                  "enable_structural", "enable_shearing", "enable_bending", "damping", "density", "ks", "mesh",
                  "pinned_vertices", "pin_box"});
  ClothSpec c;
  if (n.find("mesh"))
    readMesh(n, c, scene_file);
  else
    readGrid(n, c);
  if (auto v = n.find("pinned_vertices")) c.pinned_vertices = readVertexPins(*v, c.pointCount());
  if (auto v = n.find("pin_box")) readPinBox(*v, c);
  if (auto v = n.find("enable_structural")) c.enable_structural = v->boolean();
  if (auto v = n.find("enable_shearing")) c.enable_shearing = v->boolean();
  if (auto v = n.find("enable_bending")) c.enable_bending = v->boolean();
  if (auto v = n.find("damping")) c.damping = between(*v, 0.0, 100.0);
  if (auto v = n.find("density")) c.density = positive(*v);
  if (auto v = n.find("ks")) c.ks = positive(*v);
  return c;
}

SphereSpec readSphere(const Node& n) {
  n.expectObject({"origin", "radius", "friction"});
  SphereSpec s;
  s.origin = n.require("origin").vec3();
  s.radius = positive(n.require("radius"));
  if (auto v = n.find("friction")) s.friction = between(*v, 0.0, 1.0);
  return s;
}

PlaneSpec readPlane(const Node& n) {
  n.expectObject({"point", "normal", "friction"});
  PlaneSpec p;
  p.point = n.require("point").vec3();
  Node normal = n.require("normal");
  glm::dvec3 v = normal.vec3(/*in_float=*/false);
  // Scaled by the largest component first, so that neither 1e-200 nor 1e200 under- or overflows.
  double largest = std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)});
  if (largest == 0.0) normal.fail("zero length, a plane needs a direction");
  p.normal = glm::normalize(v / largest);
  if (auto f = n.find("friction")) p.friction = between(*f, 0.0, 1.0);
  return p;
}

// `vertices_used`: what the obstacles before this one read, of kMaxObstacleVertices.
MeshSpec readMeshObstacle(const Node& n, const std::string& scene_file, long long& vertices_used) {
  n.expectObject({"obj", "offset", "scale", "friction", "thickness"});
  MeshSpec m;
  Node obj = n.require("obj");
  m.obj = obj.text();
  if (m.obj.empty()) obj.fail("empty path");
  if (auto v = n.find("offset")) m.offset = v->vec3();
  if (auto v = n.find("scale")) m.scale = positive(*v);
  if (auto v = n.find("friction")) m.friction = between(*v, 0.0, 1.0);
  if (auto v = n.find("thickness")) m.thickness = positive(*v);
  const std::filesystem::path file = std::filesystem::path(scene_file).parent_path() / m.obj;
  const long long left = kMaxObstacleVertices - vertices_used;
  const std::string note = vertices_used == 0
                               ? " (the most the obstacles may have)"
                               : " (the obstacles may have " + std::to_string(kMaxObstacleVertices) +
                                     " in all; those before this one have " + std::to_string(vertices_used) + ")";
  try {
    const MemoryStage stage("reading and baking the obstacle " + file.string());
    const PolygonMesh mesh = readObj(file, {left, note});
    vertices_used += (long long)mesh.positions.size();
    m.mesh = std::make_shared<const MeshObstacle>(buildMeshObstacle(mesh, m.offset, m.scale));
  } catch (const MeshError& e) {
    obj.fail(file.string() + ": " + e.what());
  }
  return m;
}

WindSpec readWind(const Node& n) {
  n.expectObject({"enabled", "velocity", "turbulence", "noise_scale", "noise_speed", "drag"});
  WindSpec w;
  w.enabled = true;  // writing a wind section is asking for wind
  if (auto v = n.find("enabled")) w.enabled = v->boolean();
  if (auto v = n.find("velocity")) w.velocity = v->vec3();
  if (auto v = n.find("turbulence")) w.turbulence = atLeast(*v, 0.0);
  if (auto v = n.find("noise_scale")) w.noise_scale = positive(*v);
  if (auto v = n.find("noise_speed")) w.noise_speed = atLeast(*v, 0.0);
  if (auto v = n.find("drag")) w.drag = atLeast(*v, 0.0);
  return w;
}

StretchScheme readStretchScheme(const Node& n) {
  const std::string name = n.text();
  for (StretchScheme s : {StretchScheme::GaussSeidel, StretchScheme::Jacobi})
    if (name == stretchSchemeName(s)) return s;
  n.fail("unknown scheme '" + name + "' (gauss_seidel or jacobi)");
}

Integrator readIntegrator(const Node& n) {
  const std::string name = n.text();
  for (Integrator i : kIntegrators)
    if (name == integratorName(i)) return i;
  n.fail("unknown integrator '" + name + "' (verlet, xpbd or vbd)");
}

SimParams readSimulation(const Node& n) {
  n.expectObject({"frames_per_sec", "steps_per_frame", "gravity", "self_collision", "stretch_passes", "stretch_limit",
                  "stretch_scheme", "tethers", "integrator", "iterations", "wind"});
  SimParams s;
  if (auto v = n.find("frames_per_sec")) s.frames_per_sec = positive(*v);
  if (auto v = n.find("steps_per_frame")) s.steps_per_frame = integerBetween(*v, 1, kMaxStepsPerFrame);
  if (auto v = n.find("gravity")) s.gravity = v->vec3();
  if (auto v = n.find("self_collision")) s.self_collision = v->boolean();
  if (auto v = n.find("stretch_passes")) s.stretch_passes = integerBetween(*v, 0, kMaxStretchPasses);
  if (auto v = n.find("stretch_limit")) s.stretch_limit = atLeast(*v, 1.0);
  if (auto v = n.find("stretch_scheme")) s.stretch_scheme = readStretchScheme(*v);
  if (auto v = n.find("tethers")) s.tethers = v->boolean();
  if (auto v = n.find("integrator")) s.integrator = readIntegrator(*v);
  if (auto v = n.find("iterations")) s.iterations = integerBetween(*v, 1, kMaxIterations);
  if (auto v = n.find("wind")) s.wind = readWind(*v);
  return s;
}

// The count is checked before any element is read: each may cost a file and a bake.
void checkCount(const Node& list, std::size_t before, int most, const char* what) {
  const std::size_t count = list.arraySize();
  if (before + count > std::size_t(most))
    list.fail(std::to_string(before + count) + " " + what + ", more than the " + std::to_string(most) +
              " a scene may have");
}

template <class Spec, class Read>
void readColliders(const Node& root, const char* single, const char* list, int most, Read read,
                   std::vector<Spec>& out) {
  if (auto v = root.find(single)) out.push_back(read(*v));
  if (auto v = root.find(list)) {
    checkCount(*v, out.size(), most, list);
    for (std::size_t i = 0, count = v->arraySize(); i < count; ++i)
      out.push_back(read(v->element(i)));
  }
}

// Self-collision's work and memory grow with the neighbours each point has within the contact distance:
// a thickness large against the point spacing makes it compare nearly every pair.
void checkSelfCollisionLoad(const Scene& scene, const Node& root) {
  const ClothSpec& c = scene.cloth;
  if (!scene.sim.self_collision) return;
  const double points = double(c.pointCount());
  double per_point = 0;  // m^2 of cloth a point
  if (c.mesh) {
    for (double a : c.mesh->area)
      per_point += a / points;
  } else {
    per_point = c.width / (c.num_width_points - 1) * (c.height / (c.num_height_points - 1));
  }
  const double reach = 2.0 * c.thickness;
  const double neighbours = 3.141592653589793 * reach * reach / per_point;
  const double pairs = neighbours * points / 2;
  const auto brief = [](double v) {
    std::ostringstream s;
    s.precision(4);
    s << v;
    return s.str();
  };
  const auto count = [](double v) { return std::to_string((long long)std::llround(v)); };
  const char* fix = "; a smaller thickness or simulation.self_collision false";
  if (neighbours > kMaxSelfCollisionNeighbours)
    root.child("cloth")
        .child("thickness")
        .fail(brief(c.thickness) + " m against " + brief(std::sqrt(per_point)) +
              " m between points: self-collision would compare each point with about " + count(neighbours) +
              " others within 2 x thickness (at most " + count(kMaxSelfCollisionNeighbours) + ")" + fix);
  if (pairs > kMaxSelfCollisionPairs)
    root.child("cloth")
        .child("thickness")
        .fail(brief(c.thickness) + " m on " + count(points) + " points: self-collision would list about " +
              count(pairs) + " pairs within 2 x thickness (at most " + count(kMaxSelfCollisionPairs) + ")" + fix);
}

// A value the solvers divide by: it must be a normal float, neither 0 nor infinite there.
bool normalFloat(double v) {
  return std::fabs(v) >= double(FLT_MIN) && std::fabs(v) <= double(FLT_MAX);
}

// Quantities made from several keys, each valid alone, that the solvers divide by or square.
void checkDerived(const Scene& scene, const Node& root) {
  const ClothSpec& c = scene.cloth;
  const Node cloth = root.child("cloth");
  if (c.mesh) {
    for (double area : c.mesh->area)
      if (!normalFloat(c.density * area))
        cloth.fail("mass of a point density x its area = " + show(c.density * area) + " kg is 0 or infinite in float");
  } else {
    const double mass = c.width * c.height * c.density / double(c.pointCount());
    if (!normalFloat(mass))
      cloth.fail("mass per point width x height x density / points = " + show(mass) + " kg is 0 or infinite in float");
    const double spacing_x = c.width / (c.num_width_points - 1), spacing_y = c.height / (c.num_height_points - 1);
    if (!normalFloat(spacing_x) || !normalFloat(spacing_y))
      cloth.fail("point spacing " + show(spacing_x) + " x " + show(spacing_y) + " m is 0 in float");
  }
  // Verlet multiplies by dt^2: its square must be a normal float too.
  const double dt = scene.sim.dt();
  if (!normalFloat(dt * dt))
    throw SceneError(scene.path + ": simulation.frames_per_sec: time step 1 / (frames_per_sec x steps_per_frame) = " +
                     show(dt) + " s: its square is 0 or infinite in float");
}

}  // namespace

Scene parseScene(const std::string& json_text, const std::string& name) {
  DocumentBuilder builder(name, json_text);
  if (!Json::sax_parse(json_text, &builder)) throw SceneError(builder.error());

  Node root(name, builder.document(), "");
  if (!builder.document().is_object()) {
    throw SceneError(name + ": top level: expected an object, got " + builder.document().type_name());
  }
  root.expectObject({"cloth", "sphere", "plane", "spheres", "planes", "meshes", "simulation"});

  Scene scene;
  scene.path = name;
  scene.cloth = readCloth(root.require("cloth"), name);
  readColliders(root, "sphere", "spheres", kMaxSpheres, readSphere, scene.spheres);
  readColliders(root, "plane", "planes", kMaxPlanes, readPlane, scene.planes);
  if (auto v = root.find("simulation")) scene.sim = readSimulation(*v);
  checkDerived(scene, root);
  checkSelfCollisionLoad(scene, root);
  // Last: reading and baking the obstacles is the costly part, spent only on a scene otherwise valid.
  if (auto v = root.find("meshes")) {
    checkCount(*v, 0, kMaxMeshes, "meshes");
    long long vertices_used = 0;
    for (std::size_t i = 0, count = v->arraySize(); i < count; ++i)
      scene.meshes.push_back(readMeshObstacle(v->element(i), name, vertices_used));
  }
  return scene;
}

Scene loadScene(const std::filesystem::path& file) {
  const std::string name = file.string();
  try {
    const MemoryStage stage("reading the scene " + name);
    return parseScene(readInputFile(file, kMaxSceneBytes, "a scene"), name);
  } catch (const InputError& e) {
    throw SceneError(name + ": " + e.what());
  }
}

void applyLiveParams(Scene& scene, const ClothSpec& cloth, const SimParams& sim) {
  const ClothSpec kept = scene.cloth;
  scene.cloth = cloth;
  scene.cloth.width = kept.width;
  scene.cloth.height = kept.height;
  scene.cloth.num_width_points = kept.num_width_points;
  scene.cloth.num_height_points = kept.num_height_points;
  scene.cloth.orientation = kept.orientation;
  scene.cloth.pinned = kept.pinned;
  scene.cloth.mesh = kept.mesh;
  scene.cloth.mesh_file = kept.mesh_file;
  scene.cloth.pinned_vertices = kept.pinned_vertices;
  scene.cloth.has_pin_box = kept.has_pin_box;
  scene.cloth.pin_box_min = kept.pin_box_min;
  scene.cloth.pin_box_max = kept.pin_box_max;
  scene.sim = sim;
}

int ClothSpec::pointCount() const {
  return mesh ? int(mesh->positions.size()) : num_width_points * num_height_points;
}

}  // namespace drape
