// libFuzzer target (clang only; `tools/test --fuzz obj` builds and runs it): arbitrary bytes through the OBJ
// reader, then whatever it accepts through both of its users, the cloth mesh and the obstacle (its field
// baked), and the obstacle's distance queries. Built with ASan and UBSan (no recovery), so a memory error,
// UB, an exception other than MeshError, a hang, or a broken promise (checked below) is a crash that
// libFuzzer reports with the input that caused it.
#include "core/cloth_mesh.hpp"
#include "core/mesh_distance.hpp"
#include "core/mesh_obstacle.hpp"
#include "core/obj_reader.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string_view>
#include <vector>

namespace {

// Small enough that an input runs in milliseconds: the limits are the reader's own mechanism at a smaller
// count; an obstacle's bake is the costly part, so only small ones are baked.
const drape::ObjLimits kLimits{2000, " (the fuzzer's limit)"};
constexpr std::size_t kMaxBakedTriangles = 64;

void check(bool ok, const char* what) {
  if (ok) return;
  std::fprintf(stderr, "obj_fuzzer: a broken promise: %s\n", what);
  std::abort();
}

// What readObj promises about every mesh it returns (core/obj_reader.hpp).
void checkContract(const drape::PolygonMesh& m) {
  check(!m.faces.empty(), "at least one face");
  check((long long)m.positions.size() <= kLimits.vertices, "the vertex limit");
  check((long long)m.faces.size() <= kLimits.faces(), "the face limit");
  for (const glm::dvec3& p : m.positions)
    check(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z), "finite coordinates");
  for (const auto& face : m.faces) {
    check(!face.empty(), "a face has corners");
    for (std::uint32_t v : face)
      check(v < m.positions.size(), "every corner names a vertex");
  }
  check(m.uvs.empty() || m.uvs.size() == m.positions.size(), "one uv per vertex, or none");
}

void probeObstacle(const drape::MeshObstacle& mesh) {
  const std::vector<glm::dvec3> points = {{0, 0, 0}, {0.5, 2, -0.25}, {1e3, -1e3, 7}};
  for (const glm::dvec3& p : points) {
    double every = INFINITY;
    for (std::size_t t = 0; t < mesh.triangles.size() / 3; ++t)
      every = std::min(every, drape::triangleDistance(mesh, t, p));
    check(drape::closestTriangleDistance(mesh, {p}) == every, "the bucket search equals every triangle");
  }
  const double d = drape::closestSignedDistance(mesh, points);
  check(!std::isnan(d), "a distance, not NaN");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  drape::PolygonMesh mesh;
  try {
    mesh = drape::parseObj(text, kLimits);
  } catch (const drape::MeshError&) {
    return 0;  // refused with its one-line message: what most inputs get
  }
  checkContract(mesh);
  try {
    (void)drape::buildClothMesh(mesh);
  } catch (const drape::MeshError&) {
  }
  std::size_t triangles = 0;
  for (const auto& face : mesh.faces)
    triangles += face.size() >= 3 ? face.size() - 2 : 0;
  if (triangles > kMaxBakedTriangles) return 0;
  try {
    probeObstacle(drape::buildMeshObstacle(mesh, {0.1, -0.2, 0.3}, 1.5));
  } catch (const drape::MeshError&) {
  }
  return 0;
}
