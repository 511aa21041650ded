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
