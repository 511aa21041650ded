// cpu/parallel.hpp's balanceShares: contiguous shares of the points that move towards equal times.
#include "cpu/parallel.hpp"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace drape
