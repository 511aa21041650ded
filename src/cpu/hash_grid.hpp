// Uniform spatial hash for self-collision: cells of size >= 2*thickness, points counting-sorted by
// bucket (stable, so each bucket lists its points in ascending index), and a query that visits all 27
// neighbouring cells. A bucket can hold points of several cells (hash collisions); queries keep only
// points whose cell is the visited one, so no pair is seen twice. CS184 searched only a point's own
// cell and missed pairs across cell borders.
//
// Where the points' box of cells is small (at most kDenseCells per point), the buckets are the box's cells
// themselves, in z, y, x order: no hashing (three hashU32 a cell, 14 cells a point, were most of a list
// build) and no collisions. Which is used changes nothing that is found, only how fast.
#pragma once

#include "cpu/physics.hpp"

#include <algorithm>
#include <cstdint>
#include <exception>
#include <vector>

namespace drape {

struct GridKernels;

template <class T>
class HashGrid {
 public:
  using vec3 = glm::vec<3, T>;

  // Outside a team, by the calling thread (it throws what fails). In a team every thread calls it and each
  // takes a share of the points; an allocation that fails is kept in `failure` (shared by the team), which every
  // thread reads after the build, and the grid is then unusable until the next build.
  void build(const std::vector<vec3>& points, T cell_size);
  void build(const std::vector<vec3>& points, T cell_size, std::exception_ptr& failure);
  // Float: the instruction set's cellsOf for the points' cells (default: one point at a time). The same cells.
  void setKernels(const GridKernels* kernels) { kernels_ = kernels; }

  // Calls f(j) for every point j != i whose cell is within one cell of point i's cell, in a fixed
  // order (27 cells in z, y, x order; ascending index within a cell).
  template <class F>
  void forEachCandidate(std::size_t i, F&& f) const {
    glm::ivec3 c = cells_[i];
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          glm::ivec3 n = c + glm::ivec3(dx, dy, dz);
          std::uint32_t b;
          if (!bucketOf(n, b)) continue;
          for (std::uint32_t s = start_[b]; s < start_[b + 1]; ++s) {
            std::uint32_t j = sorted_[s];
            if (j != i && cells_[j] == n) f(j);
          }
        }
  }

  // Calls f(j) once for every pair {i, j} whose cells are within one cell of each other, over all i:
  // j > i in i's own cell, and every point of the 13 cells that come after i's cell in (z, y, x)
  // order. Half the lookups of forEachCandidate, for callers that record both ends of a pair.
  template <class F>
  void forEachForwardCandidate(std::size_t i, F&& f) const {
    const glm::ivec3 c = cells_[i];
    for (int k = 13; k < 27; ++k) {
      const glm::ivec3 n = c + glm::ivec3(k % 3 - 1, k / 3 % 3 - 1, k / 9 - 1);
      std::uint32_t b;
      if (!bucketOf(n, b)) continue;
      for (std::uint32_t s = start_[b]; s < start_[b + 1]; ++s) {
        const std::uint32_t j = sorted_[s];
        if (cells_[j] == n && (k > 13 || j > i)) f(j);
      }
    }
  }

  // forEachForwardCandidate a range of slots at a time: f(first, last, n) with [first, last) slots of sorted()
  // that may hold the points of the forward cells (i's own cell from the point after i). Dense buckets are the
  // box's cells in x-fastest order, so a row of three cells is one range (n is then its middle cell, and every
  // slot is a candidate); a hashed bucket is one cell's range and may hold other cells' points too: the caller
  // keeps the slots s whose point j = sorted()[s] is inCell(j, n), as forEachForwardCandidate does.
  template <class F>
  void forEachForwardBucket(std::size_t i, F&& f) const {
    const glm::ivec3 c = cells_[i];
    // A bucket lists its points in ascending index: those after i follow its slot (a binary search a point
    // was a third of the list builds' own time, in mispredicted branches)
    const std::uint32_t after_i = slot_[i] + 1;
    if (dense_) {
      forEachForwardRange(c, [&](std::uint32_t s, std::uint32_t e, bool own) {
        if (own) s = after_i;  // i's cell from the point after i, and the next
        if (s < e) f(s, e, c);
      });
      return;
    }
    for (int k = 13; k < 27; ++k) {
      const glm::ivec3 n = c + glm::ivec3(k % 3 - 1, k / 3 % 3 - 1, k / 9 - 1);
      std::uint32_t b;
      if (!bucketOf(n, b)) continue;
      std::uint32_t s = start_[b];
      const std::uint32_t e = start_[b + 1];
      if (k == 13) s = after_i;
      if (s < e) f(s, e, n);
    }
  }
  // Dense buckets only: f(first, last, own) for the ranges of slots of cell c's forward cells, each a row of up
  // to three cells; the first (own = true) is c's own row from c itself, the rest follow. Empty ranges too.
  template <class F>
  void forEachForwardRange(glm::ivec3 c, F&& f) const {
    const glm::ivec3 r = c - box_min_;
    const auto row = [&](int dy, int dz, int x0, int x1) {  // cells x0..x1 (inclusive) of row (dy, dz)
      const int y = r.y + dy, z = r.z + dz;
      if (y < 0 || z < 0 || y >= box_size_.y || z >= box_size_.z) return;
      const int lo = std::max(r.x + x0, 0), hi = std::min(r.x + x1, box_size_.x - 1);
      if (lo > hi) return;
      const std::uint32_t b = std::uint32_t((z * box_size_.y + y) * box_size_.x);
      f(start_[b + std::uint32_t(lo)], start_[b + std::uint32_t(hi) + 1], dy == 0 && dz == 0);
    };
    row(0, 0, 0, 1);
    row(1, 0, -1, 1);
    for (int dy = -1; dy <= 1; ++dy)
      row(dy, 1, -1, 1);
  }
  glm::ivec3 cellOfPoint(std::size_t i) const { return cells_[i]; }
  // The slot after the last of point i's bucket: on dense buckets, the end of its cell's points in sorted()
  std::uint32_t bucketEnd(std::size_t i) const { return start_[bucket_[i] + 1]; }
  bool inCell(std::uint32_t j, glm::ivec3 n) const { return dense_ || cells_[j] == n; }
  const std::vector<std::uint32_t>& sorted() const { return sorted_; }

  // A point's cell, from the reciprocal of the cell edge rounded once on the host. A product is
  // correctly rounded on every GPU while GLSL lets a division be off by 2.5 ulp (NVIDIA's is), so
  // multiplying is what keeps CPU and GPU cells identical at cell borders.
  // Coordinates are clamped to +-2^30 cells (a NaN goes to cell 0) before the conversion: converting
  // a non-finite or out-of-range float to int is undefined, and a blown-up cloth reaches this before
  // the frame's health check. Neighbouring cells (+-1) then still fit an int.
  static glm::ivec3 cellOf(vec3 p, T inv_cell_size) {
    const vec3 q = glm::floor(p * inv_cell_size);
    return {clampCell(q.x), clampCell(q.y), clampCell(q.z)};
  }
  static int clampCell(T q) {
    constexpr T kLimit = T(1 << 30);
    return q != q ? 0 : int(std::min(std::max(q, -kLimit), kLimit));
  }
  std::size_t bucketCount() const { return start_.empty() ? 0 : start_.size() - 1; }
  bool dense() const { return dense_; }

  // Most box cells per point for the dense buckets: a flat 50x50 cloth's box is about 35x1x35 cells of
  // its self-collision reach, a crumpled one's up to 35^3 (17 a point).
  static constexpr std::uint64_t kDenseCells = 24;

 private:
  // The bucket of cell n; false for a cell outside the dense box (which holds no point).
  bool bucketOf(glm::ivec3 n, std::uint32_t& b) const {
    if (!dense_) {
      b = physics::hashCell(n) & mask_;
      return true;
    }
    const glm::ivec3 r = n - box_min_;
    if (r.x < 0 || r.y < 0 || r.z < 0 || r.x >= box_size_.x || r.y >= box_size_.y || r.z >= box_size_.z) return false;
    b = std::uint32_t((r.z * box_size_.y + r.y) * box_size_.x + r.x);
    return true;
  }

  std::vector<glm::ivec3> cells_;
  std::vector<std::uint32_t> start_;           // bucketCount + 1 prefix sums
  std::vector<std::uint32_t> sorted_;          // point indices grouped by bucket
  std::vector<std::uint32_t> slot_;            // each point's slot in sorted_
  std::vector<std::uint32_t> bucket_;          // build's scratch, kept to spare the allocations
  std::vector<std::uint32_t> fill_;            // per thread of the build: its count, then its next slot, a bucket
  std::vector<glm::ivec3> part_lo_, part_hi_;  // per thread of the build: its points' box of cells
  std::vector<std::uint32_t> part_count_;      // per thread of the build: the points in its share of the buckets
  std::uint32_t mask_ = 0;
  const GridKernels* kernels_ = nullptr;
  bool dense_ = false;
  glm::ivec3 box_min_{}, box_size_{};
};

}  // namespace drape
