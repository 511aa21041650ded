// This machine's peak, measured by small probes with the grid kernels' instructions (cpu/grid_kernels.hpp):
// the ceilings of `drape bench --roofline` (app/roofline.hpp). A STREAM-style triad for memory bandwidth,
// once over arrays far larger than any cache, once over arrays a few times a core's L2 (held by an L3 where the
// machine has one large enough) and once over arrays that fit the per-core L2, and independent
// chains of vector multiplies and adds (the model's flops; no fused multiply-add, which the bits forbid) and
// of square roots and divisions (every spring takes one of each, and they are far slower than the rest).
#pragma once

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
};

// A fraction of a second per probe; the best of a few tries (others share the machine).
MachinePeak measurePeak(int threads);

}  // namespace drape
