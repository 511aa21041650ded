// CollisionPairs' list build: the grid and the scan's arrays, the search for candidates (findPairs), the entries and
// the anchors. Kept apart from collision_pairs.cpp for its size.
#include "core/memory_stage.hpp"
#include "cpu/collision_pairs.hpp"
#include "cpu/parallel.hpp"

#include <omp.h>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <new>
#include <numeric>
#include <span>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

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

// PairScanArgs and GridKernels::scanPairs in T, one candidate at a time (double, or float without kernels).
template <class T>
int CollisionPairs<T>::scanSlots(const ScanArgs& a, std::uint32_t first, std::uint32_t last, std::uint32_t* out) const {
  if constexpr (std::is_same_v<T, float>)
    if (kernels_) {
      const PairScanArgs k{a.x,  a.y,  a.z,      a.u,  a.v,  a.px,         a.py,   a.pz,
                           a.pu, a.pv, a.reach2, a.a2, a.b2, a.near_below, a.near2};
      return kernels_->scanPairs(k, first, last, out);
    }
  int count = 0;
  for (std::uint32_t s = first; s < last; ++s) {
    const T dx = a.px - a.x[s], dy = a.py - a.y[s], dz = a.pz - a.z[s];
    if (!(dx * dx + dy * dy + dz * dz < a.reach2)) continue;
    const T du = a.u[s] - a.pu, dv = a.v[s] - a.pv;
    const T nominal = du * du * a.a2 + dv * dv * a.b2;
    if (nominal < a.near_below) continue;
    out[count++] = s;
  }
  return count;
}

// The list's tables in locals, for the loops that file a build's pairs (as members they were loaded again after every
// pair a vector stored, which may alias them): f(i, j, far), far kFarBit or 0
template <class T>
struct CollisionPairs<T>::Filer {
  Found* mine;                  // the finding thread's found_, assemblers() of them
  const std::uint32_t* bounds;  // assemble_bounds_
  bool one;                     // one share to assemble: every pair to mine[0]
  const std::uint16_t *u, *v;   // the columns and rows, where pairs are classed by offset (by_offset_)
  const std::uint8_t* kind;     // kind_ there, else null
  int box;
  const vec3* rest;  // without the table: the rest shape, or null
  T range;
  void operator()(std::uint32_t i, std::uint32_t j, std::uint32_t far) const;
};

template <class T>
typename CollisionPairs<T>::Filer CollisionPairs<T>::filer(Found* mine) const {
  Filer f{mine, assemble_bounds_.data(), assemblers() == 1, nullptr, nullptr, nullptr, box_, nullptr, range_};
  if (by_offset_) {
    f.u = u_.data();
    f.v = v_.data();
    f.kind = kind_.data();
  } else if (!rest_.empty()) {
    f.rest = rest_.data();
  }
  return f;
}

// Pair {i, j} of a candidate found within reach (j in a forward cell of i's) into `mine` unless the springs hold it or
// the stencil tests it, its part told by `far` (kFarBit where its squared distance is not under the near entries'
// reach: a NaN distance is near, always tested, as the scalar sum gives such a pair its terms).
// Classed by its offset, a pair is never held at rest where the table lists it or off the box: makeStencil lists an
// offset only where its nominal distance, less the slack (the rest shape's jitter and the round-off of a distance in
// T), reaches range + margin, and the box spans that reach. So heldAtRest is asked only without the table.
template <class T>
[[gnu::always_inline]] inline void CollisionPairs<T>::Filer::operator()(std::uint32_t i, std::uint32_t j,
                                                                        std::uint32_t far) const {
  const Pair pair{std::min(i, j), std::max(i, j) | far};
  const auto keep = [&] {
    std::size_t d = 0;
    if (!one)
      while (pair.lower >= bounds[d + 1])
        ++d;
    mine[d].value.push_back(pair);
  };
  if (kind) {
    const int du = int(u[j]) - int(u[i]), dv = int(v[j]) - int(v[i]);
    if (du < -box || du > box || dv < -box || dv > box) return keep();
    const int side = 2 * box + 1;
    if (kind[std::size_t((dv + box) * side + du + box)] == kList) keep();  // else held, or on the stencil
    return;
  }
  if (!rest || !physics::heldAtRest(rest[i], rest[j], range)) keep();
}

// Each pair once (half the cell lookups), into thread t's share; the lists made from them are grouped by point and
// each point's sum orders its terms, so the bytes do not depend on how the points were split between threads nor
// in what order they were found. [lo, hi): points, or on dense buckets slots of the grid's order (findPairsByCell).
template <class T>
void CollisionPairs<T>::findPairs(const std::vector<vec3>& x, int t, long long lo, long long hi) {
  const MemoryStage stage("listing the self-collision candidates of " + std::to_string(x.size()) + " points");
  if (grid_.dense() && build_order_ == BuildOrder::ByCell) return findPairsByCell(t, lo, hi);
  const Filer file = filer(&found_[std::size_t(t) * assemblers()]);  // cleared by prepareBuild
  std::vector<std::uint32_t> slots;
  ScanArgs scan = scan_;
  const std::vector<std::uint32_t>& sorted = grid_.sorted();
  for (long long p = lo; p < hi; ++p) {
    if (out_of_memory_.set.load(std::memory_order_relaxed)) return;
    const std::size_t i = std::size_t(p);
    try {
      setPoint(scan, x, i);
      grid_.forEachForwardBucket(i, [&](std::uint32_t first, std::uint32_t last, glm::ivec3 cell) {
        if (slots.size() < last - first) slots.resize(last - first);
        const int found = scanSlots(scan, first, last, slots.data());
        for (int k = 0; k < found; ++k) {
          const std::uint32_t s = slots[std::size_t(k)], j = sorted[s];
          if (grid_.inCell(j, cell)) file(std::uint32_t(i), j, farMark(x[i], s));
        }
      });
    } catch (const std::bad_alloc&) {
      out_of_memory_.set = true;
    }
  }
}

template <class T>
void CollisionPairs<T>::setPoint(ScanArgs& scan, const std::vector<vec3>& x, std::size_t i) const {
  scan.px = x[i].x;
  scan.py = x[i].y;
  scan.pz = x[i].z;
  if (by_offset_) {
    scan.pu = T(u_[i]);
    scan.pv = T(v_[i]);
  }
}

// scanCell's test in T (double, or float without kernels): scanSlots for each point at slots [p0, p1) against each
// range.
template <class T>
int CollisionPairs<T>::scanCellSlots(const ScanArgs& a, std::uint32_t p0, std::uint32_t p1, const CellRange* ranges,
                                     int count_of, std::uint32_t* points, std::uint32_t* slots) const {
  if constexpr (std::is_same_v<T, float>)
    if (kernels_) {
      const PairScanArgs k{a.x, a.y, a.z, a.u, a.v, 0, 0, 0, 0, 0, a.reach2, a.a2, a.b2, a.near_below, a.near2};
      return kernels_->scanCell(k, p0, p1, ranges, count_of, points, slots);
    }
  int count = 0;
  for (const CellRange& range : std::span(ranges, std::size_t(count_of)))
    for (std::uint32_t p = p0; p < p1; ++p) {
      ScanArgs at = a;
      at.px = a.x[p];
      at.py = a.y[p];
      at.pz = a.z[p];
      at.pu = a.u[p];
      at.pv = a.v[p];
      const std::uint32_t from = range.own ? std::max(range.first, p + 1) : range.first;
      if (from >= range.last) continue;
      const int found = scanSlots(at, from, range.last, slots + count);
      std::fill(points + count, points + count + found, p);
      for (std::uint32_t& s : std::span(slots + count, std::size_t(found)))
        s |= farMark(vec3(at.px, at.py, at.pz), s);
      count += found;
    }
  return count;
}

// Slots [lo, hi) of the grid's order, a cell's points at a time: each of the cell's forward ranges (its own row
// first, from the cell itself) is scanned once for all of them, the ranges in one call (scanCell). A cell holds a
// few points (2.7 on selfCollision): copying its ranges into one run for each point to scan whole, as the build once
// did, cost twice the scans themselves. The scan tells each pair's part (kFarSlot), from the distance it tested.
template <class T>
void CollisionPairs<T>::findPairsByCell(int t, long long lo, long long hi) {
  const Filer file = filer(&found_[std::size_t(t) * assemblers()]);
  std::vector<std::uint32_t>& found = cell_found_[std::size_t(t)];
  const std::vector<std::uint32_t>& sorted = grid_.sorted();
  try {
    for (long long s = lo; s < hi;) {
      if (out_of_memory_.set.load(std::memory_order_relaxed)) return;
      const std::uint32_t at = sorted[std::size_t(s)];
      const glm::ivec3 cell = grid_.cellOfPoint(at);
      // the cell's points in this share: slots [s, e), to the end of its bucket (dense: a bucket is a cell)
      const long long e = std::min(hi, (long long)grid_.bucketEnd(at));
      const auto p0 = std::uint32_t(s), p1 = std::uint32_t(e);
      CellRange ranges[kCellRanges];
      int count_of = 0;
      std::size_t most = 0;
      grid_.forEachForwardRange(cell, [&](std::uint32_t first, std::uint32_t last, bool own) {
        if (own) first = p0 + 1;  // the own row from the slot after the first point
        if (first >= last) return;
        ranges[count_of++] = {first, last, own};
        most += std::size_t(p1 - p0) * (last - first);
      });
      // The points' slots, then the candidates', each with room for the vectors stored past the last pair
      const std::size_t room = most + kPairScanPad;
      if (found.size() < 2 * room) found.resize(2 * room);
      std::uint32_t *const points = found.data(), *const slots = found.data() + room;
      const int pairs = count_of > 0 ? scanCellSlots(scan_, p0, p1, ranges, count_of, points, slots) : 0;
      for (int k = 0; k < pairs; ++k)
        file(sorted[points[k]], sorted[slots[k] & ~kFarBit], slots[k] & kFarBit);
      s = e;
    }
  } catch (const std::bad_alloc&) {
    out_of_memory_.set = true;
  }
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
        scan_ = ScanArgs{.x = sx_.data(),
                         .y = sy_.data(),
                         .z = sz_.data(),
                         .u = su_.data(),
                         .v = sv_.data(),
                         .reach2 = reach * reach,
                         .near_below = T(-1),
                         .near2 = near_reach_ * near_reach_};
        if (by_offset_) {
          scan_.a2 = a2_;
          scan_.b2 = b2_;
          scan_.near_below = near_below_;
        }
        assembleBounds(n, std::size_t(teamSize()));
        // Every thread's pairs go, not only those of the threads this build runs on: a build on one thread after
        // one on a team would list the team's other pairs again.
        found_.resize(std::size_t(std::max(threads, 1)) * assemblers());
        cell_found_.resize(std::size_t(std::max(threads, 1)));
        for (Found& part : found_)
          part.value.clear();
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
// points (assemble_bounds_: every finding thread filed them apart for it), counts them, and after a barrier places
// them from the entries of the threads before it. A point's partners are in the order the pairs were found, whichever
// threads place them. Filtering every thread's pairs, as each thread did, kept a team of two 1.2 times as long in it
// as one thread on selfCollision; one thread doing it all while the others waited, 0.19 ms a build at 256^2. Listing
// every pair and then parting them by a second look at each one's distance (finishBuild, before) made CS184's
// selfCollision 1.02 times as long on one thread.
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

template void CollisionPairs<float>::build(const std::vector<vec3>&, int);
template void CollisionPairs<float>::prepareBuild(const std::vector<vec3>&, int);
template void CollisionPairs<float>::sizeLists(std::size_t);
template void CollisionPairs<float>::assembleLists(std::size_t);
template void CollisionPairs<float>::finishBuild(const std::vector<vec3>&);
template int CollisionPairs<float>::scanSlots(const ScanArgs&, std::uint32_t, std::uint32_t, std::uint32_t*) const;
template void CollisionPairs<float>::findPairs(const std::vector<vec3>&, int, long long, long long);
template void CollisionPairs<float>::setPoint(ScanArgs&, const std::vector<vec3>&, std::size_t) const;
template void CollisionPairs<float>::findPairsByCell(int, long long, long long);
template int CollisionPairs<float>::scanCellSlots(const ScanArgs&, std::uint32_t, std::uint32_t, const CellRange*, int,
                                                  std::uint32_t*, std::uint32_t*) const;
template void CollisionPairs<double>::build(const std::vector<vec3>&, int);
template void CollisionPairs<double>::prepareBuild(const std::vector<vec3>&, int);
template void CollisionPairs<double>::sizeLists(std::size_t);
template void CollisionPairs<double>::assembleLists(std::size_t);
template void CollisionPairs<double>::finishBuild(const std::vector<vec3>&);
template int CollisionPairs<double>::scanSlots(const ScanArgs&, std::uint32_t, std::uint32_t, std::uint32_t*) const;
template void CollisionPairs<double>::findPairs(const std::vector<vec3>&, int, long long, long long);
template void CollisionPairs<double>::setPoint(ScanArgs&, const std::vector<vec3>&, std::size_t) const;
template void CollisionPairs<double>::findPairsByCell(int, long long, long long);
template int CollisionPairs<double>::scanCellSlots(const ScanArgs&, std::uint32_t, std::uint32_t, const CellRange*, int,
                                                   std::uint32_t*, std::uint32_t*) const;

}  // namespace drape
