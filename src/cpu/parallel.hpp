// Loops split between OpenMP threads (the CPU solver is compiled with -fopenmp; elsewhere, such as in
// tests, parallelFor is a plain loop).
#pragma once

namespace drape {

// OpenMP team for a loop of `items` iterations: one thread below kParallelItems, where forking and the
// closing barrier cost more than the loop saves. A 50x50 cloth's loops take 10-50 us each, a dozen per
// substep; measured on the 2-core development machine under load, 2 threads on them ran 3.4x slower
// than one (threads spin at every barrier while their partner is descheduled). From 32768 items a
// loop is worth a few hundred microseconds, and the threads pay.
inline constexpr long long kParallelItems = 32768;
inline int teamFor(int threads, long long items) {
  return items >= kParallelItems ? threads : 1;
}

// body(k) for k in [first, last), split between `threads` OpenMP threads when the loop is long enough
// (teamFor). Short loops run as a plain loop: an OpenMP region, even of one thread, compiles the body
// into an outlined function that reloads every member it touches, which measured 30% slower.
template <class F>
void parallelFor(long long first, long long last, int threads, F&& body) {
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

}  // namespace drape
