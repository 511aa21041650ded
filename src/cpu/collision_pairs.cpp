#include "cpu/collision_pairs.hpp"
#include "core/memory_stage.hpp"
#include "cpu/parallel.hpp"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <chrono>
#include <cmath>
#include <exception>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <type_traits>
#include <utility>

namespace drape {

namespace {

// The largest |c| of `count` coordinates and `least` (>= 0), a NaN passed over as std::max passes it. Float's compared
// as the bits of |c|, which order as the values do for every float from +0 to infinity: a loop the compiler
// vectorises, where it may not reorder a float maximum (a fifth of finishBuild's time, one point at a time).
template <class T>
T largestCoordinate(const T* c, std::size_t count, T least) {
  if constexpr (std::is_same_v<T, float>) {
    std::int32_t most = std::bit_cast<std::int32_t>(least);
    for (std::size_t k = 0; k < count; ++k) {
      const std::int32_t b = std::bit_cast<std::int32_t>(c[k]) & 0x7fffffff;
      most = std::max(most, b > 0x7f800000 ? 0 : b);
    }
    return std::bit_cast<float>(most);
  } else {
    T most = least;
    for (std::size_t k = 0; k < count; ++k)
      most = std::max(most, std::abs(c[k]));
    return most;
  }
}

}  // namespace

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
  u_.resize(n);
  v_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    u_[i] = std::uint16_t(i % std::size_t(w));
    v_[i] = std::uint16_t(i / std::size_t(w));
  }
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
  const int u = u_[i], v = v_[i];
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

// In a team every thread calls build(): the serial steps run on one of them (teamSingle), the points and the
// lists' sorting are split between them (teamRange). Outside a team the point loops fork their own (teamFor).
// An exception may not leave an OpenMP region: a step that fails keeps it, the rest are skipped, and the
// caller rethrows it (failure()), outside a team at once.
template <class T>
void CollisionPairs<T>::build(const std::vector<vec3>& x, int threads) {
  const bool team = inTeam();
  prepareBuild(x, team ? teamSize() : threads);
  if (failure_) return rethrowOutsideTeam();
  const long long count = (long long)x.size();
  if (team) {
    // A folded cloth's candidates crowd in its fold: the shares follow the time they take. Dealing chunks of 1/32 in
    // turn instead spread them blindly and read most candidates from the other core's cache.
    const auto t = std::size_t(teamThread());
    const auto start = std::chrono::steady_clock::now();
    findPairs(x, int(t), search_bounds_[t], search_bounds_[t + 1]);
    search_seconds_[t] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    teamBarrier();
  } else {
#pragma omp parallel num_threads(teamFor(threads, count))
    {
      const int t = omp_get_thread_num(), n = omp_get_num_threads();
      findPairs(x, t, evenShare(count, t, n), evenShare(count, t + 1, n));
    }
  }
  if (!teamSerial(failure_, [&] {
        if (out_of_memory_.set) {
          found_.clear();
          failAllocation();
        }
        if (team) balanceShares(search_bounds_, search_seconds_, search_per_point_, 0.5, std::max(1LL, count / 16));
        sizeLists(x.size());
      }))
    return rethrowOutsideTeam();
  assembleLists(x.size());
  finishBuild(x);
  rethrowOutsideTeam();
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

// The grid, and the candidates' positions (and on a grid their columns and rows) in the grid's order, so that
// a point's buckets are read in sequence, several candidates at once (scanPairs): most are out of reach, held
// by the springs, or the stencil's, and only the rest are looked at one by one. In a team every thread calls it
// and the points are split between them; what fails is kept in failure_.
template <class T>
void CollisionPairs<T>::prepareBuild(const std::vector<vec3>& x, int threads) {
  const T reach = range_ + margin_;
  const std::size_t n = x.size();
  if (!teamSerial(failure_, [&] {
        // A pair's part rides in its upper end's top bit (Pair)
        if (n > kFarBit) throw std::length_error("self-collision lists take at most 2^31 points");
        near_reach_ = range_ + T(0.5) * margin_;
        by_offset_ = box_ >= 0 && u_.size() == n;
        for (std::vector<T>* a : {&sx_, &sy_, &sz_, &su_, &sv_})
          a->resize(n + kPairScanPad);  // the pad is read by the kernels' last vectors, whose lanes there are dropped
        for (std::vector<T>* a : {&su_, &sv_})
          std::fill(a->begin() + std::ptrdiff_t(n), a->end(), T(0));
        scan_ = ScanArgs{sx_.data(), sy_.data(), sz_.data(), su_.data(),    sv_.data(), 0, 0,
                         0,          0,          0,          reach * reach, 0,          0, T(-1)};
        if (by_offset_) {
          scan_.a2 = a2_;
          scan_.b2 = b2_;
          scan_.near_below = near_below_;
        }
        // Every thread's pairs go, not only those of the threads this build runs on: a build on one thread after
        // one on a team would list the team's other pairs again.
        assemblers_ = std::size_t(teamSize());
        found_.resize(std::size_t(std::max(threads, 1)) * assemblers_);
        cell_found_.resize(std::size_t(std::max(threads, 1)));
        for (Found& part : found_)
          part.value.clear();
        assembleBounds(n);
        if (const auto team = std::size_t(teamSize());
            search_bounds_.size() != team + 1 || search_bounds_.back() != (long long)n) {  // even at first
          search_bounds_.resize(team + 1);
          for (std::size_t t = 0; t <= team; ++t)
            search_bounds_[t] = evenShare((long long)n, (long long)t, (long long)team);
          search_seconds_.assign(team, 0);
          search_per_point_.assign(team, -1);
        }
        out_of_memory_.set = false;
      }))
    return;
  grid_.build(x, reach, failure_);  // cells at least as large as the reach, so neighbouring cells hold every candidate
  if (failure_) return;
  const std::vector<std::uint32_t>& sorted = grid_.sorted();
  // In a team each thread its share of the search, whose candidates are mostly its own slots
  const bool team = inTeam();
  const auto t = std::size_t(teamThread());
  const auto first = std::size_t(team ? search_bounds_[t] : 0), last = team ? std::size_t(search_bounds_[t + 1]) : n;
  for (std::size_t s = first; s < last; ++s) {
    const std::uint32_t j = sorted[s];
    sx_[s] = x[j].x;
    sy_[s] = x[j].y;
    sz_[s] = x[j].z;
    su_[s] = by_offset_ ? T(u_[j]) : T(0);
    sv_[s] = by_offset_ ? T(v_[j]) : T(0);
  }
  teamBarrier();
}

template <class T>
void CollisionPairs<T>::sizeLists(std::size_t n) {
  both_ends_.made = false;
  std::size_t pairs = 0;
  for (const Found& part : found_)
    pairs += part.value.size();
  for (EntryPart* part : {&near_, &far_}) {
    part->start.resize(n + 1);
    part->start[0] = 0;
    if (part->owner.size() < pairs) {  // only grown: either part may hold every pair
      part->owner.resize(pairs);
      part->partner.resize(pairs);
    }
  }
  fill_.resize(2 * n);
  part_pairs_.assign(2 * std::size_t(teamSize()), 0);
}

// The pairs every thread found into the entries, near and far (each pair's part was told by the thread that found
// it, from the build's distance), by their lower ends: in a team each thread takes the pairs of its share of the
// points (reading every thread's), counts them, and after a barrier places them from the entries of the threads
// before it. A point's partners are in the order the pairs were found, whichever threads place them. One thread did
// it all while the others waited: 0.19 ms a build at 256^2. Listing every pair and then parting them by a second
// look at each one's distance (finishBuild, before) made CS184's selfCollision 1.02 times as long on one thread.
template <class T>
void CollisionPairs<T>::assembleLists(std::size_t n) {
  const auto thread = std::size_t(teamThread()), team = std::size_t(teamSize());
  const std::uint32_t lo = assemble_bounds_[thread], hi = assemble_bounds_[thread + 1];
  const std::size_t first = lo, last = hi;
  std::uint32_t* const start[2] = {near_.start.data(), far_.start.data()};
  for (std::uint32_t* s : start)
    std::fill(s + first + 1, s + last + 1, 0u);
  std::uint32_t mine[2] = {0, 0};
  for (std::size_t f = thread; f < found_.size(); f += team)
    for (const Pair& pair : found_[f].value) {
      const std::uint32_t far = pair.upper >> 31;
      ++start[far][pair.lower + 1];
      ++mine[far];
    }
  part_pairs_[thread] = mine[0];
  part_pairs_[team + thread] = mine[1];
  teamBarrier();
  // from the entries of the threads before this one
  std::uint32_t* const next[2] = {fill_.data(), fill_.data() + n};
  for (std::size_t f = 0; f < 2; ++f) {
    const auto before = part_pairs_.begin() + std::ptrdiff_t(f * team);
    std::uint32_t at = std::accumulate(before, before + std::ptrdiff_t(thread), 0u);
    for (std::uint32_t i = lo; i < hi; ++i) {
      next[f][i] = at;
      at += start[f][i + 1];
      start[f][i + 1] = at;
    }
  }
  std::uint32_t* const owner[2] = {near_.owner.data(), far_.owner.data()};
  std::uint32_t* const partner[2] = {near_.partner.data(), far_.partner.data()};
  for (std::size_t f = thread; f < found_.size(); f += team)
    for (const Pair& pair : found_[f].value) {
      const std::uint32_t far = pair.upper >> 31, k = next[far][pair.lower]++;
      owner[far][k] = pair.lower;
      partner[far][k] = pair.upper & ~kFarBit;
    }
  teamBarrier();
}

// assembleLists' shares of the points, each with about as many of the last build's entries and points as the next:
// where a cloth folds its points have the most (CS184's selfCollision on two threads: one of even shares of the
// points took 1.5 times as long as the other). Even shares where no lists were built for as many points.
template <class T>
void CollisionPairs<T>::assembleBounds(std::size_t n) {
  assemble_bounds_.assign(assemblers_ + 1, std::uint32_t(n));
  assemble_bounds_[0] = 0;
  const bool last = near_.start.size() == n + 1 && far_.start.size() == n + 1;
  const std::uint64_t total = last ? std::uint64_t(near_.start[n]) + far_.start[n] + n : n;
  for (std::size_t d = 1; d < assemblers_; ++d) {
    const std::uint64_t target = total * d / assemblers_;
    // The first point whose entries and points before it reach the target (they only grow with it)
    std::size_t lo = 0, hi = n;
    while (last && lo < hi) {
      const std::size_t mid = lo + (hi - lo) / 2;
      if (std::uint64_t(near_.start[mid]) + far_.start[mid] + mid < target)
        lo = mid + 1;
      else
        hi = mid;
    }
    assemble_bounds_[d] =
        std::uint32_t(last ? lo : std::size_t(evenShare((long long)n, (long long)d, (long long)assemblers_)));
  }
}

// The build's anchors (the positions it was made from, and their padded copy) and the check's bounds. In a team every
// thread calls it, the copies split by points: on one thread of two, at 256^2, the other waited through it.
template <class T>
void CollisionPairs<T>::finishBuild(const std::vector<vec3>& x) {
  const std::size_t n = x.size(), size = padded_.x ? padded_.shape.size : 0;
  if (!teamSerial(failure_, [&] {
        anchor_.resize(n);
        for (PaddedFloats& a : padded_anchor_)
          a.resize(size);
        if (tiled_ != n) makeTiles(n);
        part_extent_.assign(std::size_t(teamSize()), range_ + margin_);
        stencil_min2_.resize(tile_count_ * forwardOffsets());
        if (edge_ > 0) shared_min2_.resize(std::size_t(recordRow()) * std::size_t(teamSize()));
        stencil_active_.resize(tile_count_ * std::size_t(teamSize()));
        active_rows_.assign(std::size_t(teamSize()), {0, 0});
      }))
    return;
  const auto thread = std::size_t(teamThread());
  teamPart(0, (long long)n, [&](long long lo, long long hi) {
    std::copy(x.begin() + lo, x.begin() + hi, anchor_.begin() + lo);
    part_extent_[thread] = largestCoordinate(&x[std::size_t(lo)].x, 3 * std::size_t(hi - lo), range_ + margin_);
  });
  if (size > 0)
    teamPart(0, (long long)size, [&](long long lo, long long hi) {
      const float* from[3] = {padded_.x, padded_.y, padded_.z};
      for (int c = 0; c < 3; ++c)
        std::copy(from[c] + lo, from[c] + hi, padded_anchor_[c].begin() + lo);
    });
  teamBarrier();
  if (thread == 0) {
    const T extent = *std::max_element(part_extent_.begin(), part_extent_.end());
    travel_ = safeTravel(margin_, extent + margin_);
    extent_ = extent + margin_;
    built_ = true;
    ++rebuilds_;
    entries_built_ += (long long)pairCount();
  }
  teamBarrier();  // farNeeded reads extent_ next, on every thread
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

template class CollisionPairs<float>;
template class CollisionPairs<double>;

HeldPairs heldPairsAtRest(const std::vector<glm::dvec3>& rest, double range) {
  HeldPairs out;
  if (rest.size() < 2) return out;
  HashGrid<double> grid;
  grid.build(rest, range);
  double closest2 = range * range;
  for (std::size_t i = 0; i < rest.size(); ++i)
    grid.forEachForwardCandidate(i, [&](std::uint32_t j) {
      const glm::dvec3 d = rest[i] - rest[j];
      const double d2 = glm::dot(d, d);
      if (d2 < range * range) {
        ++out.count;
        closest2 = std::min(closest2, d2);
      }
    });
  out.closest = out.count ? std::sqrt(closest2) : 0.0;
  return out;
}

}  // namespace drape
