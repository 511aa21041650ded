#include "app/export.hpp"

#include "app/command_error.hpp"
#include "core/atomic_file.hpp"

#include <fmt/format.h>

#include <fcntl.h>
#include <unistd.h>

#include <bit>
#include <cerrno>
#include <cstring>
#include <optional>

namespace drape {

namespace {

constexpr ExportFormat kFormats[] = {ExportFormat::Obj, ExportFormat::Ply, ExportFormat::Usda};

std::string nameOf(ExportFormat format) {
  return format == ExportFormat::Obj ? "obj" : format == ExportFormat::Ply ? "ply" : "usda";
}

std::optional<ExportFormat> formatNamed(const std::string& name) {
  for (ExportFormat f : kFormats)
    if (name == nameOf(f)) return f;
  return std::nullopt;
}

}  // namespace

std::filesystem::path ExportTarget::file(int frame) const {
  std::filesystem::path path = stem;
  if (format == ExportFormat::Usda) return path += ".usda";
  return path.replace_filename(fmt::format("{}_{:04d}.{}", stem.filename().string(), frame, nameOf(format)));
}

ExportTarget resolveExport(const std::string& path, const std::string& format) {
  if (path.empty()) throw CommandError(kExitBadInput, "--export: an empty path");
  std::optional<ExportFormat> asked;
  if (!format.empty()) {
    asked = formatNamed(format);
    if (!asked)
      throw CommandError(kExitBadInput, fmt::format("--format: unknown format '{}' (obj, ply or usda)", format));
  }
  std::error_code error;
  if (path.back() == '/' || std::filesystem::is_directory(path, error))
    return {std::filesystem::path(path) / "cloth", asked.value_or(ExportFormat::Obj)};
  const std::filesystem::path given(path);
  std::string extension = given.extension().string();
  const std::optional<ExportFormat> named = extension.empty() ? std::nullopt : formatNamed(extension.substr(1));
  if (!asked && !named)
    throw CommandError(kExitBadInput, fmt::format("--export: {}: cannot tell the format from the extension; "
                                                  "add --format obj, ply or usda",
                                                  path));
  if (asked && named && *asked != *named)
    throw CommandError(kExitBadInput, fmt::format("--export: {} is {}, but --format says {}", path, extension.substr(1),
                                                  nameOf(*asked)));
  std::filesystem::path stem = given;
  if (named) stem.replace_extension();
  return {stem, asked.value_or(named.value_or(ExportFormat::Obj))};
}

std::vector<glm::dvec3> vertexNormals(const Topology& topology, const Positions& x) {
  std::vector<glm::dvec3> n(x.size(), glm::dvec3(0.0));
  const auto add = [&](const glm::dvec3& face, std::initializer_list<std::uint32_t> corners) {
    for (std::uint32_t c : corners)
      n[c] += face;
  };
  // |cross| is twice the area: summing it weights every face by its size.
  for (const auto& f : topology.faces)
    if (f[3] == kNoCorner)
      add(glm::cross(x[f[1]] - x[f[0]], x[f[2]] - x[f[0]]), {f[0], f[1], f[2]});
    else
      add(glm::cross(x[f[2]] - x[f[0]], x[f[3]] - x[f[1]]), {f[0], f[1], f[2], f[3]});
  if (topology.faces.empty())
    for (std::size_t t = 0; t + 2 < topology.triangles.size(); t += 3) {
      const std::uint32_t a = topology.triangles[t], b = topology.triangles[t + 1], c = topology.triangles[t + 2];
      add(glm::cross(x[b] - x[a], x[c] - x[a]), {a, b, c});
    }
  for (glm::dvec3& v : n) {
    const double len = glm::length(v);
    v = len > 0.0 ? v / len : glm::dvec3(0, 1, 0);
  }
  return n;
}

std::string objText(const Topology& topology, const Positions& x, int frame) {
  const std::vector<glm::dvec3> normals = vertexNormals(topology, x);
  std::string s =
      fmt::format("# drape cloth, frame {}: {} points, {} triangles\n", frame, x.size(), topology.triangles.size() / 3);
  s.reserve(x.size() * 96 + topology.triangles.size() * 12);
  // The points as --out writes them (9 significant digits: every float exactly).
  for (const glm::dvec3& p : x)
    fmt::format_to(std::back_inserter(s), "v {:.9g} {:.9g} {:.9g}\n", p.x, p.y, p.z);
  for (const glm::vec2& uv : topology.uvs)
    fmt::format_to(std::back_inserter(s), "vt {:.9g} {:.9g}\n", uv.x, uv.y);
  for (const glm::dvec3& n : normals)
    fmt::format_to(std::back_inserter(s), "vn {:.6f} {:.6f} {:.6f}\n", n.x, n.y, n.z);
  for (std::size_t t = 0; t + 2 < topology.triangles.size(); t += 3) {
    const std::uint32_t a = topology.triangles[t] + 1, b = topology.triangles[t + 1] + 1,
                        c = topology.triangles[t + 2] + 1;
    fmt::format_to(std::back_inserter(s), "f {0}/{0}/{0} {1}/{1}/{1} {2}/{2}/{2}\n", a, b, c);
  }
  return s;
}

namespace {

void putLittleEndian(std::string& s, std::uint32_t v) {
  for (int k = 0; k < 4; ++k)
    s.push_back(char((v >> (8 * k)) & 0xffu));
}

void putFloat(std::string& s, double v) {
  putLittleEndian(s, std::bit_cast<std::uint32_t>(float(v)));
}

}  // namespace

std::string plyBytes(const Topology& topology, const Positions& x) {
  const std::vector<glm::dvec3> normals = vertexNormals(topology, x);
  const std::size_t triangles = topology.triangles.size() / 3;
  std::string s = fmt::format(
      "ply\nformat binary_little_endian 1.0\ncomment drape cloth\nelement vertex {}\n"
      "property float x\nproperty float y\nproperty float z\n"
      "property float nx\nproperty float ny\nproperty float nz\n"
      "property float s\nproperty float t\n"
      "element face {}\nproperty list uchar int vertex_indices\nend_header\n",
      x.size(), triangles);
  s.reserve(s.size() + x.size() * 32 + triangles * 13);
  for (std::size_t i = 0; i < x.size(); ++i) {
    for (int k = 0; k < 3; ++k)
      putFloat(s, x[i][k]);
    for (int k = 0; k < 3; ++k)
      putFloat(s, normals[i][k]);
    putFloat(s, topology.uvs[i].x);
    putFloat(s, topology.uvs[i].y);
  }
  for (std::size_t t = 0; t < triangles; ++t) {
    s.push_back(char(3));
    for (int k = 0; k < 3; ++k)
      putLittleEndian(s, topology.triangles[3 * t + std::size_t(k)]);
  }
  return s;
}

namespace {

// A nameless file beside the export (removed from its folder as soon as it is made, so nothing is left
// however the run ends), written once and read back once: the USD file's normals wait here while its points
// are written, since each attribute's samples must stay together.
class ScratchFile {
 public:
  explicit ScratchFile(const std::filesystem::path& beside) : target_(beside) {
    std::string name = ((beside.has_parent_path() ? beside.parent_path() : ".") / ".drape-XXXXXX").string();
    fd_ = ::mkostemp(name.data(), O_CLOEXEC);
    if (fd_ < 0) fail("cannot create a file in its directory");
    ::unlink(name.c_str());
  }
  ~ScratchFile() { ::close(fd_); }
  ScratchFile(const ScratchFile&) = delete;
  ScratchFile& operator=(const ScratchFile&) = delete;

  void append(std::string_view text) {
    if (!writeAll(fd_, text)) fail("write failed");
  }
  void copyInto(StreamedFile& out) {
    if (::lseek(fd_, 0, SEEK_SET) != 0) fail("read back failed");
    std::string chunk(std::size_t(1) << 20, '\0');
    for (;;) {
      const ssize_t n = ::read(fd_, chunk.data(), chunk.size());
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) fail("read back failed");
      if (n == 0) return;
      out.append(std::string_view(chunk.data(), std::size_t(n)));
    }
  }

 private:
  [[noreturn]] void fail(const char* what) const {
    throw OutputError(false, target_.string() + ": " + what + ": " + std::strerror(errno));
  }
  std::filesystem::path target_;
  int fd_ = -1;
};

// Frame numbers in the header are written this wide, so that the end can be rewritten in place.
constexpr int kTimeCodeWidth = 12;

template <class Vec, class Each>
void appendList(std::string& s, const std::vector<Vec>& values, Each each) {
  s += '[';
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (i) s += ", ";
    each(s, values[i]);
  }
  s += ']';
}

}  // namespace

// The USD file, streamed: the header and the mesh's topology and UVs first, then each frame's points as it
// comes; its normals wait in a scratch file and its extent (two corners a frame) in memory until finish().
class UsdaStream {
 public:
  UsdaStream(const std::filesystem::path& path, const Scene& scene, const Topology& topology, int last_frame)
      : file_(path), normals_(path), scene_(&scene), topology_(&topology), planned_last_(last_frame) {}

  void add(int frame, const Positions& x) {
    if (first_ < 0) begin(frame);
    last_ = frame;
    std::string s = fmt::format("        {}: ", frame);
    appendList(s, x, [](std::string& out, const glm::dvec3& p) {
      fmt::format_to(std::back_inserter(out), "({:.9g}, {:.9g}, {:.9g})", p.x, p.y, p.z);
    });
    file_.append(s += ",\n");
    s = fmt::format("        {}: ", frame);
    appendList(s, vertexNormals(*topology_, x), [](std::string& out, const glm::dvec3& n) {
      fmt::format_to(std::back_inserter(out), "({:.6g}, {:.6g}, {:.6g})", n.x, n.y, n.z);
    });
    normals_.append(s += ",\n");
    glm::dvec3 lo = x.front(), hi = x.front();
    for (const glm::dvec3& p : x) {
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
    fmt::format_to(std::back_inserter(extent_), "        {}: [({:.9g}, {:.9g}, {:.9g}), ({:.9g}, {:.9g}, {:.9g})],\n",
                   frame, lo.x, lo.y, lo.z, hi.x, hi.y, hi.z);
  }

  // False when no frame was added: then there is no file.
  bool finish() {
    if (first_ < 0) return false;
    file_.append(
        "    }\n    normal3f[] normals (\n        interpolation = \"vertex\"\n    )\n"
        "    normal3f[] normals.timeSamples = {\n");
    normals_.copyInto(file_);
    file_.append("    }\n    float3[] extent.timeSamples = {\n" + extent_ + "    }\n}\n");
    if (last_ != planned_last_) file_.overwrite(end_offset_, fmt::format("{:<{}}", last_, kTimeCodeWidth));
    file_.commit();
    return true;
  }

 private:
  void begin(int first) {
    first_ = first;
    const Topology& topo = *topology_;
    const double fps = scene_->sim.frames_per_sec;
    std::string s =
        fmt::format("#usda 1.0\n(\n    defaultPrim = \"Cloth\"\n    startTimeCode = {}\n    endTimeCode = ", first);
    end_offset_ = s.size();
    fmt::format_to(std::back_inserter(s),
                   "{:<{}}\n    timeCodesPerSecond = {:.9g}\n    framesPerSecond = {:.9g}\n    metersPerUnit = 1\n"
                   "    upAxis = \"Y\"\n)\n\ndef Mesh \"Cloth\"\n{{\n    int[] faceVertexCounts = [",
                   std::max(planned_last_, first), kTimeCodeWidth, fps, fps);
    planned_last_ = std::max(planned_last_, first);
    for (std::size_t t = 0; t < topo.triangles.size() / 3; ++t)
      s += t ? ", 3" : "3";
    s += "]\n    int[] faceVertexIndices = ";
    appendList(s, topo.triangles,
               [](std::string& out, std::uint32_t i) { fmt::format_to(std::back_inserter(out), "{}", i); });
    s += "\n    uniform token orientation = \"rightHanded\"\n    uniform token subdivisionScheme = \"none\"\n";
    s += "    texCoord2f[] primvars:st = ";
    appendList(s, topo.uvs, [](std::string& out, const glm::vec2& uv) {
      fmt::format_to(std::back_inserter(out), "({:.9g}, {:.9g})", uv.x, uv.y);
    });
    s += " (\n        interpolation = \"vertex\"\n    )\n    point3f[] points.timeSamples = {\n";
    file_.append(s);
  }

  StreamedFile file_;
  ScratchFile normals_;
  const Scene* scene_;
  const Topology* topology_;
  std::string extent_;
  int planned_last_;
  int first_ = -1, last_ = -1;
  std::size_t end_offset_ = 0;  // of endTimeCode's value in the file
};

ClothExport::ClothExport(const ExportTarget& target, const Scene& scene, const Topology& topology, int last_frame)
    : target_(target), topology_(&topology) {
  const std::filesystem::path first = target_.file(0);
  if (first.has_parent_path()) {
    std::error_code error;
    std::filesystem::create_directories(first.parent_path(), error);
    if (error)
      throw CommandError(kExitBadInput, fmt::format("--export: cannot create the folder {}: {}",
                                                    first.parent_path().string(), error.message()));
  }
  try {
    checkOutputFile(first);
    if (target_.format == ExportFormat::Usda) usda_ = std::make_unique<UsdaStream>(first, scene, topology, last_frame);
  } catch (const OutputError& e) {
    throw CommandError(e.badTarget() ? kExitBadInput : kExitFailure, fmt::format("--export: {}", e.what()));
  }
}

ClothExport::~ClothExport() = default;

void ClothExport::add(int frame, const Positions& x) {
  last_ = frame;
  if (usda_) {
    usda_->add(frame, x);
    return;
  }
  const std::filesystem::path file = target_.file(frame);
  writeFileAtomically(file,
                      target_.format == ExportFormat::Obj ? objText(*topology_, x, frame) : plyBytes(*topology_, x));
  ++written_;
}

std::string keepExport(ClothExport& exporter) {
  exporter.finish();
  if (exporter.lastFrame() < 0) return "; --export wrote nothing";
  return fmt::format("; --export keeps frames 0 to {}", exporter.lastFrame());
}

void ClothExport::finish() {
  if (usda_ && usda_->finish()) ++written_;
  usda_.reset();
}

}  // namespace drape
