// CollisionPairs' check of whether the lists still hold (needsBuild), and the tiles it works by: kept apart
// from collision_pairs.cpp for its size.
#include "cpu/collision_pairs.hpp"
#include "cpu/parallel.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <limits>
#include <type_traits>

namespace drape {

// A pair not listed was at least range + margin apart at the build, and its distance has changed since by at
// most |d_i - d_j|, d being each point's displacement from its anchor: at most the diagonal of the box
// around the d of i's tile and j's tile together. The lists hold while that diagonal is under the margin
// (2 * travel_, less round-off) for every two tiles (or one) close enough now to hold a pair in range: tiles
// farther apart than the range hold none, whatever their motion. So the motion a region shares with its
// neighbours (a cloth falling, swinging, unfolding) does not wear the lists out, only the motion of one
// region against another that touches it. One tile would be the box of every d (the GPU's test, a single
// reduction), which a swinging cloth wears out in a few substeps: its free end moves against its pins.
// Tiles: squares of the grid, or runs of points in index order on a mesh. Where a grid's two tiles fail, the same
// test on smaller squares of them, then on their points (tilesHold), may still clear them.
// The serial part of the check; on a cloth too small to split it, all of it (one barrier a substep in a team).
template <class T>
void CollisionPairs<T>::startCheck(const std::vector<vec3>& x) {
  if (range_ != stencil_range_ || margin_ != stencil_margin_) makeStencil();
  kept_ = closerLooksKept();
  looked_.set = false;
  looked_at_.resize(std::size_t(std::max(teamSize(), 1)));
  moved_.set = !built_ || anchor_.size() != x.size() || travel_ <= T(0);
  split_ = !moved_.set && splitCheck();
  if (moved_.set) return;
  boxes_.resize(tile_count_);
  if (split_) return;
  boxTiles(x, false);
  if (!moved_.set) compareTiles(x, false);
}

// Every thread of a team gets the same answer. A large grid's tiles are boxed and compared by all of the
// team's threads; a small cloth's by one, in startCheck, where splitting costs more barriers than it saves.
// A thread of the team may set moved_ while another has yet to read it, so which barriers a thread passes
// must not depend on moved_: it follows split_, which only startCheck writes.
template <class T>
bool CollisionPairs<T>::finishCheck(const std::vector<vec3>& x) {
  if (!split_) return moved_.set;
  boxTiles(x, true);
  compareTiles(x, true);  // stops at once where a tile's displacements were not finite
  return moved_.set;
}

template <class T>
bool CollisionPairs<T>::splitCheck() const {
  if constexpr (std::is_same_v<T, float>) return inTeam() && kernels_ && edge_ > 0 && tile_count_ >= kSplitTiles;
  return false;
}

// Each tile's boxes into boxes_ (moved_ set where a displacement is not finite). split: this thread's share
// of the rows of tiles, in a team (a float grid with the kernels).
template <class T>
void CollisionPairs<T>::boxTiles(const std::vector<vec3>& x, bool split) {
  if constexpr (std::is_same_v<T, float>)
    if (kernels_ && edge_ > 0) {  // a grid's tiles, rows of several points at once
      static_assert(sizeof(TileBox) == 12 * sizeof(float));
      const int across = tilesAcross(), down = tilesDown();
      TileBoxArgs args{&x.data()->x, &anchor_.data()->x, w_, h_, edge_, across, &boxes_.data()->dlo.x, 0, 0};
      if (padded_.x && padded_anchor_[0].size() == padded_.shape.size) {
        args.shape = padded_.shape;
        args.px = padded_.x;
        args.py = padded_.y;
        args.pz = padded_.z;
        args.ax = padded_anchor_[0].data();
        args.ay = padded_anchor_[1].data();
        args.az = padded_anchor_[2].data();
      }
      const auto rows = [&](long long first, long long last) {
        TileBoxArgs mine = args;
        mine.tv0 = int(first);
        mine.tv1 = int(last);
        if (!kernels_->tileBoxes(mine)) moved_.set = true;
      };
      if (split)
        teamRange(0, down, rows);
      else
        rows(0, down);
      return;
    }
  std::fill(boxes_.begin(), boxes_.end(), TileBox::empty());
  bool finite = true;
  for (const Run& r : runs_) {
    TileBox run = TileBox::empty();
    for (std::uint32_t i = r.begin; i < r.end; ++i) {
      const vec3 d = x[i] - anchor_[i];
      // A non-finite position counts as moved (glm::min and max would pass over a NaN).
      finite = finite && glm::dot(d, d) <= std::numeric_limits<T>::infinity();
      run.add(x[i], d);
    }
    boxes_[r.tile].add(run);
  }
  if (!finite) moved_.set = true;
}

// Sets moved_ if two tiles close enough to hold a pair in range have moved apart by the margin (see above), and a
// closer look does not clear them (tilesHold). split: this thread takes every count-th first tile (the later a tile,
// the fewer partners it has after it: interleaving evens the shares), then the team waits, and every thread looks
// at the pairs all of them found: each reaches the answer one thread would, with no barrier more.
template <class T>
void CollisionPairs<T>::compareTiles(const std::vector<vec3>& x, bool split) {
  const T limit = T(2) * travel_;
  // Tiles this far apart hold no pair in range, with room for the round-off of the boxes' differences.
  const T apart = range_ + travel_;
  std::size_t first = 0, step = 1;
  if (split) {
    first = std::size_t(teamThread());
    step = std::size_t(teamSize());
  }
  // The pairs the boxes did not clear; beyond kLookedAt in all, a build
  LookedAt& found = looked_at_[first];
  found.count = 0;
  const auto add = [&](std::size_t a, std::size_t c) {
    if (found.count == kLookedAt) return false;
    found.pairs[std::size_t(2 * found.count)] = std::uint32_t(a);
    found.pairs[std::size_t(2 * found.count + 1)] = std::uint32_t(c);
    ++found.count;
    return true;
  };
  bool tested = false;
  if constexpr (std::is_same_v<T, float>)
    if (kernels_ && boxes_.size() <= std::size_t(kMaxCompareTiles)) {
      static_assert(sizeof(TileBox) == 12 * sizeof(float));
      TileCompareArgs args{&boxes_.data()->dlo.x, int(boxes_.size()), int(first), int(step),
                           apart * apart,         limit * limit,      &moved_.set};
      if (edge_ > 0) {
        args.found = found.pairs.data();
        args.capacity = kLookedAt;
        args.found_count = &found.count;
      }
      if (kernels_->tilesMovedApart(args)) moved_.set = true;
      tested = true;
    }
  for (std::size_t a = first; !tested && a < boxes_.size() && !moved_.set.load(std::memory_order_relaxed); a += step) {
    const TileBox& p = boxes_[a];
    if (!(p.lo.x <= p.hi.x)) continue;  // an empty tile
    for (std::size_t c = a; c < boxes_.size(); ++c) {
      const TileBox& q = boxes_[c];
      if (!(q.lo.x <= q.hi.x)) continue;
      if (!TileBox::clear(p, q, limit, apart) && (edge_ <= 0 || !add(a, c))) {
        moved_.set = true;
        break;
      }
    }
  }
  if (split) teamBarrier();
  LookedAt all;
  all.count = 0;
  for (std::size_t t = 0; t < step; ++t) {
    const LookedAt& part = looked_at_[t];
    if (all.count + part.count > kLookedAt) {
      moved_.set = true;
      return;
    }
    std::copy(part.pairs.begin(), part.pairs.begin() + 2 * part.count, all.pairs.begin() + 2 * all.count);
    all.count += part.count;
  }
  // A thread may set moved_ while another is still looking: that one then stops, with the same answer
  if (all.count > 0 && !moved_.set.load(std::memory_order_relaxed)) {
    if (tilesHold(x, all.pairs.data(), all.count, limit, apart))
      looked_.set = true;
    else
      moved_.set = true;
  }
}

// Pairs of a grid's tiles that compareTiles' boxes could not clear (or a tile alone, a == c), looked at again in
// squares of about a quarter of a tile's edge, and where two of those cannot be cleared either, point by point:
// the same test on smaller boxes, down to the pairs themselves. The boxes of two whole tiles span twice a tile's
// width, while only points closer than the range can collide: at 256 x 256 with CS184's thickness a few tiles at a
// time (the corners turning about the pins, then the free hem, a fold: 4 to 8 of 256 most often) wore out every
// list in 11 substeps. Only while the
// tiles to look at hold at most 1/kLookShare of the points: where most of a cloth moves apart (a swinging 50 x 50),
// looking closely every substep cost more than the builds it spared.
template <class T>
bool CollisionPairs<T>::tilesHold(const std::vector<vec3>& x, const std::uint32_t* found, int count, T limit,
                                  T apart) const {
  // The tiles to look at, each once, within the share of the points
  std::array<std::uint32_t, 2 * kLookedAt> tiles;
  std::copy(found, found + 2 * count, tiles.begin());
  std::sort(tiles.begin(), tiles.begin() + 2 * count);
  const auto distinct = std::size_t(std::unique(tiles.begin(), tiles.begin() + 2 * count) - tiles.begin());
  if (distinct > kLookedTiles || (distinct > 2 && distinct * std::size_t(edge_ * edge_) * kLookShare > x.size()))
    return false;
  const int across = tilesAcross();
  const int sub = (edge_ + kSubSquares - 1) / kSubSquares, per = (edge_ + sub - 1) / sub;
  // Square s of tile t: its first column and row, and one past its last
  struct Square {
    int u0, v0, u1, v1;
  };
  const auto square = [&](std::uint32_t t, int s) {
    const int tu = int(t % std::uint32_t(across)) * edge_, tv = int(t / std::uint32_t(across)) * edge_;
    const int u0 = tu + s % per * sub, v0 = tv + s / per * sub;
    return Square{u0, v0, std::min({u0 + sub, w_, tu + edge_}), std::min({v0 + sub, h_, tv + edge_})};
  };
  // f(its point's box) for each point of square e
  const auto forEachPoint = [&](const Square& e, auto&& f) {
    for (int v = e.v0; v < e.v1; ++v)
      for (int u = e.u0; u < e.u1; ++u) {
        const std::size_t i = std::size_t(v) * std::size_t(w_) + std::size_t(u);
        const vec3 d = x[i] - anchor_[i];
        if (!f(TileBox{d, d, x[i], x[i]})) return false;
      }
    return true;
  };
  using Squares = std::array<TileBox, kSubSquares * kSubSquares>;
  std::array<Squares, kLookedTiles> boxes;
  for (std::size_t k = 0; k < distinct; ++k)
    for (int s = 0; s < per * per; ++s) {
      TileBox& q = boxes[k][std::size_t(s)] = TileBox::empty();
      forEachPoint(square(tiles[k], s), [&](const TileBox& point) {
        q.add(point);
        return true;
      });
    }
  const auto pointsClear = [&](const Square& e, const Square& f) {
    return forEachPoint(e, [&](const TileBox& p) {
      return forEachPoint(f, [&](const TileBox& q) { return TileBox::clear(p, q, limit, apart); });
    });
  };
  const auto index = [&](std::uint32_t t) {
    return std::size_t(std::lower_bound(tiles.begin(), tiles.begin() + std::ptrdiff_t(distinct), t) - tiles.begin());
  };
  for (int k = 0; k < count; ++k) {
    const std::uint32_t a = found[2 * k], c = found[2 * k + 1];
    const Squares &in_a = boxes[index(a)], &in_c = boxes[index(c)];
    for (int s = 0; s < per * per; ++s)
      for (int r = a == c ? s : 0; r < per * per; ++r)
        if (!TileBox::clear(in_a[std::size_t(s)], in_c[std::size_t(r)], limit, apart) &&
            (sub == 1 || !pointsClear(square(a, s), square(c, r))))
          return false;
  }
  return true;
}

// Tiles of about kTilePoints points, at most kMaxTiles of them (compareTiles() compares every two).
template <class T>
void CollisionPairs<T>::makeTiles(std::size_t n) {
  runs_.clear();
  tiled_ = n;
  edge_ = 0;
  if (w_ > 0 && u_.size() == n) {  // squares of the grid, each row of a square a run
    const int edge =
        std::max({kTileEdge, (w_ + kTilesAcross - 1) / kTilesAcross, (h_ + kTilesAcross - 1) / kTilesAcross});
    const int across = (w_ + edge - 1) / edge;
    for (int v = 0; v < h_; ++v)
      for (int u = 0; u < w_; u += edge)
        runs_.push_back({std::uint32_t(v * w_ + u), std::uint32_t(v * w_ + std::min(u + edge, w_)),
                         std::uint32_t(v / edge * across + u / edge)});
    tile_count_ = std::size_t(across) * std::size_t((h_ + edge - 1) / edge);
    edge_ = edge;
  } else {
    const std::size_t run = std::max<std::size_t>(
        std::size_t(kTileEdge) * kTileEdge, (n + kTilesAcross * kTilesAcross - 1) / (kTilesAcross * kTilesAcross));
    for (std::size_t i = 0; i < n; i += run)
      runs_.push_back({std::uint32_t(i), std::uint32_t(std::min(n, i + run)), std::uint32_t(i / run)});
    tile_count_ = runs_.size();
  }
}

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

template void CollisionPairs<float>::startCheck(const std::vector<vec3>&);
template bool CollisionPairs<float>::finishCheck(const std::vector<vec3>&);
template bool CollisionPairs<float>::splitCheck() const;
template void CollisionPairs<float>::boxTiles(const std::vector<vec3>&, bool);
template void CollisionPairs<float>::compareTiles(const std::vector<vec3>&, bool);
template bool CollisionPairs<float>::tilesHold(const std::vector<vec3>&, const std::uint32_t*, int, float, float) const;
template void CollisionPairs<float>::makeTiles(std::size_t);
template bool CollisionPairs<float>::stencilTiles(bool, GridStencilTiles&);
template double CollisionPairs<float>::squaresRuledOut() const;
template void CollisionPairs<float>::activeOffsets(long long, long long);
template void CollisionPairs<float>::mergeSharedRecord(int, long long);
template void CollisionPairs<double>::startCheck(const std::vector<vec3>&);
template bool CollisionPairs<double>::finishCheck(const std::vector<vec3>&);
template bool CollisionPairs<double>::splitCheck() const;
template void CollisionPairs<double>::boxTiles(const std::vector<vec3>&, bool);
template void CollisionPairs<double>::compareTiles(const std::vector<vec3>&, bool);
template bool CollisionPairs<double>::tilesHold(const std::vector<vec3>&, const std::uint32_t*, int, double,
                                                double) const;
template void CollisionPairs<double>::makeTiles(std::size_t);
template bool CollisionPairs<double>::stencilTiles(bool, GridStencilTiles&);
template double CollisionPairs<double>::squaresRuledOut() const;
template void CollisionPairs<double>::activeOffsets(long long, long long);
template void CollisionPairs<double>::mergeSharedRecord(int, long long);

}  // namespace drape
