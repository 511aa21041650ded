// CollisionPairs' stencil squares (stencilTiles): per square of a grid's tiles, the least distance of each stencil
// offset's pairs at the build, and which offsets the substeps after it may pass over. Kept apart from
// collision_pairs_check.cpp for its size.
#include "cpu/collision_pairs.hpp"
#include "cpu/parallel.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <type_traits>

namespace drape {

template <class T>
bool CollisionPairs<T>::stencilTiles(bool just_built, GridStencilTiles& out) {
  const std::size_t offsets = forwardOffsets();
  if (!std::is_same_v<T, float> || !squares_ || !kernels_ || edge_ <= 0 || offsets < kSquaresMinOffsets ||
      offsets > 64 || box_ < 0 || !built_)
    return false;
  const auto thread = std::size_t(teamThread());
  if (stencil_min2_.size() != tile_count_ * offsets || stencil_active_.size() < tile_count_ * (thread + 1) ||
      active_rows_.size() <= thread)
    return false;
  if (!just_built && (stencil_recorded_ != rebuilds_ || boxes_.size() != tile_count_)) return false;
  out.edge = edge_;
  out.across = tilesAcross();
  out.active = stencil_active_.data() + thread * tile_count_;
  out.min2 = stencil_min2_.data();
  out.record = just_built;
  out.shared_min2 = shared_min2_.data() + std::ptrdiff_t(thread) * recordRow();
  // No thread reads these before the next substep's call, several barriers on
  if (teamThread() == 0) squares_used_ = !just_built;
  if (just_built) {
    if (teamThread() == 0) stencil_recorded_ = rebuilds_;
    // Capturing `this` alone keeps the function in std::function's own storage: no allocation a build. A first row
    // of squares shared with the thread before is recorded into this thread's own copy (GridPath::stencilPairs).
    out.prepare = [this](long long y0, long long y1) {
      constexpr float kInf = std::numeric_limits<float>::infinity();
      const std::ptrdiff_t per_row = recordRow();
      const int shared = sharedRow(y0);
      long long first = y0 / edge_;
      if (shared >= 0) {
        float* const own = shared_min2_.data() + std::ptrdiff_t(teamThread()) * per_row;
        std::fill(own, own + per_row, kInf);
        ++first;
      }
      const long long last = (y1 + edge_ - 1) / edge_;
      if (first < last)
        std::fill(stencil_min2_.begin() + first * per_row, stencil_min2_.begin() + last * per_row, kInf);
      return shared;
    };
  } else {
    out.prepare = [this](long long y0, long long y1) {
      activeOffsets(y0 / edge_, (y1 + edge_ - 1) / edge_);
      return -1;
    };
  }
  return true;
}

// The least distances thread `from` recorded for the row of squares it shares with the thread before it, whose first
// row of points is y0, into the record; by the thread before, after the team's barrier.
template <class T>
void CollisionPairs<T>::mergeSharedRecord(int from, long long y0) {
  const int shared = sharedRow(y0);
  if (shared < 0) return;
  const std::ptrdiff_t per_row = recordRow();
  const float* own = shared_min2_.data() + std::ptrdiff_t(from) * per_row;
  float* row = stencil_min2_.data() + std::ptrdiff_t(shared) * per_row;
  for (std::ptrdiff_t k = 0; k < per_row; ++k)
    row[k] = own[k] < row[k] ? own[k] : row[k];
}

template <class T>
double CollisionPairs<T>::squaresRuledOut() const {
  const std::size_t offsets = forwardOffsets();
  if (!squares_used_ || stencil_active_.empty() || offsets == 0) return 0;
  // Each row of squares from the first thread that prepared it
  std::size_t tested = 0, squares = 0;
  const auto across = std::size_t(tilesAcross());
  for (int ty = 0; ty < tilesDown(); ++ty)
    for (std::size_t t = 0; t < active_rows_.size(); ++t)
      if (active_rows_[t].first <= ty && ty < active_rows_[t].second) {
        const std::uint64_t* row = stencil_active_.data() + t * tile_count_ + std::size_t(ty) * across;
        for (std::size_t tx = 0; tx < across; ++tx)
          tested += std::size_t(std::popcount(row[tx]));
        squares += across;
        break;
      }
  return squares == 0 ? 0 : 1.0 - double(tested) / double(squares * offsets);
}

// Each square's offsets to test in rows of squares [first, last): those whose least distance at the build does not
// exceed the range plus the most |d_i - d_j| of a pair from the square (the diagonal of the box of the displacements
// of every square a partner can lie in) plus the round-off farNeeded allows for. A NaN at the build, or a box that
// is not finite, tests them all. Where a partner is at most a square away (box_ <= edge_), those are the square and
// at most three beside and below it on the offset's side: pinned2 at 256^2 with CS184's thickness passed over 46% of
// the squares' offsets at its last substep, 33% with the nine around it (0.984 of the time). Else the boxes around a
// square are united by columns of squares first, then along the row (a sliding window each way instead of every
// square around every square: this ran a fifth of the stencil's instructions on a 50 x 50 cloth).
template <class T>
void CollisionPairs<T>::activeOffsets(long long first, long long last) {
  const int across = tilesAcross(), down = tilesDown();
  const int reach = (box_ + edge_ - 1) / edge_;  // squares away a partner can lie
  const std::size_t offsets = forwardOffsets();
  constexpr T kInf = std::numeric_limits<T>::infinity();
  const T room = T(64) * std::numeric_limits<T>::epsilon() * extent_;
  const auto thread = std::size_t(teamThread());
  std::uint64_t* const mine = stencil_active_.data() + thread * tile_count_;
  active_rows_[thread] = {int(first), int(last)};
  // The squared distance a square's offset must not exceed at the build to be tested, for the box of the
  // displacements of the squares its pairs lie in
  const auto needed = [&](vec3 lo, vec3 hi) {
    const vec3 box = hi - lo;
    const T diagonal2 = glm::dot(box, box);
    const T need = (range_ + std::sqrt(diagonal2) + room) * (T(1) + T(1.0 / 65536));
    return diagonal2 <= std::numeric_limits<T>::max() ? float(need * need) : __builtin_inff();
  };
  // Square (tx, ty)'s box of the displacements into [lo, hi], where the square is on the grid
  const auto box = [&](int tx, int ty, vec3& lo, vec3& hi) {
    if (tx < 0 || tx >= across || ty < 0 || ty >= down) return;
    const TileBox& b = boxes_[std::size_t(ty) * std::size_t(across) + std::size_t(tx)];
    lo = glm::min(lo, b.dlo);
    hi = glm::max(hi, b.dhi);
  };
  if (reach == 1) {
    // An offset's partners lie in the square or the ones beside and below it on the offset's side: four squares at
    // most (a partner is at most box_ <= edge_ columns and rows away), not the nine around it. Each forward offset's
    // squares by its kind: along the row (dv = 0, du > 0), down and right, straight down, down and left.
    const int half = int(stencil_.size() / 2);
    std::array<int, 64> kind{};
    for (std::size_t k = 0; k < offsets; ++k) {
      const int du = du_[std::size_t(half) + k], dv = dv_[std::size_t(half) + k];
      kind[k] = dv == 0 ? 0 : du > 0 ? 1 : du == 0 ? 2 : 3;
    }
    for (auto ty = int(first); ty < int(last); ++ty)
      for (int tx = 0; tx < across; ++tx) {
        float need2[4];
        vec3 lo(kInf), hi(-kInf);
        box(tx, ty, lo, hi);
        box(tx, ty + 1, lo, hi);
        need2[2] = needed(lo, hi);  // straight down
        vec3 right_lo = lo, right_hi = hi, left_lo = lo, left_hi = hi;
        box(tx + 1, ty + 1, right_lo, right_hi);
        box(tx - 1, ty + 1, left_lo, left_hi);
        lo = vec3(kInf), hi = vec3(-kInf);
        box(tx, ty, lo, hi);
        box(tx + 1, ty, lo, hi);
        need2[0] = needed(lo, hi);  // along the row
        box(tx + 1, ty, right_lo, right_hi);
        need2[1] = needed(right_lo, right_hi);
        box(tx - 1, ty, left_lo, left_hi);
        need2[3] = needed(left_lo, left_hi);
        const std::size_t t = std::size_t(ty) * std::size_t(across) + std::size_t(tx);
        const float* least = stencil_min2_.data() + t * offsets;
        std::uint64_t active = 0;
        for (std::size_t k = 0; k < offsets; ++k)
          active |= std::uint64_t(!(least[k] > need2[kind[k]])) << k;
        mine[t] = active;
      }
    return;
  }
  static thread_local std::vector<vec3> column_lo, column_hi;
  column_lo.resize(std::size_t(across));
  column_hi.resize(std::size_t(across));
  for (auto ty = int(first); ty < int(last); ++ty) {
    // Each column's displacements over the rows of squares a partner of this row can lie in
    for (int tx = 0; tx < across; ++tx) {
      vec3 lo(kInf), hi(-kInf);
      for (int y = ty - reach; y <= ty + reach; ++y)
        box(tx, y, lo, hi);
      column_lo[std::size_t(tx)] = lo;
      column_hi[std::size_t(tx)] = hi;
    }
    for (int tx = 0; tx < across; ++tx) {
      vec3 lo(kInf), hi(-kInf);
      for (int x = std::max(tx - reach, 0); x <= std::min(tx + reach, across - 1); ++x) {
        lo = glm::min(lo, column_lo[std::size_t(x)]);
        hi = glm::max(hi, column_hi[std::size_t(x)]);
      }
      const float need2 = needed(lo, hi);
      const std::size_t t = std::size_t(ty) * std::size_t(across) + std::size_t(tx);
      const float* least = stencil_min2_.data() + t * offsets;
      std::uint64_t active = 0;
      for (std::size_t k = 0; k < offsets; ++k)
        active |= std::uint64_t(!(least[k] > need2)) << k;
      mine[t] = active;
    }
  }
}

template bool CollisionPairs<float>::stencilTiles(bool, GridStencilTiles&);
template double CollisionPairs<float>::squaresRuledOut() const;
template void CollisionPairs<float>::activeOffsets(long long, long long);
template void CollisionPairs<float>::mergeSharedRecord(int, long long);
template bool CollisionPairs<double>::stencilTiles(bool, GridStencilTiles&);
template double CollisionPairs<double>::squaresRuledOut() const;
template void CollisionPairs<double>::activeOffsets(long long, long long);
template void CollisionPairs<double>::mergeSharedRecord(int, long long);

}  // namespace drape
