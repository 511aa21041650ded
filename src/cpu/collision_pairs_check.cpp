// CollisionPairs' check of whether the lists still hold (needsBuild), and the tiles it works by: kept apart
// from collision_pairs.cpp for its size.
#include "cpu/collision_pairs.hpp"
#include "cpu/parallel.hpp"

#include <algorithm>
#include <array>
#include <atomic>
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
void CollisionPairs<T>::startCheck(const std::vector<vec3>& x, long long stamp) {
  if (range_ != stencil_range_ || margin_ != stencil_margin_) makeStencil();
  kept_ = closerLooksKept();
  looked_.set = false;
  looked_at_.resize(std::size_t(std::max(teamSize(), 1)));
  moved_.set = !built_ || anchor_.size() != x.size() || travel_ <= T(0);
  split_ = !moved_.set && splitCheck();
  check_stamp_ = stamp;
  if (moved_.set) return;
  boxes_.resize(tile_count_);
  if (split_) return;
  // The box of every displacement first, all of it boxed by this thread (another's part may not be made yet)
  if (stamp >= 0 && padded_.x) {
    boxDisplacements(0, stamp, padded_.shape, padded_.x, padded_.y, padded_.z, 0, h_);
    if (displacementsHold(1)) {
      ++cleared_whole_;
      return;
    }
  }
  boxTiles(x, false);
  if (!moved_.set) compareTiles(x, false);
}

// Every thread of a team gets the same answer. A large grid's tiles are boxed and compared by all of the
// team's threads; a small cloth's by one, in startCheck, where splitting costs more barriers than it saves.
// A thread of the team may set moved_ while another has yet to read it, so which barriers a thread passes
// must not depend on moved_: it follows split_, which only startCheck writes, and the box of every displacement,
// which every thread makes alike from the same parts (a team's threads box their rows before startCheck's barrier).
template <class T>
bool CollisionPairs<T>::finishCheck(const std::vector<vec3>& x) {
  if (!split_) return moved_.set;
  if (displacementsHold(teamSize())) {
    if (teamThread() == 0) ++cleared_whole_;
    return false;
  }
  boxTiles(x, true);
  compareTiles(x, true);  // stops at once where a tile's displacements were not finite
  return moved_.set;
}

template <class T>
void CollisionPairs<T>::boxDisplacements(int part, long long stamp, const GridShape& shape, const float* x,
                                         const float* y, const float* z, int y0, int y1) {
  if (part < 0 || part >= kDisplacementParts) return;
  DisplacementPart& mine = displacement_parts_[std::size_t(part)];
  mine.stamp = -1;  // made for no check, unless made below
  if constexpr (std::is_same_v<T, float>) {
    if (!kernels_ || shape.W != w_ || shape.H != h_ || padded_anchor_[0].size() != shape.size) return;
    TileBoxArgs args{};
    args.shape = shape;
    args.px = x;
    args.py = y;
    args.pz = z;
    args.ax = padded_anchor_[0].data();
    args.ay = padded_anchor_[1].data();
    args.az = padded_anchor_[2].data();
    mine.finite = kernels_->displacementBox(args, y0, y1, mine.box);
    mine.stamp = stamp;
  }
}

template <class T>
bool CollisionPairs<T>::displacementBox(int parts, vec3& lo, vec3& hi) const {
  if (check_stamp_ < 0 || parts < 1 || parts > kDisplacementParts) return false;
  constexpr T kInf = std::numeric_limits<T>::infinity();
  lo = vec3(kInf);
  hi = vec3(-kInf);
  for (int k = 0; k < parts; ++k) {
    const DisplacementPart& p = displacement_parts_[std::size_t(k)];
    if (p.stamp != check_stamp_ || !p.finite) return false;
    lo = glm::min(lo, vec3(T(p.box[0]), T(p.box[1]), T(p.box[2])));
    hi = glm::max(hi, vec3(T(p.box[3]), T(p.box[4]), T(p.box[5])));
  }
  return true;
}

// The box of every displacement holds the two of any two tiles, so its diagonal within the limit clears every
// pair compareTiles would test, by the same arithmetic (max - min, then the squares summed x, y, z). Not where the
// stencil's squares read this substep's tile boxes (stencilReadsCheck).
template <class T>
bool CollisionPairs<T>::displacementsHold(int parts) const {
  vec3 lo, hi;
  if (stencilReadsCheck() || !displacementBox(parts, lo, hi)) return false;
  const vec3 box = hi - lo;
  const T limit = T(2) * travel_;
  return box.x * box.x + box.y * box.y + box.z * box.z <= limit * limit;
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
  if (w_ > 0 && uv_.size() == n) {  // squares of the grid, each row of a square a run
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

template void CollisionPairs<float>::startCheck(const std::vector<vec3>&, long long);
template void CollisionPairs<float>::boxDisplacements(int, long long, const GridShape&, const float*, const float*,
                                                      const float*, int, int);
template bool CollisionPairs<float>::displacementBox(int, vec3&, vec3&) const;
template bool CollisionPairs<float>::displacementsHold(int) const;
template bool CollisionPairs<float>::finishCheck(const std::vector<vec3>&);
template bool CollisionPairs<float>::splitCheck() const;
template void CollisionPairs<float>::boxTiles(const std::vector<vec3>&, bool);
template void CollisionPairs<float>::compareTiles(const std::vector<vec3>&, bool);
template bool CollisionPairs<float>::tilesHold(const std::vector<vec3>&, const std::uint32_t*, int, float, float) const;
template void CollisionPairs<float>::makeTiles(std::size_t);
template void CollisionPairs<double>::startCheck(const std::vector<vec3>&, long long);
template void CollisionPairs<double>::boxDisplacements(int, long long, const GridShape&, const float*, const float*,
                                                       const float*, int, int);
template bool CollisionPairs<double>::displacementBox(int, vec3&, vec3&) const;
template bool CollisionPairs<double>::displacementsHold(int) const;
template bool CollisionPairs<double>::finishCheck(const std::vector<vec3>&);
template bool CollisionPairs<double>::splitCheck() const;
template void CollisionPairs<double>::boxTiles(const std::vector<vec3>&, bool);
template void CollisionPairs<double>::compareTiles(const std::vector<vec3>&, bool);
template bool CollisionPairs<double>::tilesHold(const std::vector<vec3>&, const std::uint32_t*, int, double,
                                                double) const;
template void CollisionPairs<double>::makeTiles(std::size_t);

}  // namespace drape
