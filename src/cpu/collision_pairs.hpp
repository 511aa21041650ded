// Self-collision candidates kept across substeps: a neighbour list with a skin (Verlet 1967). Every
// pair closer than range + margin when the list is built is listed; the list stays valid while the
// points' displacements since the build all fit in a box whose diagonal is under the margin (stale()),
// because no pair then approaches by the margin and every pair within range is still listed. Points move
// ~1 mm a substep at CS184's speeds, mostly together, so a list of a few millimetres of skin serves
// several substeps instead of rebuilding the hash grid and reading 27 cells every substep.
//
// The sum of a point's corrections must not depend on when the list was rebuilt, or on the GPU on
// thread timing: orderedCandidates() yields the pairs in range in the order a 27-cell query of a grid
// of cell size `range` visits them (cells in z, y, x order around the point's cell, ascending index
// within a cell), so the result is the same whatever list it comes from.
#pragma once

#include "cpu/hash_grid.hpp"

#include <bit>
#include <cstdint>
#include <vector>

namespace drape {

template <class T>
class CollisionPairs {
 public:
  using vec3 = glm::vec<3, T>;

  // range = 2 * thickness; margin >= 0 (0 rebuilds every substep).
  void configure(T range, T margin);
  // The cloth's rest positions: a pair closer than `range` there is held by the springs
  // (physics::heldAtRest) and never listed. Empty (the default): every pair is a candidate.
  void setRest(std::vector<vec3> rest);
  void invalidate() { built_ = false; }

  // Makes the list valid for positions x (rebuilding if any point moved too far); returns whether it
  // rebuilt. threads: OpenMP threads for the per-point loops.
  bool update(const std::vector<vec3>& x, int threads);

  // Candidates of point i, ascending: every j with |x_i - x_j| < range + margin at the last build.
  const std::uint32_t* begin(std::size_t i) const { return list_.data() + start_[i]; }
  const std::uint32_t* end(std::size_t i) const { return list_.data() + start_[i + 1]; }
  std::size_t pairCount() const { return list_.size(); }  // each pair counted from both ends
  long long rebuilds() const { return rebuilds_; }
  T range() const { return range_; }
  T margin() const { return margin_; }

  // Largest distance any point may move from its build position before the list is rebuilt: half the
  // margin, less a few ulps of the largest coordinate so that round-off in the distances cannot
  // break the triangle inequality the proof uses.
  static T safeTravel(T margin, T extent);

 private:
  bool stale(const std::vector<vec3>& x) const;
  void build(const std::vector<vec3>& x, int threads);

  struct Pair {
    std::uint32_t i, j;
  };
  HashGrid<T> grid_;
  std::vector<std::vector<Pair>> found_;  // per thread, kept to spare the allocations
  std::vector<std::uint32_t> start_, list_, fill_;
  std::vector<vec3> anchor_;  // positions at the last build
  std::vector<vec3> rest_;
  T range_ = 0, margin_ = 0;
  T travel_ = 0;  // safeTravel at the last build
  bool built_ = false;
  long long rebuilds_ = 0;
};

// Where j lies around i in the 27-cell query of a grid of cell size `range` (0..26, z then y then x),
// or -1 if the 27 cells do not hold it. The order in which the self-collision sum visits its terms.
inline int cellOrder(glm::ivec3 cell_i, glm::ivec3 cell_j) {
  const glm::ivec3 d = cell_j - cell_i;
  if (d.x < -1 || d.x > 1 || d.y < -1 || d.y > 1 || d.z < -1 || d.z > 1) return -1;
  return (d.z + 1) * 9 + (d.y + 1) * 3 + (d.x + 1);
}

// Calls f(c) with the correction of every pair {i, j} in range, in cellOrder and then ascending j: the
// order of a 27-cell query of a grid of cell size 2*thickness, as the sum had before the lists. One sweep
// over the short candidate list computes each term once and inserts it by its cell order (stably, so one
// order's terms stay in list order, ascending j); cells are computed only for pairs in range, which most
// points have none of. A point with more terms than are held (a deep fold) sweeps once per order present.
template <class T, class F>
void forEachOrderedPair(const CollisionPairs<T>& pairs, std::size_t i, const std::vector<glm::vec<3, T>>& x,
                        T thickness, T inv_range, F&& f) {
  using vec3 = glm::vec<3, T>;
  constexpr int kHeld = 24;  // the folded selfCollision scene has at most 5 terms a point
  struct Term {
    int order;
    vec3 c;
  };
  Term held[kHeld];
  int count = 0;
  std::uint32_t present = 0;
  glm::ivec3 cell_i{};
  for (const std::uint32_t* j = pairs.begin(i); j != pairs.end(i); ++j) {
    const vec3 c = physics::selfCollisionCorrection(x[i], x[*j], thickness);
    if (c == vec3(0)) continue;
    if (present == 0) cell_i = HashGrid<T>::cellOf(x[i], inv_range);
    const int order = cellOrder(cell_i, HashGrid<T>::cellOf(x[*j], inv_range));
    if (order < 0) continue;
    present |= 1u << order;
    if (count < kHeld) {
      int k = count;
      for (; k > 0 && held[k - 1].order > order; --k)
        held[k] = held[k - 1];
      held[k] = {order, c};
    }
    ++count;
  }
  if (count <= kHeld) {
    for (int k = 0; k < count; ++k)
      f(held[k].c);
    return;
  }
  while (present != 0) {
    const int order = std::countr_zero(present);
    present &= present - 1;
    for (const std::uint32_t* j = pairs.begin(i); j != pairs.end(i); ++j) {
      const vec3 c = physics::selfCollisionCorrection(x[i], x[*j], thickness);
      if (c != vec3(0) && cellOrder(cell_i, HashGrid<T>::cellOf(x[*j], inv_range)) == order) f(c);
    }
  }
}

// Pairs of points closer than `range` in the rest shape `rest`: the pairs self-collision skips
// (heldAtRest). count: each pair once; closest: the smallest such distance (0 if none).
struct HeldPairs {
  std::size_t count = 0;
  double closest = 0;
};
HeldPairs heldPairsAtRest(const std::vector<glm::dvec3>& rest, double range);

}  // namespace drape
