#include "cpu/parallel.hpp"

#include <omp.h>

namespace drape {

TeamScope::TeamScope(TeamBarrier& barrier) : previous_(current_team) {
  const auto threads = unsigned(omp_get_num_threads());
  // More threads than processors: a waiting thread soon gives its processor up (libgomp's own spin count falls
  // from 300,000 to 1,000 there), as the thread it waits for may need it.
  const unsigned spins = threads <= unsigned(omp_get_num_procs()) ? 20000 : 200;
  current_team = {&barrier, threads, unsigned(omp_get_thread_num()), spins};
}

void runOnTeam(int threads, TeamBarrier& barrier, const std::function<void()>& body) {
#pragma omp parallel num_threads(threads)
  {
    const TeamScope scope(barrier);
    body();
  }
}

void runOnTeam(int threads, const std::function<void()>& body) {
  TeamBarrier barrier;
  runOnTeam(threads, barrier, body);
}

}  // namespace drape
