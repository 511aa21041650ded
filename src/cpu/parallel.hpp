// Loops split between OpenMP threads (the CPU solver is compiled with -fopenmp; elsewhere, such as in
// tests, these are plain loops).
//
// Two ways to run a loop on several threads. Inside a team (CpuSolver::step opens one OpenMP parallel region
// for a whole substep and every thread runs every pass), a loop is split between the team's threads and
// ends with a barrier: no fork, and the threads wait for each other only where a pass needs the previous
// one's results. Outside a team (a test running one pass, the list build), a long loop forks a team of its
// own and a short one runs as a plain loop.
#pragma once

#include "cpu/wait_log.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <exception>
#include <functional>
#include <memory>
#include <source_location>
#include <span>
#include <thread>

namespace drape {

// Sleeping on a count (TeamCount): until `word` no longer holds `seen`, a wake-up (wakeAll) or a short timeout,
// whichever comes first (parallel.cpp: a futex on Linux). The timeout is what makes a missed wake-up cost a moment, not
// a hang.
void sleepOn(std::atomic<std::uint32_t>& word, std::uint32_t seen);
void wakeAll(std::atomic<std::uint32_t>& word);

// A count one thread of a team publishes and the others wait for: a barrier's arrivals (TeamBarrier), a thread's
// finished steps (TeamProgress). On a line of its own, as its owner writes it and the others spin reading it. The
// owner's store is a release and nothing more, so that a publish costs the store: a sequentially consistent one (a
// fence, which waits for every store the pass before left in the core's buffer) before the look for sleepers made
// the last thread of a barrier take 520-1340 cycles in it here, against 150 for a line to cross between the cores
// (docs/results/cpu_speed.md). Without the fence the owner may look for sleepers before its store is seen and miss
// one that counted itself just then: that one wakes at its timeout (sleepOn) instead, a thing of a hundred
// microseconds that a spinning waiter never meets.
struct alignas(64) TeamCount {
  std::atomic<std::uint32_t> count{0};
  std::atomic<std::uint32_t> sleepers{0};  // written only by a thread about to sleep on count

  static constexpr int kYields = 12;
  static bool reached(std::uint32_t seen, std::uint32_t target) { return std::int32_t(seen - target) >= 0; }
  // The owner: the count is now `value`; everything it wrote before is seen by a thread that awaits it
  void publish(std::uint32_t value) {
    count.store(value, std::memory_order_release);
    if (sleepers.load(std::memory_order_relaxed) != 0) wakeAll(count);
  }
  // Until the count has reached `target` (counts wrap: compared by their difference); spins `spins` times, yields,
  // then sleeps. Returns the count it saw.
  std::uint32_t await(std::uint32_t target, unsigned spins) {
    for (unsigned s = 0; s < spins; ++s) {
      if (const std::uint32_t c = count.load(std::memory_order_acquire); reached(c, target)) return c;
#if defined(__x86_64__) || defined(__i386__)
      __builtin_ia32_pause();
#endif
    }
    // Then gives its processor to another thread a few times before sleeping: where a team has more threads than
    // processors, the one it waits for is often on this processor's queue, and a yield runs it at once, where a sleep
    // waits for a wake-up (CS184's selfCollision on a forced team of three threads on two cores: 0.12 s against 0.59
    // with sleeps alone, 30 frames)
    for (int y = 0; y < kYields; ++y) {
      if (const std::uint32_t c = count.load(std::memory_order_acquire); reached(c, target)) return c;
      std::this_thread::yield();
    }
    sleepers.fetch_add(1, std::memory_order_seq_cst);
    std::uint32_t c;
    while (!reached(c = count.load(std::memory_order_seq_cst), target))
      sleepOn(count, c);
    sleepers.fetch_sub(1, std::memory_order_relaxed);
    return c;
  }
};

// Each thread's count of the steps it has finished, for steps that need only some threads' earlier steps done
// rather than every thread's (a barrier): a thread publishes each step it ends and, before a step, awaits the
// counts of the threads whose rows it shares (GridPath's colours: a thread's neighbours). The counts wrap: they
// are compared by their difference.
class TeamProgress {
 public:
  TeamProgress() = default;
  // A copy is new (a solver is copied between substeps, when no thread uses it)
  TeamProgress(const TeamProgress&) {}
  TeamProgress& operator=(const TeamProgress&) { return *this; }

  // Outside concurrent use: a count for each of `threads` threads, all 0
  void resize(unsigned threads) {
    slots_ = std::make_unique<TeamCount[]>(threads);
    size_ = threads;
  }
  unsigned size() const { return size_; }
  std::uint32_t count(unsigned thread) const { return slots_[thread].count.load(std::memory_order_relaxed); }
  // Thread `thread`'s count is now `count`: everything it wrote before is seen by a thread that awaits it
  void publish(unsigned thread, std::uint32_t count) { slots_[thread].publish(count); }
  static bool reached(std::uint32_t seen, std::uint32_t count) { return TeamCount::reached(seen, count); }
  // Until thread `other` has published `count` or more; returns the count it saw (`count` or more)
  std::uint32_t await(unsigned other, std::uint32_t count, unsigned spins) { return slots_[other].await(count, spins); }

 private:
  std::unique_ptr<TeamCount[]> slots_;
  unsigned size_ = 0;
};

// The barrier of a team (CpuSolver::step's region, runOnTeam's): each thread publishes its arrivals in a count of its
// own and awaits every other's, spinning, then sleeping (TeamCount). A shared count of arrivals, which the last
// thread moved on, made every barrier three transfers of a line between the cores one after another (the count, the
// generation, the look for sleepers behind a fence): a barrier between two passes cost each of two threads 520-810
// cycles of latency, where this costs about one transfer. libgomp's `omp barrier` makes a futex_wake system call at
// every barrier (strace: 200,005 futex calls for 200,000 barriers of two threads), and a 50 x 50 substep on a team
// passes about a dozen (docs/design.md, Threads).
class TeamBarrier {
 public:
  // Outside concurrent use (runOnTeam, before its region): a team of `threads`, every count 0. (A copy is a new
  // barrier, as its counts are new: a solver is copied between substeps, when no thread waits on it.)
  void prepare(unsigned threads) { arrivals_.resize(threads); }
  // Every thread of the team calls it, `thread` its number (below prepare's count), with the same `threads`.
  void wait(unsigned threads, unsigned thread, unsigned spins) {
    // Only this thread writes its count: a thread can be one barrier ahead of another, never two
    const std::uint32_t next = arrivals_.count(thread) + 1;
    arrivals_.publish(thread, next);
    for (unsigned t = 0; t < threads; ++t)
      if (t != thread) arrivals_.await(t, next, spins);
  }

 private:
  TeamProgress arrivals_;  // each thread's barriers passed
};

// The team the calling thread is in while a TeamScope lives (barrier null outside one): its barrier, size and
// this thread's number. Set by the scope from OpenMP inside the region, so that code compiled without OpenMP
// (the tests) passes the same barriers as the solver's.
struct TeamContext {
  TeamBarrier* barrier = nullptr;
  unsigned threads = 1, thread = 0, spins = 0;
  WaitLog* waits = nullptr;  // where given, every wait below is timed into it
};
inline thread_local TeamContext current_team;

// Inside a parallel region, on every thread: the region's loops split and wait on `barrier` (teamBarrier,
// teamSingle) until the scope ends. No parallel region may open inside it: its threads would take this team's
// context (the solver opens none inside its team; the list build's own region is for calls outside one).
class TeamScope {
 public:
  // parallel.cpp: reads the region's size and the thread's number
  explicit TeamScope(TeamBarrier& barrier, WaitLog* waits = nullptr);
  ~TeamScope() { current_team = previous_; }
  TeamScope(const TeamScope&) = delete;
  TeamScope& operator=(const TeamScope&) = delete;

 private:
  TeamContext previous_;
};

// OpenMP team for a loop of `items` iterations outside a team: one thread below kParallelItems, where
// forking and the closing barrier cost more than the loop saves. A 50x50 cloth's loops take 10-50 us each,
// a dozen per substep; measured on the 2-core development machine under load, 2 threads on them ran 3.4x
// slower than one (a fork per loop, threads spinning at every barrier while their partner is descheduled).
// From 32768 items a loop is worth a few hundred microseconds, and the threads pay.
inline constexpr long long kParallelItems = 32768;
inline int teamFor(int threads, long long items) {
  return items >= kParallelItems ? threads : 1;
}

// Whether the caller is one of several threads of a team (an active parallel region).
inline bool inTeam() {
  if (current_team.barrier) return current_team.threads > 1;
#ifdef _OPENMP
  return omp_in_parallel() != 0;
#else
  return false;
#endif
}

// This thread's number in its team and the team's size (0 and 1 outside a team).
inline int teamThread() {
  if (current_team.barrier) return int(current_team.thread);
#ifdef _OPENMP
  if (inTeam()) return omp_get_thread_num();
#endif
  return 0;
}
inline int teamSize() {
  if (current_team.barrier) return int(current_team.threads);
#ifdef _OPENMP
  if (inTeam()) return omp_get_num_threads();
#endif
  return 1;
}

// Where share t of `count` even shares of [0, n) starts: share t is [evenShare(n, t, count), evenShare(n, t + 1,
// count)). The one split of every pass that divides points or rows evenly (teamShare, CpuSolver::pointShare,
// GridPath's colour rows), so that a thread's share of one is its share of the next.
inline long long evenShare(long long n, long long t, long long count) {
  return n * t / count;
}

// This thread's share [lo, hi) of [first, last) in a team (contiguous, by thread number: the same split
// every time), or all of it outside one.
inline void teamShare(long long first, long long last, long long& lo, long long& hi) {
  lo = first;
  hi = last;
  if (!inTeam()) return;
  const long long n = last - first, t = teamThread(), count = teamSize();
  lo = first + evenShare(n, t, count);
  hi = first + evenShare(n, t + 1, count);
}

// wait() in a team that keeps a WaitLog: timed, and filed under the line that called the wait (`where`)
template <class F>
void loggedWait(const std::source_location& where, F&& wait) {
  const TeamContext& team = current_team;
  if (!team.waits) {
    wait();
    return;
  }
  const auto start = std::chrono::steady_clock::now();
  wait();
  team.waits->add(team.thread, where, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
}

// The team waits for all its threads (nothing outside a team): its TeamBarrier, or an OpenMP barrier in a region
// with no TeamScope. `where`, and that of the waits below: the caller's line, which a WaitLog files the wait under.
inline void teamBarrier(std::source_location where = std::source_location::current()) {
  if (const TeamContext& team = current_team; team.barrier) {
    if (team.threads > 1) loggedWait(where, [&] { team.barrier->wait(team.threads, team.thread, team.spins); });
    return;
  }
#ifdef _OPENMP
  if (inTeam()) {
#pragma omp barrier
  }
#endif
}

// Until thread `other` of this thread's team has published `count` (TeamProgress), spinning as its barrier does.
// `seen`: a count this thread saw it publish before (it only grows), which spares reading its line again while
// that is enough: a neighbour a step ahead is awaited at every other step only, not at every one.
inline void teamAwait(TeamProgress& progress, int other, std::uint32_t count, std::uint32_t& seen,
                      std::source_location where = std::source_location::current()) {
  if (TeamProgress::reached(seen, count)) return;
  loggedWait(where,
             [&] { seen = progress.await(unsigned(other), count, current_team.barrier ? current_team.spins : 20000); });
}

// body(lo, hi) on this thread's share of [first, last), with no barrier: for a loop whose next reader reads only
// what its own thread wrote here.
template <class F>
void teamPart(long long first, long long last, F&& body) {
  long long lo, hi;
  teamShare(first, last, lo, hi);
  if (lo < hi) body(lo, hi);
}

// body(lo, hi) on this thread's share of [first, last), then a barrier: inside a team each thread calls it.
template <class F>
void teamRange(long long first, long long last, F&& body,
               std::source_location where = std::source_location::current()) {
  teamPart(first, last, body);
  teamBarrier(where);
}

// Contiguous shares of [0, n) moved towards equal times, where the work is not spread evenly (self-collision's
// pairs crowd where a cloth folds): bounds (T + 1 of them, bounds[0] = 0, bounds[T] = n) gives thread t items
// [bounds[t], bounds[t + 1]); it took seconds[t] for them. per_point[t], the thread's seconds an item smoothed
// over calls (`smoothing` the weight of this one; negative for none yet), takes that in, and the shares become
// inversely proportional to it, each at least `least` items (its rate stays measured, and a burst of noise on
// one core cannot take all of its items).
inline void balanceShares(std::span<long long> bounds, std::span<const double> seconds, std::span<double> per_point,
                          double smoothing, long long least) {
  const std::size_t team = seconds.size();
  const long long n = bounds[team];
  double speed_sum = 0;
  for (std::size_t t = 0; t < team; ++t) {
    const double mine = seconds[t] / double(std::max(bounds[t + 1] - bounds[t], 1LL));
    per_point[t] = per_point[t] < 0 ? mine : per_point[t] + smoothing * (mine - per_point[t]);
    speed_sum += 1 / std::max(per_point[t], 1e-12);
  }
  long long at = 0;
  for (std::size_t t = 0; t + 1 < team; ++t) {
    const auto share = (long long)(double(n) / std::max(per_point[t], 1e-12) / speed_sum);
    at = std::clamp(at + share, at + least, n - (long long)(team - t - 1) * least);
    bounds[t + 1] = at;
  }
}

// body(k) for k in [first, last). In a team, this thread's share, then a barrier. Outside, split between
// `threads` OpenMP threads when the loop is long enough (teamFor); short loops run as a plain loop: an
// OpenMP region, even of one thread, compiles the body into an outlined function that reloads every member
// it touches, which measured 30% slower.
template <class F>
void parallelFor(long long first, long long last, int threads, F&& body,
                 std::source_location where = std::source_location::current()) {
  if (inTeam()) {
    teamRange(
        first, last,
        [&](long long lo, long long hi) {
          for (long long k = lo; k < hi; ++k)
            body(k);
        },
        where);
    return;
  }
  if (teamFor(threads, last - first) == 1) {
    for (long long k = first; k < last; ++k)
      body(k);
    return;
  }
#ifdef _OPENMP
#pragma omp parallel for schedule(static) num_threads(threads)
#endif
  for (long long k = first; k < last; ++k)
    body(k);
}

// Serial work inside a pass (resizing a buffer, building a list): one thread of a team does it while the
// others wait; outside a team, the caller. An exception must not leave an OpenMP region, so it is kept and
// rethrown by `rethrow` once the region is over (CpuSolver::step).
template <class F>
void teamSingle(F&& body, std::source_location where = std::source_location::current()) {
  if (!inTeam()) {
    body();
    return;
  }
  if (current_team.barrier) {  // thread 0, where `omp single` takes whichever comes first
    if (current_team.thread == 0) body();
    teamBarrier(where);
    return;
  }
#ifdef _OPENMP
#pragma omp single
  body();
#endif
}

// body() on every thread of a new OpenMP team of `threads` waiting on `barrier` (CpuSolver::step runs a substep's
// passes so). Compiled in parallel.cpp with OpenMP, so that tests compiled without it run a real team too. The
// second form times the team's waits into `waits` (where not null: prepared for `threads` rows); the third gives
// the team a barrier of its own.
void runOnTeam(int threads, TeamBarrier& barrier, const std::function<void()>& body);
void runOnTeam(int threads, TeamBarrier& barrier, WaitLog* waits, const std::function<void()>& body);
void runOnTeam(int threads, const std::function<void()>& body);

// teamSingle for a step that may throw (an allocation) among steps that every thread of a team runs: in a team the
// exception is kept in `failure`, shared by the team, and every thread reads the answer after the step's barrier, so
// all take the same way; outside a team it is thrown. Returns whether no step has failed.
template <class F>
bool teamSerial(std::exception_ptr& failure, F&& body, std::source_location where = std::source_location::current()) {
  if (!inTeam()) {
    body();
    return true;
  }
  teamSingle(
      [&] {
        try {
          body();
        } catch (...) {
          failure = std::current_exception();
        }
      },
      where);
  return !failure;
}

}  // namespace drape
