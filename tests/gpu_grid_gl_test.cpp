// The self-collision hash grid built on the GPU: the same cells and buckets as the CPU grid, a
// counting sort with ascending indices in every bucket, exactly the brute-force pairs, and the same
// Jacobi corrections as the CPU pass, on random clouds (negative coordinates, points on cell borders,
// far from the origin) and for both build paths (one work group, and the multi-dispatch scan).
#include "core/derived.hpp"
#include "cpu/hash_grid.hpp"
#include "gl_fixture.hpp"
#include "gpu/gpu_solver.hpp"
#include "gpu_test_support.hpp"

#include <algorithm>
#include <cstdio>
#include <ostream>
#include <random>
#include <set>

namespace drape {
namespace {

using Pairs = std::set<std::pair<std::uint32_t, std::uint32_t>>;

struct CloudCase {
  const char* name;
  int width, height;      // the cloud is a W x H "cloth" whose points are put at random
  double lo, hi;          // coordinate range, m
  bool snap;              // coordinates on a half-cell lattice: every other one exactly on a cell border
  std::uint32_t buckets;  // 0: one per point, as the CPU grid
  const char* build;      // expected first grid pass: grid_build (one work group) or grid_scan
};

// Test names and CTest listings show the case's name instead of its bytes.
void PrintTo(const CloudCase& c, std::ostream* os) {
  *os << c.name;
}

constexpr double kThickness = 0.0095;

std::vector<glm::dvec3> makeCloud(const CloudCase& c) {
  const double cell = double(2.0f * float(kThickness));
  std::mt19937 rng(1234);
  std::uniform_real_distribution<double> u(c.lo, c.hi);
  std::vector<glm::dvec3> cloud(std::size_t(c.width) * std::size_t(c.height));
  for (glm::dvec3& p : cloud) {
    p = {u(rng), u(rng), u(rng)};
    if (c.snap) p = glm::round(p / (cell / 2)) * (cell / 2);
    p = gpu_test::asFloat(p);  // float coordinates, as both solvers store them
  }
  return cloud;
}

Pairs bruteForce(const std::vector<glm::vec3>& p, float range) {
  Pairs out;
  for (std::uint32_t i = 0; i < p.size(); ++i)
    for (std::uint32_t j = 0; j < p.size(); ++j)
      if (i != j && glm::dot(p[i] - p[j], p[i] - p[j]) < range * range) out.insert({i, j});
  return out;
}

// The CPU query (HashGrid::forEachCandidate) run over the grid the GPU built.
Pairs queryGpuGrid(const GpuGrid& grid, const std::vector<glm::vec3>& p, float range) {
  const std::uint32_t mask = std::uint32_t(grid.start.size() - 2);
  Pairs out;
  for (std::uint32_t i = 0; i < p.size(); ++i)
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const glm::ivec3 n = grid.cells[i] + glm::ivec3(dx, dy, dz);
          const std::uint32_t b = hashCell(n) & mask;
          for (std::uint32_t s = grid.start[b]; s < grid.start[b + 1]; ++s) {
            const std::uint32_t j = grid.sorted[s];
            if (j == i || grid.cells[j] != n) continue;
            EXPECT_TRUE(out.insert({i, j}).second) << "pair " << i << "," << j << " visited twice";
          }
        }
  Pairs close;
  for (const auto& [i, j] : out)
    if (glm::dot(p[i] - p[j], p[i] - p[j]) < range * range) close.insert({i, j});
  return close;
}

class GpuGridTest : public GlTest, public ::testing::WithParamInterface<CloudCase> {};

TEST_P(GpuGridTest, MatchesTheCpuGridAndBruteForce) {
  const CloudCase c = GetParam();
  Scene scene;
  scene.path = c.name;
  scene.cloth.num_width_points = c.width;
  scene.cloth.num_height_points = c.height;
  scene.cloth.thickness = kThickness;
  scene.sim.self_collision = true;
  const std::vector<glm::dvec3> cloud = makeCloud(c);
  const std::vector<glm::dvec3> still(cloud.size(), glm::dvec3(0));

  GpuSolver gpu(scene, {.buckets = c.buckets});
  ASSERT_EQ(gpu.passes()[1], c.build);
  gpu.uploadState(cloud, still, 0);
  gpu.selfCollide();
  const GpuGrid grid = gpu.readGrid();
  const std::size_t n = cloud.size();
  const std::uint32_t buckets = c.buckets ? c.buckets : std::uint32_t(derived::hashBucketCount(n));
  ASSERT_EQ(grid.cells.size(), n);
  ASSERT_EQ(grid.start.size(), std::size_t(buckets) + 1);

  // Cells and buckets as on the CPU, and a counting sort: start[] the prefix sums of the bucket
  // sizes, each bucket holding its own points in ascending order.
  const float cell = 2.0f * float(kThickness);
  std::vector<glm::vec3> points(cloud.begin(), cloud.end());
  std::vector<std::uint32_t> size(buckets, 0);
  for (std::size_t i = 0; i < n; ++i) {
    ASSERT_EQ(grid.cells[i], HashGrid<float>::cellOf(points[i], 1.0f / cell)) << "point " << i;
    ASSERT_EQ(grid.buckets[i], hashCell(grid.cells[i]) & (buckets - 1)) << "point " << i;
    ++size[grid.buckets[i]];
  }
  std::uint32_t sum = 0;
  for (std::uint32_t b = 0; b < buckets; ++b) {
    ASSERT_EQ(grid.start[b], sum) << "bucket " << b;
    sum += size[b];
    for (std::uint32_t s = grid.start[b]; s < grid.start[b] + size[b]; ++s) {
      ASSERT_EQ(grid.buckets[grid.sorted[s]], b) << "slot " << s;
      if (s > grid.start[b]) {
        ASSERT_LT(grid.sorted[s - 1], grid.sorted[s]) << "bucket " << b << " out of order";
      }
    }
  }
  ASSERT_EQ(grid.start[buckets], n);

  const Pairs expected = bruteForce(points, cell);
  EXPECT_GT(expected.size(), 0u) << "the cloud must contain close pairs for the test to mean anything";
  EXPECT_EQ(queryGpuGrid(grid, points, cell), expected);

  // The corrections: the same sums in the same order as the CPU pass (bound: tests/gpu_passes_gl_test.cpp).
  CpuSolver<float> cpu(scene);
  cpu.setState(cloud, still);
  cpu.selfCollide();
  const auto expected_x = cpu.readPositions();
  const double bound =
      gpu_test::bitIdenticalDevice(gpu.contextInfo()) ? 0.0 : 4.0 * gpu_test::floatUlp(gpu_test::maxAbs(cloud));
  const double dx = gpu_test::maxComponentDifference(gpu.readPositions(), expected_x);
  std::printf("%-16s %zu points, %u buckets, %zu close pairs, max |dx| %.3g m (bound %.3g m)\n", c.name, n, buckets,
              expected.size() / 2, dx, bound);
  EXPECT_LE(dx, bound);
  EXPECT_GT(gpu_test::changedPoints(cloud, expected_x), 0);
}

INSTANTIATE_TEST_SUITE_P(
    Clouds, GpuGridTest,
    ::testing::Values(CloudCase{"positive", 30, 50, 0.0, 0.3, false, 0, "grid_build"},
                      CloudCase{"negative", 30, 50, -0.3, 0.0, false, 0, "grid_build"},
                      CloudCase{"straddling_zero", 30, 50, -0.15, 0.15, false, 0, "grid_build"},
                      CloudCase{"on_cell_borders", 20, 40, -0.1, 0.1, true, 0, "grid_build"},
                      CloudCase{"far_from_origin", 30, 50, 100.0, 100.3, false, 0, "grid_build"},
                      // 64 buckets for 1500 points: every bucket mixes many cells.
                      CloudCase{"crowded_buckets", 30, 50, -0.15, 0.15, false, 64, "grid_build"},
                      // More buckets than one work group scans: the three-dispatch scan.
                      CloudCase{"multi_block_scan", 30, 50, -0.15, 0.15, false, 1u << 16, "grid_scan"},
                      CloudCase{"large_cloud", 80, 80, -0.25, 0.25, true, 0, "grid_scan"}),
    [](const ::testing::TestParamInfo<CloudCase>& param) { return std::string(param.param.name); });

}  // namespace
}  // namespace drape
