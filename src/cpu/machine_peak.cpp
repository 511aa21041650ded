#include "cpu/machine_peak.hpp"
#include "cpu/grid_kernels.hpp"
#include "cpu/parallel.hpp"

#include <omp.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <ctime>
#include <vector>

namespace drape {

namespace {

double threadCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return double(t.tv_sec) + double(t.tv_nsec) * 1e-9;
}

// Seconds for body() run by `threads` threads at once, each on its own data (the slowest thread's time
// is the region's): the best of `tries`. One thread is timed by its CPU time, which leaves out the slices
// other processes on a shared machine take from it; a team by the wall clock (its threads must run at once).
template <class F>
double bestSeconds(int threads, int tries, F&& body) {
  double best = 1e30;
  for (int t = 0; t < tries; ++t) {
    if (threads == 1) {
      const double start = threadCpuSeconds();
      body(0);
      best = std::min(best, threadCpuSeconds() - start);
      continue;
    }
    const auto start = std::chrono::steady_clock::now();
#pragma omp parallel num_threads(threads)
    body(omp_get_thread_num());
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  return best;
}

// Triad over `floats` per array and thread, `sweeps` times: GB/s over all threads.
double triadGbs(const GridKernels& k, int threads, long long floats, int sweeps) {
  std::vector<std::vector<float>> a(std::size_t(threads), std::vector<float>(std::size_t(floats) * 3, 1.0f));
  const double s = bestSeconds(threads, 5, [&](int t) {
    float* p = a[std::size_t(t)].data();
    for (int r = 0; r < sweeps; ++r)
      k.probeTriad(p, p + floats, p + 2 * floats, floats, 0.5f);
  });
  volatile float sink = a[0][std::size_t(floats) / 2];
  (void)sink;
  return 12.0 * double(floats) * sweeps * threads / s * 1e-9;
}

// Each thread reads the clock over and over for a quarter of a second (a read takes tens of nanoseconds), counting
// the steps between two reads as gaps (GapCount).
void measureGaps(MachinePeak& peak, int threads) {
  using Clock = std::chrono::steady_clock;
  constexpr auto kLength = std::chrono::milliseconds(250);
  struct alignas(64) Count {
    GapCount gaps;
    Clock::duration length{};
  };
  std::vector<Count> counts(static_cast<std::size_t>(threads));
#pragma omp parallel num_threads(threads)
  {
    Count& mine = counts[std::size_t(omp_get_thread_num())];
    const Clock::time_point start = Clock::now();
    Clock::time_point last = start;
    while (last - start < kLength) {
      const Clock::time_point now = Clock::now();
      mine.gaps.add(now - last);
      last = now;
    }
    mine.length = last - start;
  }
  for (const Count& c : counts) {
    const double seconds = std::chrono::duration<double>(c.length).count() * threads;
    peak.gap_share += std::chrono::duration<double>(c.gaps.lost).count() / seconds;
    peak.gaps_per_second += double(c.gaps.gaps) / seconds;
    peak.long_gaps_per_second += double(c.gaps.long_gaps) / seconds;
  }
}

}  // namespace

MachinePeak measurePeak(int threads) {
  const GridKernels& k = gridKernels();
  MachinePeak peak;
  peak.isa = k.name;
  peak.threads = threads;
  peak.dram_gbs = triadGbs(k, threads, (16LL << 20) / threads / GridShape::kMaxWidth * GridShape::kMaxWidth,
                           4);                              // 64 MiB an array in all
  peak.l3_gbs = triadGbs(k, threads, 1LL << 20, 30);        // 4 MiB an array and thread
  peak.cache_gbs = triadGbs(k, threads, 16LL << 10, 2000);  // 64 KiB an array, in L2
  peak.l2_bytes = std::max(0L, sysconf(_SC_LEVEL2_CACHE_SIZE));
  peak.l3_bytes = std::max(0L, sysconf(_SC_LEVEL3_CACHE_SIZE));
  const long long reps = 4'000'000;
  std::vector<float> sink(static_cast<std::size_t>(threads), 0.0f);
  double s = bestSeconds(threads, 5, [&](int t) { sink[std::size_t(t)] = k.probeAddMul(reps); });
  peak.addmul_gflops = 12.0 * k.width * double(reps) * threads / s * 1e-9;
  const long long div_reps = 1'000'000;
  s = bestSeconds(threads, 5, [&](int t) { sink[std::size_t(t)] += k.probeDivSqrt(div_reps); });
  volatile float keep = sink[0];
  (void)keep;
  peak.divsqrt_gops = 8.0 * k.width * double(div_reps) * threads / s * 1e-9;
  measureGaps(peak, threads);
  if (threads > 1) {
    // What a pass boundary costs a team (CpuSolver::step): all threads pass the team's barrier (TeamBarrier),
    // over and over; and OpenMP's own, which the team used before, for comparison.
    constexpr int kBarriers = 2000;
    TeamBarrier barrier;
    const auto microseconds = [&](bool openmp) {
      std::vector<double> tries;
      for (int t = 0; t < 5; ++t) {
        const auto start = std::chrono::steady_clock::now();
        if (openmp) {
#pragma omp parallel num_threads(threads)
          for (int b = 0; b < kBarriers; ++b) {
#pragma omp barrier
          }
        } else {
          runOnTeam(threads, barrier, [&] {
            for (int b = 0; b < kBarriers; ++b)
              teamBarrier();
          });
        }
        tries.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count() /
                        kBarriers);
      }
      std::sort(tries.begin(), tries.end());
      return tries;
    };
    const std::vector<double> team = microseconds(false), openmp = microseconds(true);
    peak.barrier_us = team[team.size() / 2];
    peak.barrier_best_us = team.front();
    peak.omp_barrier_us = openmp[openmp.size() / 2];
  }
  return peak;
}

}  // namespace drape
