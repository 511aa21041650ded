#include "app/export.hpp"

#include "app/commands.hpp"
#include "core/atomic_file.hpp"

#include <fmt/format.h>

#include <bit>
#include <cstring>

namespace drape {

ExportFormat parseExportFormat(const std::string& format, const std::filesystem::path& path) {
  std::string name = format;
  if (name.empty()) {
    name = path.extension().string();
    if (!name.empty()) name.erase(0, 1);
    if (name != "obj" && name != "ply" && name != "usda")
      throw CommandError(kExitBadInput, fmt::format("--export: {}: cannot tell the format from the extension; "
                                                    "add --format obj, ply or usda",
                                                    path.string()));
  }
  if (name == "obj") return ExportFormat::Obj;
  if (name == "ply") return ExportFormat::Ply;
  if (name == "usda") return ExportFormat::Usda;
  throw CommandError(kExitBadInput, fmt::format("--format: unknown format '{}' (obj, ply or usda)", name));
}

std::filesystem::path sequenceFile(const std::filesystem::path& path, int frame) {
  std::filesystem::path file = path;
  file.replace_filename(fmt::format("{}_{:04d}{}", path.stem().string(), frame, path.extension().string()));
  return file;
}

std::vector<glm::dvec3> vertexNormals(const Topology& topology, const Positions& x) {
  std::vector<glm::dvec3> n(x.size(), glm::dvec3(0.0));
  for (std::size_t t = 0; t + 2 < topology.triangles.size(); t += 3) {
    const std::uint32_t a = topology.triangles[t], b = topology.triangles[t + 1], c = topology.triangles[t + 2];
    // |cross| is twice the area: summing it weights every face by its size.
    const glm::dvec3 face = glm::cross(x[b] - x[a], x[c] - x[a]);
    n[a] += face;
    n[b] += face;
    n[c] += face;
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

ClothExport::ClothExport(std::filesystem::path path, ExportFormat format, const Scene& scene, const Topology& topology)
    : path_(std::move(path)), format_(format), scene_(&scene), topology_(&topology) {
  try {
    checkOutputFile(format_ == ExportFormat::Usda ? path_ : sequenceFile(path_, 0));
  } catch (const OutputError& e) {
    throw CommandError(kExitBadInput, fmt::format("--export: {}", e.what()));
  }
}

void ClothExport::add(int frame, const Positions& x) {
  if (first_ < 0) first_ = frame;
  last_ = frame;
  if (format_ == ExportFormat::Usda) {
    fmt::format_to(std::back_inserter(samples_), "        {}: [", frame);
    for (std::size_t i = 0; i < x.size(); ++i)
      fmt::format_to(std::back_inserter(samples_), "{}({:.9g}, {:.9g}, {:.9g})", i ? ", " : "", x[i].x, x[i].y, x[i].z);
    samples_ += "],\n";
    return;
  }
  const std::filesystem::path file = sequenceFile(path_, frame);
  writeFileAtomically(file, format_ == ExportFormat::Obj ? objText(*topology_, x, frame) : plyBytes(*topology_, x));
  ++written_;
}

void ClothExport::finish() {
  if (format_ != ExportFormat::Usda || first_ < 0) return;
  const Topology& topo = *topology_;
  const double fps = scene_->sim.frames_per_sec;
  std::string s = "#usda 1.0\n(\n    defaultPrim = \"Cloth\"\n";
  fmt::format_to(std::back_inserter(s),
                 "    startTimeCode = {}\n    endTimeCode = {}\n    timeCodesPerSecond = {:.9g}\n"
                 "    framesPerSecond = {:.9g}\n    metersPerUnit = 1\n    upAxis = \"Y\"\n)\n\n",
                 first_, last_, fps, fps);
  s += "def Mesh \"Cloth\"\n{\n    int[] faceVertexCounts = [";
  for (std::size_t t = 0; t < topo.triangles.size() / 3; ++t)
    s += t ? ", 3" : "3";
  s += "]\n    int[] faceVertexIndices = [";
  for (std::size_t k = 0; k < topo.triangles.size(); ++k)
    fmt::format_to(std::back_inserter(s), "{}{}", k ? ", " : "", topo.triangles[k]);
  s += "]\n    uniform token orientation = \"rightHanded\"\n    uniform token subdivisionScheme = \"none\"\n";
  s += "    point3f[] points.timeSamples = {\n";
  s += samples_;
  s += "    }\n    texCoord2f[] primvars:st = [";
  for (std::size_t i = 0; i < topo.uvs.size(); ++i)
    fmt::format_to(std::back_inserter(s), "{}({:.9g}, {:.9g})", i ? ", " : "", topo.uvs[i].x, topo.uvs[i].y);
  s += "] (\n        interpolation = \"vertex\"\n    )\n}\n";
  writeFileAtomically(path_, s);
  ++written_;
}

}  // namespace drape
