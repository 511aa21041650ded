#include "app/jobs.hpp"

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace drape {

int availableCores() {
  return std::max(1, int(std::thread::hardware_concurrency()));
}

int jobsFor(int jobs, std::size_t count) {
  const int wanted = jobs > 0 ? jobs : availableCores();
  return int(std::max<std::size_t>(1, std::min<std::size_t>(std::size_t(wanted), count)));
}

int threadsPerJob(int jobs) {
  return std::max(1, availableCores() / std::max(1, jobs));
}

void forEachJob(std::size_t count, int jobs, const std::function<void(std::size_t)>& run) {
  const int threads = jobsFor(jobs, count);
  if (threads == 1) {
    for (std::size_t j = 0; j < count; ++j)
      run(j);
    return;
  }
  std::atomic<std::size_t> next{0};
  std::mutex failure_mutex;
  std::exception_ptr failure;
  auto worker = [&] {
    for (std::size_t j; (j = next++) < count;) {
      try {
        run(j);
      } catch (...) {
        std::lock_guard<std::mutex> lock(failure_mutex);
        if (!failure) failure = std::current_exception();
      }
    }
  };
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t)
    pool.emplace_back(worker);
  for (std::thread& t : pool)
    t.join();
  if (failure) std::rethrow_exception(failure);
}

}  // namespace drape
