// cpu/parallel.hpp: balanceShares (contiguous shares of the points that move towards equal times), the team's
// barrier and its threads' progress counts, and the log of their waits (cpu/wait_log.hpp).
#include "cpu/parallel.hpp"

#include "cpu/wait_log.hpp"

#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <thread>
#include <vector>

namespace drape {
namespace {

// `rounds` calls where thread t takes per_item[t] seconds an item of its share.
std::vector<long long> balanced(std::vector<long long> bounds, const std::vector<double>& per_item, int rounds,
                                long long least = 1) {
  std::vector<double> smoothed(per_item.size(), -1), seconds(per_item.size());
  for (int r = 0; r < rounds; ++r) {
    for (std::size_t t = 0; t < per_item.size(); ++t)
      seconds[t] = per_item[t] * double(bounds[t + 1] - bounds[t]);
    balanceShares(bounds, seconds, smoothed, 0.25, least);
  }
  return bounds;
}

TEST(BalanceShares, EqualRatesKeepEvenShares) {
  EXPECT_EQ(balanced({0, 500, 1000}, {1e-8, 1e-8}, 10), (std::vector<long long>{0, 500, 1000}));
  EXPECT_EQ(balanced({0, 250, 500, 750, 1000}, {2e-8, 2e-8, 2e-8, 2e-8}, 10),
            (std::vector<long long>{0, 250, 500, 750, 1000}));
}

TEST(BalanceShares, ASlowerThreadGetsFewerItemsInProportion) {
  // Thread 0 three times slower an item: a quarter of the items for equal times.
  const std::vector<long long> b = balanced({0, 500, 1000}, {3e-8, 1e-8}, 1);
  EXPECT_EQ(b, (std::vector<long long>{0, 250, 1000}));
  const std::vector<long long> three = balanced({0, 300, 600, 900}, {1e-8, 2e-8, 1e-8}, 1);
  EXPECT_EQ(three, (std::vector<long long>{0, 360, 540, 900}));
}

TEST(BalanceShares, WorkCrowdedAtOneEndIsSplitEvenly) {
  // Items 0-99 cost 100 units, the others 1: thread 0's rate depends on where its share ends, and the shares
  // settle where both take about the same time.
  const long long n = 1000;
  const auto cost = [](long long lo, long long hi) {
    long long c = 0;
    for (long long i = lo; i < hi; ++i)
      c += i < 100 ? 100 : 1;
    return double(c);
  };
  std::vector<long long> bounds = {0, n / 2, n};
  std::vector<double> smoothed(2, -1), seconds(2);
  for (int r = 0; r < 200; ++r) {
    seconds = {cost(bounds[0], bounds[1]), cost(bounds[1], bounds[2])};
    balanceShares(bounds, seconds, smoothed, 0.25, 1);
  }
  const double a = cost(0, bounds[1]), b = cost(bounds[1], n);
  EXPECT_LT(bounds[1], 100) << "thread 0 keeps only part of the crowded end";
  EXPECT_NEAR(a / (a + b), 0.5, 0.05);
}

TEST(BalanceShares, EveryShareKeepsTheLeast) {
  // A thread a million times slower (a core taken by other work) still keeps `least` items, and so does every
  // other thread when one is much faster.
  EXPECT_EQ(balanced({0, 500, 1000}, {1.0, 1e-6}, 5, 31), (std::vector<long long>{0, 31, 1000}));
  EXPECT_EQ(balanced({0, 500, 1000}, {1e-6, 1.0}, 5, 31), (std::vector<long long>{0, 969, 1000}));
  const std::vector<long long> b = balanced({0, 250, 500, 750, 1000}, {1e-9, 1.0, 1.0, 1.0}, 5, 20);
  EXPECT_EQ(b, (std::vector<long long>{0, 940, 960, 980, 1000}));
}

TEST(BalanceShares, TheBoundsStayInOrderAndCoverEveryItem) {
  std::vector<long long> bounds = {0, 100, 200, 300};
  std::vector<double> smoothed(3, -1);
  const double patterns[4][3] = {{1, 1, 1}, {5e-3, 1, 1e3}, {0, 0, 0}, {1e3, 0, 1}};
  for (int r = 0; r < 40; ++r) {
    const double* p = patterns[r % 4];
    balanceShares(bounds, std::vector<double>(p, p + 3), smoothed, 0.25, 1);
    ASSERT_EQ(bounds.front(), 0);
    ASSERT_EQ(bounds.back(), 300);
    for (std::size_t t = 0; t + 1 < bounds.size(); ++t)
      ASSERT_GE(bounds[t + 1] - bounds[t], 1) << "round " << r;
  }
}

// Ends the test binary with a message unless it is destroyed within 120 s: threads that lost a wake-up hang, and
// a hang fails here rather than at CI's time limit.
class Watchdog {
 public:
  Watchdog(const char* what, unsigned threads)
      : thread_([this, what, threads] {
          const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
          while (!done_.load() && std::chrono::steady_clock::now() < deadline)
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
          if (!done_.load()) {
            std::fprintf(stderr, "%s: %u threads still waiting after 120 s (a lost wake-up)\n", what, threads);
            std::abort();
          }
        }) {}
  ~Watchdog() {
    done_ = true;
    thread_.join();
  }
  Watchdog(const Watchdog&) = delete;
  Watchdog& operator=(const Watchdog&) = delete;

 private:
  std::atomic<bool> done_{false};  // before thread_, which reads it
  std::thread thread_;
};

// `threads` threads each write their slot, pass the barrier and read every slot, `rounds` times; returns the
// reads that missed a write made before the barrier. A barrier that lets a thread through early, or loses a
// wake-up, fails it (the second by the watchdog: a hang ends the test binary with a message, not CI's time limit).
long long missedWrites(unsigned threads, unsigned spins, int rounds, bool nap) {
  TeamBarrier barrier;
  barrier.prepare(threads);
  std::vector<std::atomic<int>> slot(threads);
  std::atomic<long long> missed{0};
  const Watchdog watchdog("TeamBarrier", threads);
  std::vector<std::thread> team;
  for (unsigned t = 0; t < threads; ++t)
    team.emplace_back([&, t] {
      for (int r = 1; r <= rounds; ++r) {
        slot[t].store(r, std::memory_order_relaxed);
        // Now and then a thread arrives late, so that the others spin out and sleep
        if (nap && (r + int(t)) % 97 == 0) std::this_thread::sleep_for(std::chrono::microseconds(200));
        barrier.wait(threads, t, spins);
        for (unsigned u = 0; u < threads; ++u)
          missed += slot[u].load(std::memory_order_relaxed) != r;
        barrier.wait(threads, t, spins);  // no thread writes the next round before every one has read this one
      }
    });
  for (std::thread& t : team)
    t.join();
  return missed.load();
}

TEST(TeamBarrier, EveryThreadSeesTheWritesMadeBeforeIt) {
  EXPECT_EQ(missedWrites(2, 20000, 20000, false), 0);
  // More threads than this machine's two cores: most waits end asleep
  EXPECT_EQ(missedWrites(5, 200, 2000, false), 0);
}

TEST(TeamBarrier, ASleepingThreadIsWoken) {
  // No spinning at all: every thread but the last sleeps at every barrier, and a late one makes them wait long
  EXPECT_EQ(missedWrites(2, 0, 3000, true), 0);
  EXPECT_EQ(missedWrites(3, 0, 1000, true), 0);
}

// `threads` threads in a row, `rounds` times: each writes its slot, publishes the round (TeamProgress), awaits its
// neighbours' and reads their slots; returns the reads that missed a neighbour's write of that round. A neighbour
// may be one round ahead (it awaits only this thread's round before), never two. Counts start at `first`, so that a
// start just below 2^32 crosses the wrap.
long long missedNeighbourWrites(unsigned threads, unsigned spins, int rounds, std::uint32_t first, bool nap,
                                long long* ahead_by_two) {
  TeamProgress progress;
  progress.resize(threads);
  for (unsigned t = 0; t < threads; ++t)
    progress.publish(t, first);
  std::vector<std::atomic<std::uint32_t>> slot(threads);
  for (auto& s : slot)
    s.store(first);
  std::atomic<long long> missed{0}, two{0};
  const Watchdog watchdog("TeamProgress", threads);
  std::vector<std::thread> team;
  for (unsigned t = 0; t < threads; ++t)
    team.emplace_back([&, t] {
      for (int r = 1; r <= rounds; ++r) {
        const std::uint32_t round = first + std::uint32_t(r);
        slot[t].store(round, std::memory_order_relaxed);
        if (nap && (r + int(t)) % 97 == 0) std::this_thread::sleep_for(std::chrono::microseconds(200));
        progress.publish(t, round);
        for (const unsigned u : {t - 1, t + 1}) {
          if (u >= threads) continue;  // t - 1 of thread 0 wraps past the team too
          missed += !TeamProgress::reached(progress.await(u, round, spins), round);  // it returns what it saw
          const auto seen = std::int32_t(slot[u].load(std::memory_order_relaxed) - round);
          missed += seen < 0;
          two += seen > 1;
        }
      }
    });
  for (std::thread& t : team)
    t.join();
  *ahead_by_two = two.load();
  return missed.load();
}

TEST(TeamProgress, ANeighbourSeesTheWritesMadeBeforeAPublishAndIsNeverTwoAhead) {
  long long two = -1;
  EXPECT_EQ(missedNeighbourWrites(2, 20000, 20000, 0, false, &two), 0);
  EXPECT_EQ(two, 0);
  // More threads than cores; the middle ones have two neighbours
  EXPECT_EQ(missedNeighbourWrites(5, 200, 3000, 0, false, &two), 0);
  EXPECT_EQ(two, 0);
}

TEST(TeamProgress, ASleepingThreadIsWokenAndTheCountsWrap) {
  long long two = -1;
  // No spinning: every wait that is not already over sleeps; a late thread now and then makes them sleep long
  EXPECT_EQ(missedNeighbourWrites(3, 0, 2000, 0, true, &two), 0);
  EXPECT_EQ(two, 0);
  // From 1000 below 2^32: the counts wrap to 0 halfway, and a count just past the wrap is still later
  EXPECT_EQ(missedNeighbourWrites(2, 0, 2000, 0xFFFFFFFFu - 999u, false, &two), 0);
  EXPECT_EQ(two, 0);
}

TEST(TeamCount, ASleeperWhoseWakeUpIsMissedWakesAtItsTimeout) {
  // The owner's store is seen, but no wake-up is sent (what a publish whose look for sleepers ran ahead of its store
  // does): the sleeper must still return, at its timeout, with the count it waited for.
  TeamCount count;
  const Watchdog watchdog("TeamCount", 1);
  std::atomic<std::uint32_t> seen{0};
  std::thread sleeper([&] { seen = count.await(1, 0); });
  while (count.sleepers.load() == 0)  // asleep, or about to be
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  std::this_thread::sleep_for(std::chrono::milliseconds(5));
  const auto start = std::chrono::steady_clock::now();
  count.count.store(1, std::memory_order_release);
  sleeper.join();
  EXPECT_EQ(seen.load(), 1u);
  EXPECT_EQ(count.sleepers.load(), 0u);
  // A timeout of a hundred microseconds; a loaded machine may take its time to run the thread again
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(10));
}

TEST(TeamBarrier, ABarrierServesTeamsOfOtherSizesInTurn) {
  // One barrier for teams of 3, 2, 3 and 2 threads one after another (runOnTeam's prepare between): the counts of a
  // thread that sat out a team must not hold the next team back or let it through early.
  TeamBarrier barrier;
  const Watchdog watchdog("TeamBarrier", 3);
  for (const unsigned threads : {3u, 2u, 3u, 2u}) {
    barrier.prepare(threads);
    std::vector<std::atomic<int>> slot(threads);
    std::atomic<long long> missed{0};
    std::vector<std::thread> team;
    for (unsigned t = 0; t < threads; ++t)
      team.emplace_back([&, t] {
        for (int r = 1; r <= 300 + int(threads); ++r) {  // teams end on different counts
          slot[t].store(r, std::memory_order_relaxed);
          barrier.wait(threads, t, 200);
          for (unsigned u = 0; u < threads; ++u)
            missed += slot[u].load(std::memory_order_relaxed) != r;
          barrier.wait(threads, t, 200);
        }
      });
    for (std::thread& t : team)
      t.join();
    EXPECT_EQ(missed.load(), 0) << threads << " threads";
  }
}

TEST(TeamBarrier, ATeamScopeGivesItsThreadsTheirNumbersOneSingleAndItsBarrier) {
  // runOnTeam is compiled with OpenMP and this file without: the scope carries the team over
  constexpr int kThreads = 3, kRounds = 500;
  std::atomic<int> singles{0}, numbers{0}, late{0};
  std::vector<std::atomic<int>> reached(kThreads);
  runOnTeam(kThreads, [&] {
    if (!inTeam()) return;  // the runtime gave fewer threads: nothing to check
    numbers += 1 << (4 * teamThread());
    for (int r = 1; r <= kRounds; ++r) {
      reached[std::size_t(teamThread())].store(r);
      teamSingle([&] { ++singles; });  // ends with the barrier
      for (int t = 0; t < teamSize(); ++t)
        late += reached[std::size_t(t)].load() < r;
      teamBarrier();
    }
  });
  if (numbers.load() == 0) GTEST_SKIP() << "OpenMP gave runOnTeam one thread";
  EXPECT_EQ(numbers.load(), 0x111) << "threads 0, 1 and 2, each once";
  EXPECT_EQ(singles.load(), kRounds);
  EXPECT_EQ(late.load(), 0);
}

// Two lines of this file, each filed apart and summed over the threads, the longest first.
TEST(WaitLog, FilesEachLineApartAndSortsTheLongestFirst) {
  WaitLog log;
  log.prepare(2);
  const std::source_location a = std::source_location::current();
  const std::source_location b = std::source_location::current();
  log.add(0, a, 0.001);
  log.add(1, b, 0.004);
  log.add(0, b, 0.002);
  log.add(0, a, 0.001);
  log.add(2, a, 1.0);   // a thread the log was not prepared for: not filed
  log.add(1, b, 5e-7);  // under 1 us, 1-20 us, 20 us or more
  log.add(1, b, 5e-6);
  log.add(1, b, 0);
  const std::vector<WaitLog::Site> sites = log.sites();
  ASSERT_EQ(sites.size(), 2u);
  EXPECT_EQ(sites[0].line, b.line());
  EXPECT_EQ(sites[0].count, (std::vector<long long>{1, 4}));
  EXPECT_DOUBLE_EQ(sites[0].seconds[1], 0.004 + 5e-7 + 5e-6);
  EXPECT_EQ(sites[1].count, (std::vector<long long>{2, 0}));
  EXPECT_DOUBLE_EQ(sites[1].seconds[0], 0.002);
  EXPECT_NE(sites[1].file.find("parallel_test.cpp"), std::string::npos) << sites[1].file;
  EXPECT_DOUBLE_EQ(log.totals()[0], 0.004);
  EXPECT_DOUBLE_EQ(log.totals()[1], 0.004 + 5e-7 + 5e-6);
  const std::vector<WaitLog::Lengths> lengths = log.lengths();
  EXPECT_EQ(lengths[0].count, (std::array<long long, 3>{0, 0, 3}));
  EXPECT_EQ(lengths[1].count, (std::array<long long, 3>{2, 1, 1}));
  EXPECT_DOUBLE_EQ(lengths[1].seconds[1], 5e-6);
}

// A team given a log times each wait on the thread that waits, under the line that called it: thread 1 sleeps 2 ms
// before each barrier, so thread 0 waits for it there; thread 1 then waits at a single for thread 0's 2 ms body.
TEST(WaitLog, ATeamsWaitsAreTimedUnderTheLinesThatCalledThem) {
  constexpr int kRounds = 10;
  constexpr auto kNap = std::chrono::milliseconds(2);
  WaitLog log;
  TeamBarrier barrier;
  std::atomic<unsigned> barrier_line{0}, single_line{0};  // both threads store the same value
  std::atomic<int> logged{0};
  runOnTeam(2, barrier, &log, [&] {
    if (!inTeam()) return;
    logged += current_team.waits == &log;
    for (int r = 0; r < kRounds; ++r) {
      if (teamThread() == 1) std::this_thread::sleep_for(kNap);
      barrier_line = __LINE__ + 1;
      teamBarrier();
      single_line = __LINE__ + 1;
      teamSingle([&] { std::this_thread::sleep_for(kNap); });
    }
  });
  if (logged.load() == 0) GTEST_SKIP() << "OpenMP gave runOnTeam one thread";
  EXPECT_EQ(logged.load(), 2);
  const std::vector<WaitLog::Site> sites = log.sites();
  ASSERT_EQ(sites.size(), 2u);
  for (const WaitLog::Site& s : sites) {
    EXPECT_EQ(s.count, (std::vector<long long>{kRounds, kRounds})) << s.line;
    const double slept = 0.9 * kRounds * std::chrono::duration<double>(kNap).count();
    if (s.line == barrier_line.load()) {
      EXPECT_GT(s.seconds[0], slept);  // each of thread 0's waits there 2 ms or more: 20 us or more (lengths below)
      EXPECT_LT(s.seconds[1], s.seconds[0]);
    } else {
      EXPECT_EQ(s.line, single_line.load());
      EXPECT_GT(s.seconds[1], slept);
      EXPECT_LT(s.seconds[0], s.seconds[1]);
    }
  }
  const std::vector<WaitLog::Lengths> lengths = log.lengths();
  EXPECT_GE(lengths[0].count[2], kRounds);
  EXPECT_GE(lengths[1].count[2], kRounds);
  // Without a log the team times nothing
  std::atomic<int> unlogged{0};
  runOnTeam(2, barrier, [&] { unlogged += current_team.waits != nullptr; });
  EXPECT_EQ(unlogged.load(), 0);
}

}  // namespace
}  // namespace drape
