#include "cpu/hash_grid.hpp"
#include "cpu/parallel.hpp"
#include "kernel_sets.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <iterator>
#include <limits>
#include <random>
#include <set>

namespace drape {
namespace {

using Pairs = std::set<std::pair<std::uint32_t, std::uint32_t>>;

template <class T>
Pairs bruteForce(const std::vector<glm::vec<3, T>>& p, T range) {
  Pairs out;
  for (std::uint32_t i = 0; i < p.size(); ++i)
    for (std::uint32_t j = 0; j < p.size(); ++j)
      if (i != j && glm::distance(p[i], p[j]) < range) out.insert({i, j});
  return out;
}

template <class T>
Pairs viaGrid(const std::vector<glm::vec<3, T>>& p, T range) {
  HashGrid<T> grid;
  grid.build(p, range);
  Pairs out;
  for (std::uint32_t i = 0; i < p.size(); ++i) {
    std::vector<std::uint32_t> seen;
    grid.forEachCandidate(i, [&](std::uint32_t j) {
      seen.push_back(j);
      if (glm::distance(p[i], p[j]) < range) out.insert({i, j});
    });
    std::sort(seen.begin(), seen.end());
    EXPECT_TRUE(std::adjacent_find(seen.begin(), seen.end()) == seen.end()) << "candidate visited twice";
  }
  return out;
}

struct CloudCase {
  const char* name;
  int points;
  double lo, hi;  // coordinate range
  bool snap;      // put coordinates exactly on cell borders
};

class HashGridCloud : public ::testing::TestWithParam<CloudCase> {};

TEST_P(HashGridCloud, FindsExactlyTheBruteForcePairs) {
  const CloudCase c = GetParam();
  const double range = 2 * 0.0095;
  std::mt19937 rng(1234);
  std::uniform_real_distribution<double> u(c.lo, c.hi);
  std::vector<glm::dvec3> pd(std::size_t(c.points));
  for (auto& p : pd) {
    p = {u(rng), u(rng), u(rng)};
    if (c.snap) p = glm::round(p / range) * range;  // many points exactly on cell borders
  }
  std::vector<glm::vec3> pf(pd.begin(), pd.end());
  Pairs expected_d = bruteForce(pd, range), expected_f = bruteForce(pf, float(range));
  EXPECT_GT(expected_d.size(), 0u) << "the cloud must contain close pairs for the test to mean anything";
  EXPECT_EQ(viaGrid(pd, range), expected_d);
  EXPECT_EQ(viaGrid(pf, float(range)), expected_f);
}

INSTANTIATE_TEST_SUITE_P(Clouds, HashGridCloud,
                         ::testing::Values(CloudCase{"positive", 1500, 0.0, 0.3, false},
                                           CloudCase{"negative", 1500, -0.3, 0.0, false},
                                           CloudCase{"straddling_zero", 1500, -0.15, 0.15, false},
                                           CloudCase{"on_cell_borders", 800, -0.1, 0.1, true},
                                           CloudCase{"far_from_origin", 1500, 100.0, 100.3, false}),
                         [](const auto& row) { return std::string(row.param.name); });

// Each point's candidates in the order the query visits them: the grid's buckets and their order.
std::vector<std::vector<std::uint32_t>> candidates(const HashGrid<float>& grid, std::size_t n) {
  std::vector<std::vector<std::uint32_t>> out(n);
  for (std::size_t i = 0; i < n; ++i)
    grid.forEachCandidate(i, [&](std::uint32_t j) { out[i].push_back(j); });
  return out;
}

// A team builds the grid together (each thread its share of the points): the buckets must list their points as one
// thread's stable sort does, in a dense box and hashed, with teams whose shares split buckets between threads.
TEST(HashGrid, ATeamBuildsTheGridOfOneThread) {
  for (const double side : {0.3, 30.0}) {  // a dense box; a box too large for one, hashed
    std::mt19937 rng(77);
    std::uniform_real_distribution<float> u(0.0f, float(side));
    std::vector<glm::vec3> p(3001);
    for (auto& q : p)
      q = {u(rng), u(rng), u(rng)};
    const float cell = 0.019f;
    HashGrid<float> one;
    one.build(p, cell);
    EXPECT_EQ(one.dense(), side < 1) << side;
    for (const int threads : {2, 3}) {
      HashGrid<float> team;
      team.build({glm::vec3(5)}, cell);  // a grid built before, for another cloud, as a solver's is
      std::exception_ptr failure;
      runOnTeam(threads, [&] { team.build(p, cell, failure); });
      EXPECT_FALSE(failure);
      EXPECT_EQ(team.dense(), one.dense()) << side << ", " << threads << " threads";
      EXPECT_EQ(team.bucketCount(), one.bucketCount()) << side << ", " << threads << " threads";
      EXPECT_EQ(team.sorted(), one.sorted()) << side << ", " << threads << " threads";
      EXPECT_EQ(candidates(team, p.size()), candidates(one, p.size())) << side << ", " << threads << " threads";
      // Again on the same grid, for a cloud of fewer points in a smaller box: the counts of the larger one are gone
      std::vector<glm::vec3> part;
      std::copy_if(p.begin(), p.end(), std::back_inserter(part), [&](glm::vec3 q) { return q.x < 0.3f * side; });
      HashGrid<float> one_part;
      one_part.build(part, cell);
      runOnTeam(threads, [&] { team.build(part, cell, failure); });
      EXPECT_EQ(team.sorted(), one_part.sorted()) << side << ", " << threads << " threads, a second build";
      EXPECT_EQ(candidates(team, part.size()), candidates(one_part, part.size())) << side << ", " << threads;
    }
  }
}

// With the kernels' cellsOf every point gets cellOf's cell, several at once, and so the same buckets: on one thread and
// on teams (a share of none among them), for counts that leave a vector part full, with the coordinates cellOf clamps
// or sends to cell 0 (NaN, infinities, beyond 2^30 cells), -0 and points on cell borders.
TEST(HashGrid, EveryKernelSetMakesTheCellsOfOnePointAtATime) {
  const float cell = 0.019f, inf = std::numeric_limits<float>::infinity();
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-0.2f, 0.3f);
  std::vector<glm::vec3> cloud(3001);
  for (auto& q : cloud)
    q = {u(rng), u(rng), u(rng)};
  for (std::size_t k = 0; k < 40; ++k)
    cloud[k * 7] = glm::round(cloud[k * 7] / cell) * cell;  // on borders
  const std::vector<glm::vec3> odd = {{std::numeric_limits<float>::quiet_NaN(), 0.1f, -0.1f},
                                      {inf, -inf, 0.0f},
                                      {-0.0f, 1e12f, -1e12f},
                                      {0.05f, -0.0f, 0.019f}};
  std::copy(odd.begin(), odd.end(), cloud.begin() + 1000);
  for (const std::size_t n : {std::size_t(2), std::size_t(37), cloud.size()}) {
    const std::vector<glm::vec3> p(cloud.begin() + std::ptrdiff_t(n == 2 ? 1001 : 0),
                                   cloud.begin() + std::ptrdiff_t(n == 2 ? 1003 : n));
    HashGrid<float> one;
    one.build(p, cell);
    for (const GridKernels* kernels : test::kernelSets())
      for (const int threads : {1, 2, 3}) {
        HashGrid<float> grid;
        grid.setKernels(kernels);
        std::exception_ptr failure;
        if (threads == 1)
          grid.build(p, cell);
        else
          runOnTeam(threads, [&] { grid.build(p, cell, failure); });
        ASSERT_FALSE(failure);
        for (std::size_t i = 0; i < p.size(); ++i)
          ASSERT_EQ(grid.cellOfPoint(i), HashGrid<float>::cellOf(p[i], 1.0f / cell))
              << kernels->name << ", " << threads << " threads, point " << i << " of " << p.size();
        EXPECT_EQ(grid.dense(), one.dense()) << kernels->name << ", " << n;
        EXPECT_EQ(grid.bucketCount(), one.bucketCount()) << kernels->name << ", " << n;
        EXPECT_EQ(grid.sorted(), one.sorted()) << kernels->name << ", " << threads << " threads, " << n;
      }
  }
}

TEST(HashGrid, CellOfFloorsNegativeCoordinates) {
  EXPECT_EQ(HashGrid<double>::cellOf({-0.01, 0.0, 0.029}, 1.0 / 0.02), glm::ivec3(-1, 0, 1));
}

}  // namespace
}  // namespace drape
