// The progress lines of `simulate` (on a terminal) and `accuracy`.
#include "app/progress.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <thread>

namespace drape {
namespace {

TEST(Progress, DurationsInTheTwoLargestUnits) {
  EXPECT_EQ(formatDuration(0.0), "0 s");
  EXPECT_EQ(formatDuration(0.4), "0 s");
  EXPECT_EQ(formatDuration(41.6), "42 s");
  EXPECT_EQ(formatDuration(59.4), "59 s");
  EXPECT_EQ(formatDuration(60.0), "1 min 00 s");
  EXPECT_EQ(formatDuration(185.0), "3 min 05 s");
  EXPECT_EQ(formatDuration(3600.0), "1 h 00 min");
  EXPECT_EQ(formatDuration(7620.0), "2 h 07 min");
  EXPECT_EQ(formatDuration(-3.0), "0 s");
}

TEST(Progress, TheEstimateIsTheMeanTimeOfAPartDoneTimesThePartsLeft) {
  EXPECT_EQ(progressText(12, 48, 40.0), "12/48, 40 s, about 2 min 00 s left");
  EXPECT_EQ(progressText(1, 3, 10.0), "1/3, 10 s, about 20 s left");
  // No estimate before anything is done, nor once everything is.
  EXPECT_EQ(progressText(0, 48, 2.0), "0/48, 2 s");
  EXPECT_EQ(progressText(48, 48, 160.0), "48/48, 2 min 40 s");
}

// A sweep of unequal runs: what is left is weighed by cost, not counted. One cheap run done in 10 s, one
// nine times its cost left: 90 s, where the count alone would say 10.
TEST(Progress, TheSweepEstimateWeighsTheRunsLeftByTheirCost) {
  using Clock = SweepEstimate::Clock;
  const Clock::time_point t0{};
  SweepEstimate estimate({1.0, 9.0}, {}, 1.0, t0);
  EXPECT_EQ(estimate.finished(0, t0 + std::chrono::seconds(10)), "1/2, 10 s, about 1 min 30 s left");
  EXPECT_EQ(estimate.finished(1, t0 + std::chrono::seconds(95)), "2/2, 1 min 35 s");
}

// The accuracy sweep's GPU runs come after its CPU runs and cost more: before one has finished they are taken
// at the CPU runs' pace times the prior, then at their own.
TEST(Progress, ALaterLaneIsTakenAtItsOwnPaceOnceOneOfItsRunsIsIn) {
  using Clock = SweepEstimate::Clock;
  const Clock::time_point t0{};
  const auto at = [&](int s) { return t0 + std::chrono::seconds(s); };
  SweepEstimate estimate({1.0, 1.0, 1.0, 1.0}, {0, 0, 1, 1}, 4.0, t0);
  // Lane 0 at 10 s a run: one left of it (10 s), two of lane 1 at 40 s each.
  EXPECT_EQ(estimate.finished(0, at(10)), "1/4, 10 s, about 1 min 30 s left");
  EXPECT_EQ(estimate.finished(1, at(20)), "2/4, 20 s, about 1 min 20 s left");
  // Lane 1's first run took 100 s from when lane 0 ended: the one left will too.
  EXPECT_EQ(estimate.finished(2, at(120)), "3/4, 2 min 00 s, about 1 min 40 s left");
}

std::string written(std::FILE* file) {
  std::fflush(file);
  std::rewind(file);
  std::string text;
  for (int c; (c = std::fgetc(file)) != EOF;)
    text += char(c);
  return text;
}

TEST(Progress, NothingWhenNotEnabledOrWithinTheFirstSecond) {
  std::FILE* file = std::tmpfile();
  ASSERT_NE(file, nullptr);
  {
    TerminalProgress off("simulate: frame", 10, false, file);
    off.update(5);
    TerminalProgress quick("simulate: frame", 10, true, file);
    for (int k = 1; k <= 10; ++k)
      quick.update(k);
  }
  EXPECT_EQ(written(file), "");
  std::fclose(file);
}

TEST(Progress, OneLineRewrittenInPlaceAndFinishedWithANewline) {
  std::FILE* file = std::tmpfile();
  ASSERT_NE(file, nullptr);
  TerminalProgress progress("simulate: frame", 900, true, file);
  std::this_thread::sleep_for(std::chrono::milliseconds(1100));
  progress.update(300);
  std::this_thread::sleep_for(std::chrono::milliseconds(150));
  progress.update(900);
  progress.finish();
  progress.finish();  // once only
  const std::string text = written(file);
  std::fclose(file);
  // The times depend on the machine's load; progressText's own test checks them.
  EXPECT_EQ(text.rfind("\rsimulate: frame 300/900, ", 0), 0u) << text;
  EXPECT_NE(text.find(" left"), std::string::npos) << text;
  EXPECT_NE(text.find("\rsimulate: frame 900/900, "), std::string::npos) << text;
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 1) << text;
  EXPECT_EQ(text.back(), '\n') << text;
  // The second line covers the first one's longer text.
  const std::size_t second = text.find('\r', 1);
  EXPECT_EQ(text.size() - 1 - second, second) << "both lines drawn at the same width: " << text;
}

}  // namespace
}  // namespace drape
