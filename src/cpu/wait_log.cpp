#include "cpu/wait_log.hpp"

#include <algorithm>
#include <cstring>
#include <numeric>

namespace drape {

void WaitLog::prepare(unsigned threads) {
  if (rows_.size() < threads) rows_.resize(threads);
}

void WaitLog::add(unsigned thread, const std::source_location& where, double seconds) {
  if (thread >= rows_.size()) return;  // a team larger than prepared for: not logged rather than a race on the rows
  Lengths& lengths = rows_[thread].lengths;
  const std::size_t length = seconds < kLengthBounds[0] ? 0 : seconds < kLengthBounds[1] ? 1 : 2;
  ++lengths.count[length];
  lengths.seconds[length] += seconds;
  std::vector<Entry>& entries = rows_[thread].entries;
  // A few dozen lines at most: a search, and the file names compared only where the lines agree
  for (Entry& e : entries)
    if (e.line == where.line() && (e.file == where.file_name() || std::strcmp(e.file, where.file_name()) == 0)) {
      ++e.count;
      e.seconds += seconds;
      return;
    }
  entries.push_back({where.file_name(), where.line(), 1, seconds});
}

std::vector<WaitLog::Site> WaitLog::sites() const {
  const std::size_t threads = rows_.size();
  std::vector<Site> out;
  for (std::size_t t = 0; t < threads; ++t)
    for (const Entry& e : rows_[t].entries) {
      std::string file = e.file;
      if (const std::size_t src = file.rfind("/src/"); src != std::string::npos) file = file.substr(src + 5);
      auto site =
          std::find_if(out.begin(), out.end(), [&](const Site& s) { return s.line == e.line && s.file == file; });
      if (site == out.end()) {
        out.push_back({file, e.line, std::vector<long long>(threads, 0), std::vector<double>(threads, 0.0)});
        site = out.end() - 1;
      }
      site->count[t] += e.count;
      site->seconds[t] += e.seconds;
    }
  const auto total = [](const Site& s) { return std::accumulate(s.seconds.begin(), s.seconds.end(), 0.0); };
  std::stable_sort(out.begin(), out.end(), [&](const Site& a, const Site& b) { return total(a) > total(b); });
  return out;
}

std::vector<WaitLog::Lengths> WaitLog::lengths() const {
  std::vector<Lengths> out;
  for (const Row& row : rows_)
    out.push_back(row.lengths);
  return out;
}

std::vector<double> WaitLog::totals() const {
  std::vector<double> out;
  for (const Row& row : rows_)
    out.push_back(std::accumulate(row.lengths.seconds.begin(), row.lengths.seconds.end(), 0.0));
  return out;
}

}  // namespace drape
