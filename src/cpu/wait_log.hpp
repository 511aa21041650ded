// Where the threads of a team waited for each other, and for how long: each barrier and progress wait of
// cpu/parallel.hpp, timed by the thread that waits and filed under the line that called it (CpuSolverOptions::
// record_waits, `drape simulate --waits`). A team's time that is neither its work nor these waits is the work done
// more slowly on a team (lines moved between the cores, what a thread recomputes of its neighbour's rows):
// docs/results/cpu_speed.md measures both.
#pragma once

#include <array>
#include <source_location>
#include <string>
#include <vector>

namespace drape {

class WaitLog {
 public:
  // A line's waits on each thread of the team: count[t] waits took seconds[t] on thread t
  struct Site {
    std::string file;  // from the source tree's src/ on, where the path has one
    unsigned line = 0;
    std::vector<long long> count;
    std::vector<double> seconds;
  };

  // Before a team of `threads` runs (runOnTeam): a row for each thread, what was logged kept
  void prepare(unsigned threads);
  // On thread `thread` only (each thread writes its own row): a wait of `seconds` called from `where`
  void add(unsigned thread, const std::source_location& where, double seconds);
  // Every line a team waited at, the longest waits (summed over the threads) first
  std::vector<Site> sites() const;
  unsigned threads() const { return unsigned(rows_.size()); }
  // Each thread's waits in all, in seconds
  std::vector<double> totals() const;
  // Each thread's waits by length, whatever their line: under 1 us, about a crossing of the waited-for count's line
  // between cores (the sync itself); 1-20 us, one thread's share of the work before it took longer; 20 us or more, a
  // thread that did not run for a while (the host, another job) or a long uneven share
  static constexpr std::array<double, 2> kLengthBounds = {1e-6, 20e-6};
  struct Lengths {
    std::array<long long, 3> count{};
    std::array<double, 3> seconds{};
  };
  std::vector<Lengths> lengths() const;
  void clear() { rows_.clear(); }

 private:
  struct Entry {
    const char* file;  // source_location's: static storage
    unsigned line;
    long long count;
    double seconds;
  };
  struct alignas(64) Row {  // a line of its own per thread: the threads write them at once
    std::vector<Entry> entries;
    Lengths lengths;
  };
  std::vector<Row> rows_;
};

}  // namespace drape
