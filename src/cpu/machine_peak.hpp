// This machine's peak, measured by small probes with the grid kernels' instructions (cpu/grid_kernels.hpp):
// the ceilings of `drape bench --roofline` (app/roofline.hpp). A STREAM-style triad for memory bandwidth,
// once over arrays far larger than any cache, once over arrays a few times a core's L2 (held by an L3 where the
// machine has one large enough) and once over arrays that fit the per-core L2, and independent
// chains of vector multiplies and adds (the model's flops; no fused multiply-add, which the bits forbid) and
// of square roots and divisions (every spring takes one of each, and they are far slower than the rest); and the
// time the machine takes from a thread that runs (gaps between reads of the clock).
#pragma once

#include <chrono>
#include <string>

namespace drape {

struct MachinePeak {
  std::string isa;       // the grid kernels' instruction set the probes ran with
  int threads = 1;       // threads that ran each probe at once
  double dram_gbs = 0;   // triad over 3 x 64 MiB, all threads
  double l3_gbs = 0;     // triad over 3 x 4 MiB per thread (past L2; in L3 where it holds them)
  double cache_gbs = 0;  // triad over 3 x 64 KiB per thread (in its L2)
  // The caches the system reports (sysconf; 0 where it does not say), which decide where a cloth's state lives
  long long l2_bytes = 0, l3_bytes = 0;
  double addmul_gflops = 0;
  double divsqrt_gops = 0;
  // One barrier of a team of `threads` threads (0 for one thread; cpu/parallel.hpp's TeamBarrier, what the solver's
  // team passes): the median of 5 tries of 2000, and the best. On a shared machine the two differ by orders of
  // magnitude: a thread whose partner is descheduled waits a slice. And the median of an OpenMP barrier's tries.
  double barrier_us = 0, barrier_best_us = 0, omp_barrier_us = 0;
  // Time the machine takes from a thread that runs (measureGaps): the share of the wall clock lost in steps of 1 µs
  // or more between two reads of the clock, and how many such gaps a second, and of 16 µs or more; the mean over
  // the threads, which ran at once. A virtual machine's host takes it without the guest seeing it (no steal time, and
  // thirty times as many gaps as the guest's interrupts here). A team loses every thread's: a stall of one holds the
  // others at its next barrier.
  double gap_share = 0, gaps_per_second = 0, long_gaps_per_second = 0;
};

// The steps between successive reads of a clock, counted as a thread's gaps (measurePeak's time taken): a step of
// 1 µs or more is time the thread did not run, one of 16 µs or more a long gap.
struct GapCount {
  static constexpr std::chrono::nanoseconds kGap{1000}, kLongGap{16000};
  std::chrono::nanoseconds lost{0};
  long long gaps = 0, long_gaps = 0;
  void add(std::chrono::nanoseconds step) {
    if (step < kGap) return;
    lost += step;
    ++gaps;
    long_gaps += step >= kLongGap;
  }
};

// A fraction of a second per probe; the best of a few tries (others share the machine).
MachinePeak measurePeak(int threads);

}  // namespace drape
