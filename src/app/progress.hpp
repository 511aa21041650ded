// Progress of long runs: `simulate` on a terminal (one line updated in place) and `accuracy` (a count
// and an estimate of the time left on each finished run's line).
#pragma once

#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

namespace drape {

// "1 s", "42 s", "3 min 05 s", "2 h 07 min": whole seconds, the two largest units.
std::string formatDuration(double seconds);

// "12/48, 40 s, about 2 min 40 s left" after `done` of `total` equal parts in `elapsed_s`. The estimate
// assumes the parts left take as long as those done; it is left out before the first part is done and
// once the last is.
std::string progressText(long long done, long long total, double elapsed_s);

// The same count with an estimate for runs of unequal cost, in lanes that run one after another (the
// accuracy sweep's CPU runs side by side, then its GPU runs one at a time): each lane's pace (seconds per
// unit of cost) is measured from its finished runs; a lane none of whose runs has finished yet is taken at
// the pace of the lane before it times `prior_slowdown`. Not thread-safe: the callers hold their lock.
class SweepEstimate {
 public:
  using Clock = std::chrono::steady_clock;
  // cost[r] in any unit (substeps x points, say); lane[r] (empty: every run in lane 0).
  SweepEstimate(std::vector<double> cost, std::vector<int> lane = {}, double prior_slowdown = 1.0,
                Clock::time_point start = Clock::now());

  // Run r finished now: "12/48, 40 s, about 2 min 40 s left".
  std::string finished(std::size_t run, Clock::time_point now = Clock::now());
  double secondsLeft(Clock::time_point now) const;

 private:
  struct Lane {
    double cost_done = 0, cost_left = 0;
    Clock::time_point start{}, last_finish{};
    bool started = false;
  };
  std::vector<double> cost_;
  std::vector<int> lane_;
  std::vector<Lane> lanes_;
  double prior_slowdown_;
  Clock::time_point start_;
  long long done_ = 0;
};

// One line on `stream`, rewritten in place with '\r' and ended with a newline by finish(). Shown only
// when `enabled` (the callers pass whether stderr is a terminal: a log or a pipe gets no progress noise)
// and only once the run has taken a second, so that a short run prints nothing; redrawn at most ten
// times a second.
class TerminalProgress {
 public:
  TerminalProgress(std::string label, long long total, bool enabled, std::FILE* stream = stderr);
  ~TerminalProgress() { finish(); }
  TerminalProgress(const TerminalProgress&) = delete;
  TerminalProgress& operator=(const TerminalProgress&) = delete;

  void update(long long done);
  // Ends a shown line with a newline, so that what follows starts on its own line; then shows nothing more.
  void finish();

 private:
  using Clock = std::chrono::steady_clock;
  std::string label_;
  long long total_;
  bool enabled_;
  std::FILE* stream_;
  Clock::time_point start_ = Clock::now();
  Clock::time_point last_draw_{};
  bool shown_ = false;
  std::size_t width_ = 0;  // of the longest line drawn, so a shorter one covers it
};

}  // namespace drape
