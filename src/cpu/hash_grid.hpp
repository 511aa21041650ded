// Uniform spatial hash for self-collision: cells of size >= 2*thickness, points counting-sorted by
// bucket (stable, so each bucket lists its points in ascending index), and a query that visits all 27
// neighbouring cells. A bucket can hold points of several cells (hash collisions); queries keep only
// points whose cell is the visited one, so no pair is seen twice. CS184 searched only a point's own
// cell and missed pairs across cell borders.
#pragma once

#include "cpu/physics.hpp"

#include <cstdint>
#include <vector>

namespace drape {

template <class T>
class HashGrid {
 public:
  using vec3 = glm::vec<3, T>;

  void build(const std::vector<vec3>& points, T cell_size);

  // Calls f(j) for every point j != i whose cell is within one cell of point i's cell, in a fixed
  // order (27 cells in z, y, x order; ascending index within a cell).
  template <class F>
  void forEachCandidate(std::size_t i, F&& f) const {
    glm::ivec3 c = cells_[i];
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          glm::ivec3 n = c + glm::ivec3(dx, dy, dz);
          std::uint32_t b = physics::hashCell(n) & mask_;
          for (std::uint32_t s = start_[b]; s < start_[b + 1]; ++s) {
            std::uint32_t j = sorted_[s];
            if (j != i && cells_[j] == n) f(j);
          }
        }
  }

  // A point's cell, from the reciprocal of the cell edge rounded once on the host. A product is
  // correctly rounded on every GPU while GLSL lets a division be off by 2.5 ulp (NVIDIA's is), so
  // multiplying is what keeps CPU and GPU cells identical at cell borders.
  static glm::ivec3 cellOf(vec3 p, T inv_cell_size) { return glm::ivec3(glm::floor(p * inv_cell_size)); }
  std::size_t bucketCount() const { return start_.empty() ? 0 : start_.size() - 1; }

 private:
  std::vector<glm::ivec3> cells_;
  std::vector<std::uint32_t> start_;   // bucketCount + 1 prefix sums
  std::vector<std::uint32_t> sorted_;  // point indices grouped by bucket
  std::uint32_t mask_ = 0;
};

}  // namespace drape
