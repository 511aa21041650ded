// Exact queries against a mesh obstacle's triangles, fast enough to measure a whole cloth against a large
// obstacle every frame (drape penetration, tests): the triangles bucketed by the cells of a grid, so that a
// query visits the triangles near the point rather than all of them. The answers are those of
// signedDistance and insideMesh (core/mesh_obstacle.hpp), which loop over every triangle.
#pragma once

#include "core/mesh_obstacle.hpp"

#include <cstdint>
#include <vector>

namespace drape {

class MeshQuery {
 public:
  explicit MeshQuery(const MeshObstacle& mesh);

  // Whether p is inside (winding number > 0), as insideMesh.
  bool inside(glm::dvec3 p) const;
  // Distance to the nearest triangle, as unsignedDistance.
  double distance(glm::dvec3 p) const;
  double signedDistance(glm::dvec3 p) const { return inside(p) ? -distance(p) : distance(p); }

 private:
  const MeshObstacle* mesh_;
  glm::dvec3 origin_{0.0};
  double cell_ = 0.0;
  glm::ivec3 dims_{0};
  std::vector<std::uint32_t> cell_start_, cell_triangles_;      // CSR: the triangles whose box meets each cell
  std::vector<std::uint32_t> column_start_, column_triangles_;  // the same per (x, z) column, for the parity
  double nearestIn(glm::dvec3 p, const std::uint32_t* first, const std::uint32_t* last, double best) const;
};

// The field's trilinear value at p in double (the solvers interpolate in float), or +infinity outside its
// lattice: an estimate within 2 cells of the exact signed distance, to tell quickly what is far from the mesh.
double fieldDistance(const DistanceField& field, glm::dvec3 p);

}  // namespace drape
