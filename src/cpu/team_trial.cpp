// TeamTrial's room on this machine: how busy its processors are, from /proc/stat and the load average.
#include "cpu/team_trial.hpp"

#include <omp.h>
#include <sched.h>
#include <time.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace drape {

namespace {

std::optional<ProcessorTicks> readProcessorTicks() {
  std::ifstream in("/proc/stat");
  std::string name;
  long long field[8] = {};  // user nice system idle iowait irq softirq steal
  in >> name;
  for (long long& f : field)
    in >> f;
  if (!in || name != "cpu") return std::nullopt;
  ProcessorTicks t;
  for (const long long f : field)
    t.total += f;
  t.idle = field[3] + field[4];
  return t;
}

// The processors' idle time since `last` (the time this run has been running on one thread, or since the last
// answer), or, until a few ticks have passed (20 ms on two processors), what the 1-minute load average and the tasks
// runnable now say, either of them enough. The load average also counts processes that ended a moment ago: run after
// another run (a benchmark's rounds, a build), CS184's selfCollision kept one thread for its first 300-400 substeps
// of 2700 while it stayed above 1.5, until the ticks had passed. The tasks runnable now count a shell or a process
// that is about to end: alone they kept a team from more runs than the load average did. A team probed on busy
// cores waits a time slice at each barrier.
bool roomForTeam(int team, ProcessorTicks& last) {
  const int processors = omp_get_num_procs();
  if (const std::optional<ProcessorTicks> now = readProcessorTicks()) {
    const double idle = last.total > 0 ? idleProcessors(last, *now, processors, 2LL * processors)
                                       : std::numeric_limits<double>::quiet_NaN();
    if (last.total == 0 || !std::isnan(idle)) last = *now;
    if (!std::isnan(idle)) return idle >= double(team - 1) - 0.5;
  }
  double load = 0;
  if (getloadavg(&load, 1) != 1 || load + double(team - 1) <= double(processors) + 0.5) return true;
  std::ifstream in("/proc/loadavg");
  std::string text;
  std::getline(in, text);
  const int runnable = runnableTasks(text);
  return runnable >= 1 && roomAmongRunnable(runnable, processors, team);
}

}  // namespace

int runnableTasks(const std::string& loadavg) {
  std::istringstream in(loadavg);
  double averages[3];
  int runnable = -1, all = -1;
  char slash = 0;
  if (!(in >> averages[0] >> averages[1] >> averages[2] >> runnable >> slash >> all) || slash != '/' || runnable < 1 ||
      all < runnable)
    return -1;
  return runnable;
}

bool spreadTeam(int team) {
  cpu_set_t allowed;
  CPU_ZERO(&allowed);
  if (team < 2 || sched_getaffinity(0, sizeof allowed, &allowed) != 0) return false;
  std::vector<int> processors;
  for (int c = 0; c < CPU_SETSIZE; ++c)
    if (CPU_ISSET(c, &allowed)) processors.push_back(c);
  if ((int)processors.size() < team) return false;
  std::atomic<int> moved{0}, done{0};
#pragma omp parallel num_threads(team)
  {
    const int t = omp_get_thread_num();
    cpu_set_t one;
    CPU_ZERO(&one);
    CPU_SET(processors[std::size_t(t)], &one);
    // Setting the mask moves the thread at once; the whole mask back leaves it there until the scheduler
    // has a reason to move it.
    if (sched_setaffinity(0, sizeof one, &one) == 0) moved.fetch_add(1);
    sched_setaffinity(0, sizeof allowed, &allowed);
    done.fetch_add(1);
    // Yield rather than spin until the others have been here: one of them may be queued behind this thread.
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(50);
    while (done.load() < omp_get_num_threads() && std::chrono::steady_clock::now() < deadline)
      sched_yield();
  }
  return moved.load() == team;
}

std::function<double()> missedProcessorTime(int team) {
  const auto processorSeconds = [] {
    timespec t{};
    return clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t) == 0 ? double(t.tv_sec) + 1e-9 * double(t.tv_nsec) : 0.0;
  };
  using Clock = std::chrono::steady_clock;
  return [team, processorSeconds, wall = Clock::now(), processor = processorSeconds()] {
    return double(team) * std::chrono::duration<double>(Clock::now() - wall).count() - (processorSeconds() - processor);
  };
}

std::function<bool()> machineRoom(int team) {
  return [team, last = readProcessorTicks().value_or(ProcessorTicks{})]() mutable { return roomForTeam(team, last); };
}

}  // namespace drape
