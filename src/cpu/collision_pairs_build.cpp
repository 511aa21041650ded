// CollisionPairs' list build: the grid and the scan's arrays, the entries and the anchors; the search for candidates
// is in collision_pairs_search.cpp. Kept apart from collision_pairs.cpp for its size.
#include "core/memory_stage.hpp"
#include "cpu/collision_pairs.hpp"
#include "cpu/parallel.hpp"

#include <omp.h>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <stdexcept>
#include <type_traits>
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
        by_offset_ = box_ >= 0 && uv_.size() == n;
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
        cell_points_.resize(std::size_t(std::max(threads, 1)));
        cell_slots_.resize(cell_points_.size());
        for (Found& part : found_)
          part.value.clear();
        // Even at first; one thread (the trial's probe) leaves the team's where they were
        if (const auto team = std::size_t(teamSize());
            team > 1 && (search_bounds_.size() != team + 1 || search_bounds_.back() != (long long)n)) {
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
    su_[s] = by_offset_ ? T(columnOf(uv_[j])) : T(0);
    sv_[s] = by_offset_ ? T(rowOf(uv_[j])) : T(0);
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
template void CollisionPairs<double>::build(const std::vector<vec3>&, int);
template void CollisionPairs<double>::prepareBuild(const std::vector<vec3>&, int);
template void CollisionPairs<double>::sizeLists(std::size_t);
template void CollisionPairs<double>::assembleLists(std::size_t);
template void CollisionPairs<double>::finishBuild(const std::vector<vec3>&);

}  // namespace drape
