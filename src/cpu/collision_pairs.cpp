#include "cpu/collision_pairs.hpp"
#include "cpu/parallel.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <exception>
#include <limits>
#include <type_traits>
#include <utility>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace drape {

template <class T>
void CollisionPairs<T>::configure(T range, T margin) {
  if (range != range_ || margin != margin_) built_ = false;
  range_ = range;
  margin_ = margin;
}

template <class T>
void CollisionPairs<T>::setRest(std::vector<vec3> rest) {
  rest_ = std::move(rest);
  stencil_range_ = stencil_margin_ = -1;
  built_ = false;
}

template <class T>
void CollisionPairs<T>::setGrid(int w, int h) {
  w_ = w;
  h_ = h;
  const std::size_t n = std::size_t(w) * std::size_t(h);
  uv_.resize(n);
  for (std::size_t i = 0; i < n; ++i)
    uv_[i] = std::uint32_t(i % std::size_t(w)) | std::uint32_t(i / std::size_t(w)) << 16;
  stencil_range_ = stencil_margin_ = -1;
  tiled_ = std::size_t(-1);
  built_ = false;
}

// Which offsets hold, which are on the stencil, and which a build tests pair by pair. The rest shape is a grid
// origin + u a + v b to within `slack` a point (round-off, and a vertical cloth's millimetre of jitter out of
// its plane), so a pair at offset (du, dv) is within 2 slack of the offset's nominal distance |du a + dv b|:
// offsets surely under the range are held; those that may reach within range + margin at rest are on the
// stencil, which tests each pair's rest distance where the offset straddles the range (mixed: some of its
// pairs held, some not); the farther ones are the list's. No pair is classed by a guess: a mixed offset asks
// heldAtRest pair by pair, as the list does.
template <class T>
void CollisionPairs<T>::makeStencil() {
  a2_ = b2_ = 0;
  near_below_ = -1;
  stencil_.clear();
  du_.clear();
  dv_.clear();
  mixed_.clear();
  kind_.clear();
  forward_bits_ = 0;
  box_ = -1;
  stencil_range_ = range_;
  stencil_margin_ = margin_;
  if (w_ < 2 || h_ < 2 || rest_.size() != std::size_t(w_) * std::size_t(h_)) return;
  const auto at = [&](int u, int v) { return glm::dvec3(rest_[std::size_t(v) * std::size_t(w_) + std::size_t(u)]); };
  // The grid's steps from its corners (a jitter averages out over a row)
  const glm::dvec3 origin = at(0, 0), a = (at(w_ - 1, 0) - origin) / double(w_ - 1),
                   b = (at(0, h_ - 1) - origin) / double(h_ - 1);
  const double step = std::min(glm::length(a), glm::length(b));
  if (!(step > 0) || !std::isfinite(step)) return;
  // Square to round-off, so that a pair off the box (|du| or |dv| over it) is farther than the box reaches.
  if (std::abs(glm::dot(a, b)) > 1e-6 * glm::length(a) * glm::length(b)) return;
  double extent = 0, off = 0;
  for (int v = 0; v < h_; ++v)
    for (int u = 0; u < w_; ++u) {
      extent = std::max(extent, glm::length(at(u, v)));
      off = std::max(off, glm::length(at(u, v) - (origin + double(u) * a + double(v) * b)));
    }
  // Each distance computed in T is off by a few ulps of the coordinates: 64 of the largest cover it.
  const double slack = 2 * off + 64 * std::numeric_limits<T>::epsilon() * (extent + step);
  const double range = double(range_), reach = double(range_ + margin_);
  if (slack > 0.25 * step) return;  // not a grid
  const int box = std::min(int(std::ceil((reach + slack) / step)) + 1, std::max(w_, h_) - 1);
  if (box < 1 || box > kMaxStencilBox) return;
  box_ = box;
  const int side = 2 * box + 1;
  kind_.assign(std::size_t(side) * std::size_t(side), kList);
  std::vector<std::uint8_t> straddles(kind_.size(), 0);
  for (int dv = -box; dv <= box; ++dv)
    for (int du = -box; du <= box; ++du) {
      const double nominal = glm::length(double(du) * a + double(dv) * b);
      const std::size_t k = std::size_t((dv + box) * side + du + box);
      if (du == 0 && dv == 0) continue;
      if (nominal + slack < range)
        kind_[k] = kHeld;
      else if (nominal - slack < reach)
        kind_[k] = kStencil;
      straddles[k] = nominal - slack <= range && nominal + slack >= range;
      if (kind_[k] == kStencil) {
        stencil_.push_back({du, dv, std::int64_t(dv) * w_ + du});
        mixed_.push_back(straddles[k]);
      }
    }
  // What scanPairs passes over without a look at the table: the offsets held or on the stencil are exactly
  // those under reach + slack, less a margin for the float arithmetic of the nominal distance.
  a2_ = T(glm::dot(a, a));
  b2_ = T(glm::dot(b, b));
  near_below_ = T((reach + slack) * (reach + slack) * (1 - 1e-5));
  std::vector<std::size_t> order(stencil_.size());
  for (std::size_t k = 0; k < order.size(); ++k)
    order[k] = k;
  std::sort(order.begin(), order.end(),
            [&](std::size_t p, std::size_t q) { return stencil_[p].step < stencil_[q].step; });
  std::vector<Offset> sorted;
  std::vector<std::uint8_t> mixed;
  for (std::size_t k : order) {
    sorted.push_back(stencil_[k]);
    mixed.push_back(mixed_[k]);
    du_.push_back(stencil_[k].du);
    dv_.push_back(stencil_[k].dv);
  }
  stencil_ = std::move(sorted);
  mixed_ = std::move(mixed);
  forward_bits_ = 0;
  // The stencil is symmetric and sorted by step: its second half is the offsets of positive step.
  for (std::size_t k = stencil_.size() / 2; k < stencil_.size(); ++k)
    forward_bits_ |= stencilBit(int(k));
}

template <class T>
StencilMask CollisionPairs<T>::stencilMask(const std::vector<vec3>& x, std::size_t i) const {
  const int u = columnOf(uv_[i]), v = rowOf(uv_[i]);
  const T range2 = range_ * range_;
  StencilMask mask = 0;
  for (std::size_t k = 0; k < stencil_.size(); ++k) {
    const Offset& o = stencil_[k];
    if (!onGrid(u + o.du, v + o.dv)) continue;
    const std::size_t j = std::size_t(std::int64_t(i) + o.step);
    if (mixed_[k] && physics::heldAtRest(rest_[i], rest_[j], range_)) continue;
    const vec3 d = x[i] - x[j];
    if (!(glm::dot(d, d) >= range2)) mask |= stencilBit(int(k));  // selfCollisionCorrection's test; NaN counts
  }
  return mask;
}

template <class T>
T CollisionPairs<T>::safeTravel(T margin, T extent) {
  // Each computed distance is off by at most a few ulps of the coordinates it came from; 16 ulps of
  // the largest coordinate covers the differences, dot products and square roots of the argument.
  return T(0.5) * margin - T(16) * std::numeric_limits<T>::epsilon() * extent;
}

// startCheck may throw (it allocates): in a team that is kept, as the build keeps its failures, and the
// answer is false (no build) until the caller has taken it (takeFailure); outside a team it is thrown.
template <class T>
bool CollisionPairs<T>::needsBuild(const std::vector<vec3>& x) {
  teamSingle([&] { guarded([&] { startCheck(x); }); });
  if (failure_) {
    rethrowOutsideTeam();
    return false;
  }
  return finishCheck(x);
}

template <class T>
bool CollisionPairs<T>::update(const std::vector<vec3>& x, int threads) {
  if (!needsBuild(x)) return false;
  build(x, threads);
  return true;
}

template <class T>
template <class F>
void CollisionPairs<T>::guarded(F&& f) {
  try {
    f();
  } catch (...) {
    failure_ = std::current_exception();
  }
}

template <class T>
void CollisionPairs<T>::rethrowOutsideTeam() {
  if (!failure_ || inTeam()) return;
  std::exception_ptr e = failure_;
  failure_ = nullptr;
  std::rethrow_exception(e);
}

template <class T>
bool CollisionPairs<T>::farNeeded(bool just_built) const {
  if (far_.start.empty() || far_.start.back() == 0) return false;
  T diagonal2 = 0;  // just built: no displacement
  if (!just_built) {
    // The box of every displacement, as this substep's check made it: whole, or from its tiles (the same bounds)
    vec3 lo, hi;
    if (!displacementBox(split_ ? teamSize() : 1, lo, hi)) {
      if (boxes_.size() != tile_count_ || boxes_.empty()) return true;
      constexpr T kInf = std::numeric_limits<T>::infinity();
      lo = vec3(kInf);
      hi = vec3(-kInf);
      for (const TileBox& b : boxes_) {
        lo = glm::min(lo, b.dlo);
        hi = glm::max(hi, b.dhi);
      }
    }
    const vec3 box = hi - lo;
    diagonal2 = glm::dot(box, box);
    if (!(diagonal2 <= std::numeric_limits<T>::max())) return true;  // not finite
  }
  // Each computed distance is off by a few ulps of the coordinates it came from (safeTravel): 64 of the largest,
  // and a relative 2^-16 on top, cover the distances at the build and now and the box.
  const T reach =
      (range_ + std::sqrt(diagonal2) + T(64) * std::numeric_limits<T>::epsilon() * extent_) * (T(1) + T(1.0 / 65536));
  return !(reach < near_reach_);
}

template <class T>
auto CollisionPairs<T>::bothEnds() const -> const BothEnds& {
  BothEnds& b = both_ends_;
  if (b.made) return b;
  const std::size_t n = near_.start.empty() ? 0 : near_.start.size() - 1;
  b.start.assign(n + 1, 0);
  for (const EntryPart* part : {&near_, &far_})
    for (std::size_t k = 0; k < (n ? part->start[n] : 0); ++k) {
      ++b.start[part->owner[k] + 1];
      ++b.start[part->partner[k] + 1];
    }
  for (std::size_t i = 0; i < n; ++i)
    b.start[i + 1] += b.start[i];
  b.list.resize(b.start[n]);
  std::vector<std::uint32_t> fill(b.start.begin(), b.start.end() - 1);
  for (const EntryPart* part : {&near_, &far_})
    for (std::size_t k = 0; k < (n ? part->start[n] : 0); ++k) {
      b.list[fill[part->owner[k]]++] = part->partner[k];
      b.list[fill[part->partner[k]]++] = part->owner[k];
    }
  for (std::size_t i = 0; i < n; ++i)
    std::sort(b.list.begin() + b.start[i], b.list.begin() + b.start[i + 1]);
  b.made = true;
  return b;
}

// assembleLists' shares of the points, each with about as many of the last build's entries and points as the next:
// where a cloth folds its points have the most (CS184's selfCollision on two threads: one of even shares of the
// points took 1.5 times as long as the other). Even shares where no lists were built for as many points.
template <class T>
void CollisionPairs<T>::assembleBounds(std::size_t n, std::size_t shares) {
  assemble_bounds_.assign(shares + 1, std::uint32_t(n));
  assemble_bounds_[0] = 0;
  // A point's cost: its entries, where the last lists were built for as many points, and itself
  const bool last = near_.start.size() == n + 1 && far_.start.size() == n + 1;
  const auto before = [&](std::size_t i) {
    return (last ? std::uint64_t(near_.start[i]) + far_.start[i] : 0) + i;  // the cost of the points before i
  };
  for (std::size_t d = 1; d < shares; ++d) {
    // The first point whose points before it reach share d's start (their cost only grows with it)
    const std::uint64_t target = before(n) * d / shares;
    std::size_t lo = 0, hi = n;
    while (lo < hi) {
      const std::size_t mid = lo + (hi - lo) / 2;
      if (before(mid) < target)
        lo = mid + 1;
      else
        hi = mid;
    }
    assemble_bounds_[d] = std::uint32_t(lo);
  }
}

template class CollisionPairs<float>;
template class CollisionPairs<double>;

HeldPairs heldPairsAtRest(const std::vector<glm::dvec3>& rest, double range) {
  HeldPairs out;
  if (rest.size() < 2) return out;
  HashGrid<double> grid;
  grid.build(rest, range);
  // The points in the grid's order, a coordinate an array: a row of a point's forward cells is then one run of
  // each, tested two at a time. A fine cloth has about a hundred points a cell (512 x 512 with CS184's thickness:
  // 1,270 candidates a point; one at a time they took 0.37 s of `drape simulate`'s 0.68 s start, now about 0.07).
  const std::vector<std::uint32_t>& sorted = grid.sorted();
  const std::size_t n = rest.size();
  std::vector<double> xs(n), ys(n), zs(n);
  for (std::size_t s = 0; s < n; ++s) {
    xs[s] = rest[sorted[s]].x;
    ys[s] = rest[sorted[s]].y;
    zs[s] = rest[sorted[s]].z;
  }
  const double range2 = range * range;
  std::size_t count = 0;
  double closest2 = range2;
  for (std::size_t i = 0; i < n; ++i) {
    const glm::dvec3 p = rest[i];
    const auto distance2 = [&](std::uint32_t s) {
      const double dx = p.x - xs[s], dy = p.y - ys[s], dz = p.z - zs[s];
      return dx * dx + dy * dy + dz * dz;
    };
    const auto take = [&](double d2) {
      count += d2 < range2;
      closest2 = std::min(closest2, d2);
    };
    grid.forEachForwardBucket(i, [&](std::uint32_t first, std::uint32_t last, glm::ivec3 cell) {
      // Every slot of a dense range is a candidate; a hashed bucket may hold other cells' points too
      if (!grid.dense()) {
        for (std::uint32_t s = first; s < last; ++s)
          if (grid.inCell(sorted[s], cell)) take(distance2(s));
        return;
      }
      // Two lanes of doubles (SSE2, which every x86-64 has): the compiler keeps a loop with a least value scalar
      std::uint32_t s = first;
#if defined(__SSE2__)
      const __m128d px = _mm_set1_pd(p.x), py = _mm_set1_pd(p.y), pz = _mm_set1_pd(p.z), r2 = _mm_set1_pd(range2);
      __m128d least = _mm_set1_pd(closest2), in_range = _mm_setzero_pd();
      for (; s + 2 <= last; s += 2) {
        const __m128d dx = _mm_sub_pd(px, _mm_loadu_pd(&xs[s])), dy = _mm_sub_pd(py, _mm_loadu_pd(&ys[s])),
                      dz = _mm_sub_pd(pz, _mm_loadu_pd(&zs[s]));
        const __m128d d2 = _mm_add_pd(_mm_add_pd(_mm_mul_pd(dx, dx), _mm_mul_pd(dy, dy)), _mm_mul_pd(dz, dz));
        in_range = _mm_add_pd(in_range, _mm_and_pd(_mm_cmplt_pd(d2, r2), _mm_set1_pd(1.0)));
        least = _mm_min_pd(least, d2);
      }
      double lanes[2], counts[2];
      _mm_storeu_pd(lanes, least);
      _mm_storeu_pd(counts, in_range);
      closest2 = std::min(lanes[0], lanes[1]);
      count += std::size_t(counts[0] + counts[1]);
#endif
      for (; s < last; ++s)
        take(distance2(s));
    });
  }
  out.count = count;
  out.closest = count ? std::sqrt(closest2) : 0.0;
  return out;
}

}  // namespace drape
