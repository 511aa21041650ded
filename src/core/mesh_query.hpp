// Exact queries against a mesh obstacle's triangles, fast enough to measure a whole cloth against a large
// obstacle every frame (drape penetration, simulate's summary, tests): the triangles sorted into a grid of
// buckets over the mesh's bounding box, each in every bucket its bounding box meets, so that a query visits
// the triangles near the point rather than all of them. The answers are those of unsignedDistance and
// insideMesh (core/mesh_obstacle.hpp), which loop over every triangle.
#pragma once

#include "core/mesh_obstacle.hpp"

#include <cstdint>
#include <limits>
#include <vector>

namespace drape {

class MeshQuery {
 public:
  explicit MeshQuery(const MeshObstacle& mesh);

  // Whether p is inside (winding number > 0), as insideMesh: the same shifted vertical line, so the same
  // crossings, tried against the triangles of its column of buckets only.
  bool inside(glm::dvec3 p) const;
  // min(best, the distance to the nearest triangle), as unsignedDistance: searched outward from p's bucket
  // in rings, a ring visited only while the part of the grid beyond the rings seen may hold something nearer
  // than the best so far (a `best` from an earlier point prunes the whole search).
  double distance(glm::dvec3 p, double best = std::numeric_limits<double>::infinity()) const;
  double signedDistance(glm::dvec3 p) const { return inside(p) ? -distance(p) : distance(p); }
  // No triangle is nearer p than this: the distance to the mesh's bounding box.
  double lowerBound(glm::dvec3 p) const;

 private:
  const MeshObstacle* mesh_;
  glm::dvec3 lo_{0.0}, hi_{0.0}, cell_{1.0};
  glm::ivec3 dims_{1};
  std::vector<std::uint32_t> start_, triangles_;                // CSR: the triangles whose box meets each bucket
  std::vector<std::uint32_t> column_start_, column_triangles_;  // the same per (x, z) column, for the winding

  bool fill(glm::ivec3 dims, std::size_t most);
  template <class F>
  void forEachBucketOfEachTriangle(F&& f) const;
  glm::ivec3 bucketOf(glm::dvec3 p) const;
  std::size_t index(int i, int j, int k) const;
  double searchRing(glm::dvec3 p, glm::ivec3 c, int r, double best) const;
  double outsideDistance(glm::dvec3 p, glm::ivec3 from, glm::ivec3 to) const;
};

}  // namespace drape
