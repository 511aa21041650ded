#include "app/progress.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <utility>

namespace drape {

std::string formatDuration(double seconds) {
  const long long s = std::llround(std::max(seconds, 0.0));
  if (s < 60) return fmt::format("{} s", s);
  if (s < 3600) return fmt::format("{} min {:02d} s", s / 60, s % 60);
  return fmt::format("{} h {:02d} min", s / 3600, s % 3600 / 60);
}

std::string progressText(long long done, long long total, double elapsed_s) {
  std::string text = fmt::format("{}/{}, {}", done, total, formatDuration(elapsed_s));
  if (done > 0 && done < total)
    text += fmt::format(", about {} left", formatDuration(elapsed_s / double(done) * double(total - done)));
  return text;
}

SweepEstimate::SweepEstimate(std::vector<double> cost, std::vector<int> lane, double prior_slowdown,
                             Clock::time_point start)
    : cost_(std::move(cost)), lane_(std::move(lane)), prior_slowdown_(prior_slowdown), start_(start) {
  lane_.resize(cost_.size(), 0);
  for (std::size_t r = 0; r < cost_.size(); ++r) {
    if (std::size_t(lane_[r]) >= lanes_.size()) lanes_.resize(std::size_t(lane_[r]) + 1);
    lanes_[std::size_t(lane_[r])].cost_left += cost_[r];
  }
  if (!lanes_.empty()) {
    lanes_.front().start = start;
    lanes_.front().started = true;
  }
}

std::string SweepEstimate::finished(std::size_t run, Clock::time_point now) {
  Lane& lane = lanes_[std::size_t(lane_[run])];
  if (!lane.started) {
    // A later lane starts when the one before it has finished.
    const std::size_t l = std::size_t(lane_[run]);
    lane.start = l > 0 && lanes_[l - 1].cost_left <= 0 ? lanes_[l - 1].last_finish : start_;
    lane.started = true;
  }
  lane.cost_done += cost_[run];
  lane.cost_left -= cost_[run];
  lane.last_finish = now;
  ++done_;
  const long long total = (long long)cost_.size();
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  std::string text = fmt::format("{}/{}, {}", done_, total, formatDuration(elapsed));
  if (done_ < total) text += fmt::format(", about {} left", formatDuration(secondsLeft(now)));
  return text;
}

double SweepEstimate::secondsLeft(Clock::time_point now) const {
  double left = 0, pace = 0;  // seconds per unit of cost, of the last lane that has one
  for (const Lane& lane : lanes_) {
    if (lane.cost_done > 0) {
      // A lane still running has been running until now; a finished one until its last run ended.
      const Clock::time_point until = lane.cost_left > 0 ? now : lane.last_finish;
      pace = std::chrono::duration<double>(until - lane.start).count() / lane.cost_done;
    } else {
      pace *= prior_slowdown_;
    }
    left += lane.cost_left * pace;
  }
  return std::max(left, 0.0);
}

TerminalProgress::TerminalProgress(std::string label, long long total, bool enabled, std::FILE* stream)
    : label_(std::move(label)), total_(total), enabled_(enabled), stream_(stream) {}

void TerminalProgress::update(long long done) {
  if (!enabled_) return;
  const Clock::time_point now = Clock::now();
  if (now - start_ < std::chrono::seconds(1)) return;
  if (shown_ && now - last_draw_ < std::chrono::milliseconds(100) && done < total_) return;
  last_draw_ = now;
  shown_ = true;
  std::string line = label_ + " " + progressText(done, total_, std::chrono::duration<double>(now - start_).count());
  width_ = std::max(width_, line.size());
  line.resize(width_, ' ');
  fmt::print(stream_, "\r{}", line);
  std::fflush(stream_);
}

void TerminalProgress::finish() {
  if (shown_) {
    fmt::print(stream_, "\n");
    std::fflush(stream_);
  }
  enabled_ = false;
  shown_ = false;
}

}  // namespace drape
