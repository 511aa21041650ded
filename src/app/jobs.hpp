// Independent runs side by side (the accuracy and stability sweeps): each run is one job, `jobs` run at
// a time on their own threads, and each CPU solver gets its share of the cores, so a sweep of single-
// threaded runs fills the machine. Results go to the slot of their job, so a report's order does not
// depend on which run finished first.
#pragma once

#include <cstddef>
#include <functional>

namespace drape {

// Cores this process may use (at least 1).
int availableCores();

// `jobs` clamped to [1, count]; 0 means every core.
int jobsFor(int jobs, std::size_t count);

// CPU solver threads for each of `jobs` simultaneous runs: the cores shared out, at least 1.
int threadsPerJob(int jobs);

// Calls run(j) for every j in [0, count), `jobs` at a time (jobsFor). Waits for all of them; if any
// threw, rethrows the first exception once every job has finished.
void forEachJob(std::size_t count, int jobs, const std::function<void(std::size_t)>& run);

}  // namespace drape
