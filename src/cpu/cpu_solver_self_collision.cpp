// CpuSolver's self-collision (selfCollide): the candidate lists and the grid stencil of
// cpu/collision_pairs.hpp, then CS184's averaged push between points closer than 2 x thickness, as a Jacobi
// pass. Kept apart from cpu_solver.cpp for its size.
#include "cpu/cpu_solver.hpp"
#include "cpu/parallel.hpp"

#include <algorithm>
#include <chrono>
#include <exception>
#include <span>
#include <type_traits>
#include <utility>

namespace drape {

template <class T>
void CpuSolver<T>::selfCollide() {
  positionsMoved();
  const T thickness = T(scene_.cloth.thickness);
  const T range = T(2) * thickness;
  // The skin is a share of the contact distance, or of two spacings where the cloth is finer than half of it
  // (derived::pairSkin). On a grid the stencil tests the ring of unheld pairs within range + skin at rest every
  // substep (40 offsets at 256^2 with CS184's thickness), so the skin sets both its width and how long the
  // lists last. The bytes do not depend on it.
  // Every thread of a team shares the list check and the build; an exception (out of memory) is kept for
  // step() to rethrow after the region.
  // On a grid path the check and the stencil read the positions from its padded arrays, loaded once here.
  bool padded = false;
  if constexpr (std::is_same_v<T, float>)
    if (grid_) {
      if (!grid_integrate_) grid_->loadPositions(x_);  // else integrate left them there
      padded = true;
    }
  // In a team whose check is split, each thread boxes the displacements of its rows first (the check's first
  // test, CollisionPairs::startCheck): rows it wrote itself, and no barrier more.
  if constexpr (std::is_same_v<T, float>)
    if (padded && inTeam()) {
      long long y0, y1;
      teamShare(0, topo_.H, y0, y1);
      pairs_.boxDisplacements(teamThread(), substeps_, grid_->shape(), grid_->positions(0), grid_->positions(1),
                              grid_->positions(2), int(y0), int(y1));
    }
  teamSingle([&] {
    try {
      // A switch of skin is a build (configure): narrow once a list has lasted kSettledSubsteps, wide again when
      // a narrow one lasted under kBusySubsteps.
      if (adaptive_skin_ && wide_skin_ && list_built_at_ >= 0 && substeps_ - list_built_at_ >= kSettledSubsteps) {
        wide_skin_ = false;
        ++skin_switches_;
      } else if (adaptive_skin_ && !wide_skin_ && last_list_life_ >= 0 && last_list_life_ < kBusySubsteps) {
        wide_skin_ = true;
        ++skin_switches_;
      }
      const double margin = wide_skin_ ? pair_margin_ : pair_margin_ * (2.0 / 3.0);
      pairs_.configure(range, derived::pairSkin(margin, range, shortest_spring_));
      if (!padded) near_.resize(x_.size());  // a grid path lists the stencil's pairs instead
      first_term_.resize(x_.size(), -1);
      const int team = teamSize();
      // A scratch given up (the trial's one thread after a team) takes the corrections its points kept with it, and
      // keeps its arrays for the team's return (grown again from nothing, they were reallocated over its first
      // substeps)
      for (std::size_t t = std::size_t(team); t < pair_scratch_.size(); ++t)
        clearSelfCorrections(pair_scratch_[t]);
      if (pair_scratch_.size() < std::size_t(team)) pair_scratch_.resize(std::size_t(team));
      pair_team_ = team;
      for (PairScratch& scratch : teamScratch()) {
        if (scratch.to.size() < std::size_t(team)) scratch.to.resize(std::size_t(team));
        scratch.sent.assign(std::size_t(team), 0);
        scratch.failure = nullptr;  // a failed substep's, rethrown by step()
      }
      // Each thread's shares of the pairs: every other pass's at first (pointShare). One thread (the trial's probe)
      // leaves the team's where they were: reset to even, they started over after each probe (selfCollision's
      // search shares had followed the times to 28/72%, and move half the way a build, a build in 12 substeps).
      const long long n = (long long)x_.size();
      if (team > 1 && (pair_bounds_.size() != std::size_t(team) + 1 || pair_bounds_.back() != n)) {
        pair_shares_fixed_ = false;
        pair_bounds_.resize(std::size_t(team) + 1);
        for (int t = 0; t < team; ++t)
          pointShare(t, team, pair_bounds_[std::size_t(t)], pair_bounds_[std::size_t(t) + 1]);
        find_bounds_ = built_find_bounds_ = pair_bounds_;
        pair_per_point_.clear();
      }
      if (team > 1 && pair_per_point_.size() != std::size_t(team)) {
        for (std::vector<double>* seconds : {&pair_seconds_, &find_seconds_})
          seconds->assign(std::size_t(team), 0);
        for (std::vector<double>* per_point : {&pair_per_point_, &find_per_point_, &built_find_per_point_})
          per_point->assign(std::size_t(team), -1);
      }
      if constexpr (std::is_same_v<T, float>)
        if (padded)
          pairs_.setPaddedPositions(&grid_->shape(), grid_->positions(0), grid_->positions(1), grid_->positions(2));
      pairs_.startCheck(x_, padded ? substeps_ : -1);
    } catch (...) {
      failure_ = std::current_exception();
    }
  });
  if (failure_) return;
  const bool built = pairs_.finishCheck(x_);
  if (built) {
    try {
      pairs_.build(x_, threads_);
    } catch (...) {  // outside a team
      failure_ = std::current_exception();
    }
    teamSingle([&] {
      if (std::exception_ptr e = pairs_.takeFailure()) failure_ = e;
      last_list_life_ = list_built_at_ >= 0 ? substeps_ - list_built_at_ : -1;
      list_built_at_ = substeps_;
    });
    if (failure_) return;
  }
  // Jacobi: every correction is computed from the positions before the pass, so the result does not
  // depend on the order points are visited (nor, on the GPU, on thread order). Each pair in range is found
  // once, from its lower end, with both ends' terms, each sent to the thread that owns its point; then each
  // point sums its terms in the order of forEachOrderedPair (the 27-cell query's, docs/design.md section 2),
  // whichever thread found them. Each thread takes a contiguous share of the points to find and one to sum, at
  // first the one every other pass gives it: the positions, the terms' heads and the corrections then stay in the
  // cache of the core that writes them (dealing chunks of points in turn instead measured slower on 50 x 50: every
  // line of them moved between the cores each substep). The shares then follow the work (balancePairShares): a
  // refined cloth's contacts crowd where it wrinkles, and at 256 x 256 even shares left one thread most of them.
  const std::size_t stencil = pairs_.stencil().size();
  const T inv_range = T(1) / range;
  const T steps = T(scene_.sim.steps_per_frame);
  const int thread = teamThread();
  PairScratch& mine = pair_scratch_[std::size_t(thread)];
  const bool team = inTeam();
  using Clock = std::chrono::steady_clock;
  const auto start = team ? Clock::now() : Clock::time_point();
  const long long n = (long long)x_.size();
  const std::vector<long long>& find_bounds = built ? built_find_bounds_ : find_bounds_;
  long long lo = team ? find_bounds[std::size_t(thread)] : 0, hi = team ? find_bounds[std::size_t(thread) + 1] : n;
  mine.stencil_pairs = 0;
  bool shared_record = false;
  long long shared_from = -1;  // the next thread's first row of points, where a record is shared with it
  if (stencil > 0) {
    if constexpr (std::is_same_v<T, float>)
      if (padded) {
        // The stencil's pairs of this thread's rows, listed for the same thread to find their terms: no barrier
        // between, and no flag words a point to write, scan and clear (pinned2 at 256 x 256 on two threads: the
        // stencil and the search 0.71-0.74 s of each thread's run with them and their wait, 0.51 s without).
        // Whole rows of points. At a record two threads may share a row of squares, the later recording it apart for
        // the earlier to merge, where every thread's rows span a square's edge (else whole rows of squares): at 256 x
        // 256 rounding the shares to rows of 16 left one thread 0.15 ms a build waiting for the other.
        GridStencilTiles tiles;
        const bool ruled_out = pairs_.stencilTiles(built, tiles), record = ruled_out && tiles.record;
        const long long w = pairs_.gridWidth();
        // The last bound stays the last point: a grid's last row of squares may be short of rows
        const auto whole = [&](long long bound, long long unit) {
          return bound >= n ? n : std::min(n, (bound + unit / 2) / unit * unit);
        };
        shared_record = record && team;
        for (std::size_t t = 0; shared_record && t + 1 < find_bounds.size(); ++t)
          shared_record = whole(find_bounds[t + 1], w) - whole(find_bounds[t], w) >= w * tiles.edge;
        const long long unit = w * (record && !shared_record ? tiles.edge : 1);
        lo = whole(lo, unit);
        hi = whole(hi, unit);
        if (shared_record && std::size_t(thread) + 2 < find_bounds.size())
          shared_from = whole(find_bounds[thread + 1], w) / w;
        mine.stencil_pairs = grid_->stencilPairs(pairs_.stencilDu(), pairs_.stencilDv(), pairs_.stencilMixed(),
                                                 int(stencil), range * range, int(lo / w), int(hi / w), mine.lower,
                                                 mine.upper, ruled_out ? &tiles : nullptr);
      }
    if (!padded)
      parallelFor(0, n, threads_, [&](long long p) { near_[std::size_t(p)] = pairs_.stencilMask(x_, std::size_t(p)); });
  }
  // The corrections this thread's last pass kept are zeroed before any thread writes this pass's (the barrier)
  clearSelfCorrections(mine);
  findPairHits(lo, hi, stencil > 0 && !padded, thickness, inv_range, pairs_.farNeeded(built), mine);
  const auto found = team ? Clock::now() : Clock::time_point();
  teamBarrier();
  if (shared_from >= 0) pairs_.mergeSharedRecord(thread + 1, shared_from);
  // A thread's sums are its own points' corrections, computed from terms alone: it adds them at once, as no
  // thread reads another's points until the barrier.
  const auto summing = team ? Clock::now() : Clock::time_point();
  mine.summed = sumPairTerms(thread, steps, mine);
  if (team) {
    find_seconds_[std::size_t(thread)] = std::chrono::duration<double>(found - start).count();
    pair_seconds_[std::size_t(thread)] = std::chrono::duration<double>(Clock::now() - summing).count();
  }
  teamBarrier();
  // Every thread reads the same flags after the barrier, so all take the same way (and pass the same barriers).
  const std::span<PairScratch> scratches = teamScratch();
  if (std::any_of(scratches.begin(), scratches.end(), [](const PairScratch& s) { return bool(s.failure); })) {
    teamSingle([&] {
      for (PairScratch& s : scratches)
        if (s.failure && !failure_) failure_ = s.failure;
    });
    return;
  }
  // No thread reads these again before the next substep's first teamSingle: one thread takes them, no barrier.
  if (thread == 0) {
    for (const PairScratch& s : scratches)
      pair_terms_ += s.summed;  // pairs in range, counted from both ends for `drape simulate -v`
    pairs_.setPaddedPositions(nullptr, nullptr, nullptr, nullptr);  // they change before the next substep's
    if (team) balancePairShares(built);
  }
}

// The team's shares of the pairs towards equal times (balanceShares), unless a test fixed them. Which thread
// sums a point's terms does not change them (each point orders its own): the bytes do not depend on the shares.
template <class T>
void CpuSolver<T>::balancePairShares(bool built) {
  constexpr double kSmoothing = 0.25;  // a substep's weight in the smoothed times
  if (pair_shares_fixed_) return;
  const long long least = std::max(1LL, pair_bounds_.back() / (16 * (long long)pair_seconds_.size()));
  balanceShares(pair_bounds_, pair_seconds_, pair_per_point_, kSmoothing, least);
  if (built)
    balanceShares(built_find_bounds_, find_seconds_, built_find_per_point_, kSmoothing, least);
  else
    balanceShares(find_bounds_, find_seconds_, find_per_point_, kSmoothing, least);
}

template <class T>
void CpuSolver<T>::fixPairShares(std::vector<long long> sums, std::vector<long long> find) {
  pair_bounds_ = std::move(sums);
  find_bounds_ = built_find_bounds_ = find.empty() ? pair_bounds_ : std::move(find);
  pair_shares_fixed_ = true;
}

// The pairs in range of points [lo, hi) with a partner above them: the lists' forward pairs (their entries
// tested side by side where the kernels run) and the stencil's, listed (mine.lower and upper: GridPath::stencilPairs)
// or, where flagged, the forward offsets whose bits near_ has. Each end's term goes into mine.to[the thread that
// sums it]; a zero term, or one for a pinned point, adds nothing and is dropped.
template <class T>
void CpuSolver<T>::findPairHits(long long lo, long long hi, bool flagged, T thickness, T inv_range, bool far,
                                PairScratch& mine) {
  try {
    // Either end may be in another thread's share of the sums. A term of this thread's own share is linked to its
    // point's at once (linkTerm), as sumPairTerms links the others' after the barrier: no copy of it in between.
    const bool alone = pair_team_ == 1;
    const std::size_t self = std::size_t(&mine - pair_scratch_.data());
    const auto send = [&](std::size_t to, std::uint32_t i, std::uint32_t j, int order, vec3 c) {
      if (c == vec3(0) || topo_.pinned[i]) return;
      if (to == self) {
        if (mine.linked == mine.terms.size()) {  // only grown: no reallocation check a term
          mine.terms.resize(2 * mine.linked + 64);
          if (mine.touched.size() < mine.terms.size()) mine.touched.resize(mine.terms.size());
        }
        linkTerm(mine, i, j, order, c);
        return;
      }
      std::vector<FoundTerm>& terms = mine.to[to];
      std::size_t& sent = mine.sent[to];
      if (sent == terms.size()) terms.resize(2 * sent + 64);  // only grown: no reallocation check a term
      terms[sent++] = {i, j, order, c};
    };
    const auto both = [&](std::uint32_t i, std::uint32_t j, int order_i, int order_j, vec3 ci, vec3 cj) {
      send(alone ? 0 : std::size_t(pairOwner(i)), i, j, order_i, ci);
      send(alone ? 0 : std::size_t(pairOwner(j)), j, i, order_j, cj);
    };
    const auto pair = [&](std::uint32_t i, std::uint32_t j) {
      vec3 ci, cj;
      if (!physics::selfCollisionCorrections(x_[i], x_[j], thickness, ci, cj)) return;
      if (ci == vec3(0) && cj == vec3(0)) return;
      const glm::ivec3 cell_i = HashGrid<T>::cellOf(x_[i], inv_range), cell_j = HashGrid<T>::cellOf(x_[j], inv_range);
      const int order_i = cellOrder(cell_i, cell_j);
      if (order_i < 0) return;
      both(i, j, order_i, cellOrder(cell_j, cell_i), ci, cj);
    };
    if constexpr (std::is_same_v<T, float>)
      if (kernels_) {
        // Both ends' terms and cells side by side, the list's entries and then the stencil's pairs in range
        const auto take = [&](const std::uint32_t* a, const std::uint32_t* b, std::uint32_t from, std::uint32_t to) {
          // Grown, never shrunk: a resize from the stencil's few to the list's many would zero them every substep
          if (mine.hits.size() < to - from) mine.hits.resize(to - from);
          const int found =
              kernels_->pairTerms(&x_.data()->x, x_.size(), a, b, from, to, thickness, inv_range, mine.hits.data());
          for (int s = 0; s < found; ++s) {
            const PairTermOut& h = mine.hits[std::size_t(s)];
            const std::uint32_t i = a[h.k], j = b[h.k];
            if (h.order_i == -2) {  // a NaN distance: the scalar code's two calls
              pair(i, j);
              continue;
            }
            const vec3 ci(h.ci[0], h.ci[1], h.ci[2]), cj(h.cj[0], h.cj[1], h.cj[2]);
            if ((ci == vec3(0) && cj == vec3(0)) || h.order_i < 0) continue;
            both(i, j, h.order_i, h.order_j, ci, cj);
          }
        };
        // The list's near entries, and its far ones only where some may be in range (CollisionPairs::farNeeded):
        // for most of a list's life half its entries need no test
        for (const auto* part : {&pairs_.nearEntries(), far ? &pairs_.farEntries() : nullptr})
          if (part)
            take(part->owner.data(), part->partner.data(), part->start[std::size_t(lo)], part->start[std::size_t(hi)]);
        if (flagged) {
          mine.lower.clear();
          mine.upper.clear();
          // Most points have no stencil partner in range: they are passed over in a loop of their own, which
          // keeps its index in a register, eight flags (a cache line) at a time where all eight are clear
          const StencilMask* near = near_.data();
          const auto next = [near, hi](long long q) {
            for (; q + 8 <= hi; q += 8)
              if ((near[q] | near[q + 1] | near[q + 2] | near[q + 3] | near[q + 4] | near[q + 5] | near[q + 6] |
                   near[q + 7]) != 0)
                break;
            while (q < hi && near[q] == 0)
              ++q;
            return q;
          };
          for (long long p = next(lo); p < hi; p = next(p + 1)) {
            const std::size_t i = std::size_t(p);
            pairs_.forEachForwardPartner(i, near[i], [&](std::uint32_t j) {
              mine.lower.push_back(std::uint32_t(i));
              mine.upper.push_back(j);
            });
          }
          mine.stencil_pairs = mine.lower.size();
        }
        if (mine.stencil_pairs > 0) take(mine.lower.data(), mine.upper.data(), 0, std::uint32_t(mine.stencil_pairs));
        return;
      }
    for (const auto* part : {&pairs_.nearEntries(), &pairs_.farEntries()})
      for (std::uint32_t k = part->start[std::size_t(lo)]; k < part->start[std::size_t(hi)]; ++k)
        pair(part->owner[k], part->partner[k]);
    for (std::size_t k = 0; k < mine.stencil_pairs; ++k)
      pair(mine.lower[k], mine.upper[k]);
    if (flagged)
      for (long long p = lo; p < hi; ++p) {
        const std::size_t i = std::size_t(p);
        if (near_[i] != 0)
          pairs_.forEachForwardPartner(i, near_[i], [&](std::uint32_t j) { pair(std::uint32_t(i), j); });
      }
  } catch (...) {  // out of memory: kept, as an exception may not leave the team
    mine.failure = std::current_exception();
  }
}

template <class T>
void CpuSolver<T>::clearSelfCorrections(PairScratch& scratch) {
  if (!self_correction_.empty())
    for (const std::uint32_t i : std::span(scratch.touched.data(), scratch.points))
      self_correction_[i] = vec3(0);
  scratch.points = 0;
  scratch.linked = 0;
}

// The points of thread `thread`'s share (pair_bounds_): each one's terms, sent by every thread, summed in ascending
// (cell order, partner), and the point moved by their average at once (displace, into self_correction_ too); returns
// how many terms were summed. Only the points with terms are visited: adding a zero to every other point, as the
// pass once did, cost more than its sums on a cloth with few contacts (the sum x + 0 only turns a -0 into +0,
// which the GPU's pass no longer does either).

template <class T>
long long CpuSolver<T>::sumPairTerms(int thread, T steps, PairScratch& mine) {
  long long summed = 0;
  if (mine.failure) {  // its search failed: none of its points moves (step() rethrows)
    unlinkTerms(mine);
    return 0;
  }
  try {
    // The other threads' terms for this share, linked after the ones this thread found itself (findPairHits).
    // Linked by point without a branch on whether the point is new (half the terms are, unpredictably): the
    // arrays are sized for every term first, and only grown.
    std::size_t total = mine.linked;
    for (const PairScratch& part : teamScratch())
      total += part.sent[std::size_t(thread)];
    if (mine.terms.size() < total) mine.terms.resize(total);
    if (mine.touched.size() < total) mine.touched.resize(total);
    // Reserved here, so that nothing below can throw: a failure leaves every point of the share where it was.
    if (mine.chain.capacity() < total) mine.chain.reserve(total);
    for (const PairScratch& part : teamScratch())
      for (const FoundTerm& f : std::span(part.to[std::size_t(thread)].data(), part.sent[std::size_t(thread)]))
        linkTerm(mine, f.i, f.j, f.order, f.c);
    PairTerm* const terms = mine.terms.data();
    const std::uint32_t* const touched = mine.touched.data();
    const std::size_t points = mine.points;
    std::vector<std::int32_t>& chain = mine.chain;
    constexpr std::uint64_t kNoTerm = ~std::uint64_t(0);
    // A term in a slot: for float the three coordinates in one vector, added lane by lane (the same bits as three
    // additions). Each term is added to +0 first, as the sum starts from +0: a -0 becomes +0, so that four terms of
    // -0 sum to +0 as they do from +0 (x + 0 and x + -0 are x for every other x, so nothing else changes).
    using Slot = std::conditional_t<std::is_same_v<T, float>, float __attribute__((vector_size(16))), vec3>;
    const auto slot = [](vec3 c) {
      if constexpr (std::is_same_v<T, float>)
        return Slot{c.x, c.y, c.z, 0.0f} + Slot{};
      else
        return vec3(0) + c;
    };
    const auto unslot = [](Slot s) {
      if constexpr (std::is_same_v<T, float>)
        return vec3(s[0], s[1], s[2]);
      else
        return s;
    };
    // A compare-exchange of two slots by their terms' keys (termKey), with selects
    const auto order = [](std::uint64_t& ka, int& a, std::uint64_t& kb, int& b) {
      const bool swap = kb < ka;
      const std::uint64_t lo = swap ? kb : ka, hi = swap ? ka : kb;
      const int first = swap ? b : a, second = swap ? a : b;
      ka = lo, kb = hi, a = first, b = second;
    };
    for (const std::uint32_t i : std::span(touched, points)) {
      const std::int32_t head = first_term_[i];
      first_term_[i] = -1;
      Slot sum{};
      // Up to four terms side by side, each slot without one keyed past every term and holding +0: the slots sorted
      // by key with selects (no branch on how many there are, or on which came first) and summed whole give the
      // bits of the point's own terms summed in order, as a sum of terms is never -0 and x + 0 = x for every other x.
      // The branches they replace were mispredicted at most points (pinned2 at 256^2: 29% of the points with terms
      // have one, 43% two, 12% three, 10% four).
      std::uint64_t key[4] = {kNoTerm, kNoTerm, kNoTerm, kNoTerm};
      Slot term[4] = {};
      int count = 0;
      std::int32_t t = head;
      for (; t >= 0 && count < 4; t = terms[t].next, ++count) {
        key[count] = terms[t].key;
        term[count] = slot(terms[t].c);
      }
      if (t < 0) {
        int s0 = 0, s1 = 1, s2 = 2, s3 = 3;
        order(key[0], s0, key[1], s1);
        order(key[2], s2, key[3], s3);
        order(key[0], s0, key[2], s2);
        order(key[1], s1, key[3], s3);
        order(key[1], s1, key[2], s2);
        sum = ((term[s0] + term[s1]) + term[s2]) + term[s3];
      } else {
        chain.clear();
        for (t = head; t >= 0; t = terms[t].next) {
          // Insertion by (order, partner): a deep fold, a point has a few terms.
          const std::uint64_t k_t = terms[t].key;
          std::size_t k = chain.size();
          chain.push_back(t);
          for (; k > 0 && k_t < terms[chain[k - 1]].key; --k)
            chain[k] = chain[k - 1];
          chain[k] = t;
        }
        for (const std::int32_t k : chain)
          sum += slot(terms[k].c);
        count = int(chain.size());
      }
      const vec3 c = unslot(sum / (T(count) * steps));
      if (!self_correction_.empty()) self_correction_[i] = c;
      displace(i, c);
      summed += count;
    }
  } catch (...) {
    mine.failure = std::current_exception();
    unlinkTerms(mine);
  }
  return summed;
}

template void CpuSolver<float>::selfCollide();
template void CpuSolver<double>::selfCollide();
template void CpuSolver<float>::balancePairShares(bool);
template void CpuSolver<double>::balancePairShares(bool);
template void CpuSolver<float>::clearSelfCorrections(PairScratch&);
template void CpuSolver<double>::clearSelfCorrections(PairScratch&);
template void CpuSolver<float>::fixPairShares(std::vector<long long>, std::vector<long long>);
template void CpuSolver<double>::fixPairShares(std::vector<long long>, std::vector<long long>);
template void CpuSolver<float>::findPairHits(long long, long long, bool, float, float, bool, PairScratch&);
template void CpuSolver<double>::findPairHits(long long, long long, bool, double, double, bool, PairScratch&);
template long long CpuSolver<float>::sumPairTerms(int, float, PairScratch&);
template long long CpuSolver<double>::sumPairTerms(int, double, PairScratch&);

}  // namespace drape
