#include "cpu/parallel.hpp"

#include <omp.h>

#include <climits>
#ifdef __linux__
#include <linux/futex.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <ctime>
#else
#include <chrono>
#include <thread>
#endif

namespace drape {

TeamScope::TeamScope(TeamBarrier& barrier, WaitLog* waits) : previous_(current_team) {
  const auto threads = unsigned(omp_get_num_threads());
  // More threads than processors: a waiting thread soon gives its processor up (libgomp's own spin count falls
  // from 300,000 to 1,000 there), as the thread it waits for may need it.
  const unsigned spins = threads <= unsigned(omp_get_num_procs()) ? 20000 : 200;
  current_team = {&barrier, threads, unsigned(omp_get_thread_num()), spins, waits};
}

// A sleeper's timeout: long against a thread's wait for a descheduled one's time slice (it is woken then), short
// against a run, where a wake-up missed (TeamCount::publish) costs no more than this.
constexpr long kSleepNanoseconds = 100'000;

void sleepOn(std::atomic<std::uint32_t>& word, std::uint32_t seen) {
#ifdef __linux__
  static_assert(sizeof(std::atomic<std::uint32_t>) == sizeof(std::uint32_t));
  const timespec timeout{0, kSleepNanoseconds};
  syscall(SYS_futex, reinterpret_cast<std::uint32_t*>(&word), FUTEX_WAIT_PRIVATE, seen, &timeout, nullptr, 0);
#else
  (void)word;
  (void)seen;
  std::this_thread::sleep_for(std::chrono::nanoseconds(kSleepNanoseconds));
#endif
}

void wakeAll(std::atomic<std::uint32_t>& word) {
#ifdef __linux__
  syscall(SYS_futex, reinterpret_cast<std::uint32_t*>(&word), FUTEX_WAKE_PRIVATE, INT_MAX, nullptr, nullptr, 0);
#else
  (void)word;
#endif
}

void runOnTeam(int threads, TeamBarrier& barrier, const std::function<void()>& body) {
  runOnTeam(threads, barrier, nullptr, body);
}

void runOnTeam(int threads, TeamBarrier& barrier, WaitLog* waits, const std::function<void()>& body) {
  barrier.prepare(unsigned(threads));
  if (waits) waits->prepare(unsigned(threads));
#pragma omp parallel num_threads(threads)
  {
    const TeamScope scope(barrier, waits);
    body();
  }
}

void runOnTeam(int threads, const std::function<void()>& body) {
  TeamBarrier barrier;
  runOnTeam(threads, barrier, body);
}

}  // namespace drape
