// A static triangle-mesh obstacle (scene key "meshes") and the signed distance field both solvers collide
// with: baked once on the CPU when the scene loads, exact point-triangle distances in a band around the
// surface and a closest-point transform beyond it, the sign by winding number, stored as floats that the CPU reference
// and the GPU interpolate with the same float operations (src/cpu/mesh_physics.hpp, glsl/sim/phases/mesh_collide.glsl).
// Why a field and not a triangle BVH: docs/design.md section 6.
#pragma once

#include "core/obj_reader.hpp"

#include <glm/glm.hpp>

#include <cstdint>
#include <optional>
#include <vector>

namespace drape {

struct DistanceField {
  glm::dvec3 origin{0.0};  // m, sample (0, 0, 0)
  double cell = 0.0;       // m between samples
  glm::ivec3 dims{0};      // samples per axis
  // The float constants the solvers use: both read these, never the doubles above.
  glm::vec3 origin_f{0.0f};
  float inv_cell_f = 0.0f;     // 1 / cell rounded once here (a GLSL division may differ from C++'s)
  std::vector<float> samples;  // m, signed (negative inside); x fastest, then y, then z
  double band = 0.0;           // m: samples within this of the surface hold exact distances (beyond: see below)

  std::size_t index(int x, int y, int z) const {
    return (std::size_t(z) * std::size_t(dims.y) + std::size_t(y)) * std::size_t(dims.x) + std::size_t(x);
  }
};

struct MeshObstacle {
  std::vector<glm::dvec3> positions;     // m, offset and scaled as the scene places it
  std::vector<std::uint32_t> triangles;  // 3 per triangle, as wound in the file
  DistanceField field;
};

// Samples per axis across the mesh's largest extent: 1.25 cm on a 1.6 m table, whose rounded edges
// (2 cm) the trilinear field then follows within about a millimetre.
inline constexpr int kFieldResolution = 128;
// The band of exact distances, in cells: every triangle is measured from every sample this close to its
// bounding box. Beyond it each sample holds its distance to the nearest surface point its neighbours hold (a
// closest-point transform), never less than the exact distance and at most 0.17 cells more on the
// bundled obstacles (docs/design.md, section 2). The 8 samples around a point within a cell of the surface
// are within 1 + sqrt(3) cells of it, inside the band, so where the cloth touches the field is exact at its
// samples; deeper, it still has the true sign and a gradient towards the nearest surface.
inline constexpr int kFieldBandCells = 3;
// The lattice reaches this many cells beyond the mesh's bounding box on every side.
inline constexpr int kFieldPadCells = 6;
// Cloth points are kept this far outside the field's zero level: its trilinear surface may cut a convex
// edge by about this much.
inline constexpr double kMeshSurfaceOffset = 2e-3;

// Checks that the mesh is closed and consistently wound (every edge once each way: inside must mean
// something; closed parts may overlap, the inside is their union, by winding number) and has no zero-area
// triangle, places it (x * scale + offset), winds it outward, and bakes the field. Throws MeshError.
MeshObstacle buildMeshObstacle(const PolygonMesh& mesh, glm::dvec3 offset, double scale);

// The field's value at p: trilinear between the eight samples around it, as the solvers interpolate it
// (in double here). nullopt outside the sampled box, and for a non-finite p.
std::optional<double> fieldDistance(const DistanceField& field, glm::dvec3 p);

// Distance from p to triangle t (the t-th three entries of `triangles`).
double triangleDistance(const MeshObstacle& mesh, std::size_t t, glm::dvec3 p);

// Exact queries against the triangles, for tests and reports (slow: every triangle).
double unsignedDistance(const MeshObstacle& mesh, glm::dvec3 p);
bool insideMesh(const MeshObstacle& mesh, glm::dvec3 p);
inline double signedDistance(const MeshObstacle& mesh, glm::dvec3 p) {
  const double d = unsignedDistance(mesh, p);
  return insideMesh(mesh, p) ? -d : d;
}

}  // namespace drape
