// The self-collision lists built on the GPU (glsl/sim/pairs.glsl): a hash grid with the same cells and
// buckets as the CPU grid, a counting sort with ascending indices in every bucket, exactly the
// brute-force pairs, candidate lists equal to the CPU's (src/cpu/collision_pairs.hpp) entry for entry,
// and the same Jacobi corrections as the CPU pass, on random clouds (negative coordinates, points on
// cell borders, far from the origin), for both build paths (one work group, and the multi-dispatch
// scans), and with a list buffer too small for the lists (the points that do not fit are served from
// the grid).
#include "core/derived.hpp"
#include "cpu/collision_pairs.hpp"
#include "cpu/hash_grid.hpp"
#include "gl_fixture.hpp"
#include "gpu/cloth_tables.hpp"
#include "gpu/gpu_solver.hpp"
#include "gpu_test_support.hpp"

#include <algorithm>
#include <cstdio>
#include <optional>
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
  std::size_t capacity;   // list entries the GPU buffer holds; 0: the solver's estimate
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

  GpuSolver gpu(scene, {.path = GpuPath::General, .buckets = c.buckets, .pair_capacity = c.capacity});
  ASSERT_EQ(gpu.passes()[3], c.build);
  gpu.uploadState(cloud, still, 0);
  gpu.selfCollide();
  const GpuGrid grid = gpu.readGrid();
  const GpuPairs lists = gpu.readPairs();
  const std::size_t n = cloud.size();
  const std::uint32_t buckets = c.buckets ? c.buckets : std::uint32_t(derived::hashBucketCount(n));
  ASSERT_EQ(grid.cells.size(), n);
  ASSERT_EQ(grid.start.size(), std::size_t(buckets) + 1);

  // Cells and buckets as on the CPU, and a counting sort: start[] the prefix sums of the bucket
  // sizes, each bucket holding its own points in ascending order. The cell edge is the lists' reach.
  const float range = 2.0f * float(kThickness);
  // The lists' skin as the CPU solver's: a share of the contact distance, or of two spacings on a cloth finer
  // than half of it (large_cloud's 80 x 80 grid).
  const Topology topo = buildTopology(scene.cloth);
  const float skin = derived::pairSkin(kDefaultPairMargin, range, gpu::shortestStructural(topo));
  const float cell = range + skin;
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
      ASSERT_EQ(grid.sorted_anchor[s], points[grid.sorted[s]]) << "slot " << s << ": the anchor's copy";
      if (s > grid.start[b]) {
        ASSERT_LT(grid.sorted[s - 1], grid.sorted[s]) << "bucket " << b << " out of order";
      }
    }
  }
  ASSERT_EQ(grid.start[buckets], n);

  const Pairs expected = bruteForce(points, range);
  EXPECT_GT(expected.size(), 0u) << "the cloud must contain close pairs for the test to mean anything";
  EXPECT_EQ(queryGpuGrid(grid, points, range), expected);
  EXPECT_EQ(queryGpuGrid(grid, points, cell), bruteForce(points, cell));

  // The lists: the CPU's, entry for entry (the pairs within reach and not held at rest, ascending), as far as
  // the buffer holds them.
  CollisionPairs<float> cpu_lists;
  cpu_lists.configure(range, skin);
  // Without the pairs held at rest (closer than 2 x thickness in the cloth's rest shape), as CpuSolver's.
  cpu_lists.setRest(std::vector<glm::vec3>(topo.initial_positions.begin(), topo.initial_positions.end()));
  cpu_lists.update(points, 1);
  ASSERT_EQ(lists.start.size(), n + 1);
  EXPECT_EQ(lists.builds, 1u);
  EXPECT_EQ(std::size_t(lists.start[n]), cpu_lists.pairCount());
  EXPECT_EQ(lists.overflow, lists.start[n] > lists.capacity);
  if (c.capacity != 0) {
    EXPECT_EQ(lists.capacity, c.capacity);
    EXPECT_TRUE(lists.overflow) << "the case must overflow the buffer for the test to mean anything";
  }
  std::size_t listed = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (lists.start[i + 1] > lists.capacity) continue;
    const std::vector<std::uint32_t> gpu_list(lists.list.begin() + lists.start[i],
                                              lists.list.begin() + lists.start[i + 1]);
    ASSERT_EQ(gpu_list, std::vector<std::uint32_t>(cpu_lists.begin(i), cpu_lists.end(i))) << "point " << i;
    ++listed;
  }
  EXPECT_GT(listed, 0u);

  // The corrections: the same sums in the same order as the CPU pass (bound: tests/gpu_passes_gl_test.cpp).
  CpuSolver<float> cpu(scene);
  cpu.setState(cloud, still);
  cpu.selfCollide();
  const auto expected_x = cpu.readPositions();
  const double bound =
      gpu_test::exactDevice(gpu.contextInfo()) ? 0.0 : 4.0 * gpu_test::floatUlp(gpu_test::maxAbs(cloud));
  const double dx = gpu_test::maxComponentDifference(gpu.readPositions(), expected_x);
  std::printf(
      "%-16s %zu points, %u buckets, %zu close pairs, %u list entries (%zu points listed), max |dx| %.3g m "
      "(bound %.3g m)\n",
      c.name, n, buckets, expected.size() / 2, lists.start[n], listed, dx, bound);
  EXPECT_LE(dx, bound);
  EXPECT_GT(gpu_test::changedPoints(cloud, expected_x), 0);
}

INSTANTIATE_TEST_SUITE_P(
    Clouds, GpuGridTest,
    ::testing::Values(CloudCase{"positive", 30, 50, 0.0, 0.3, false, 0, "grid_build", 0},
                      CloudCase{"negative", 30, 50, -0.3, 0.0, false, 0, "grid_build", 0},
                      CloudCase{"straddling_zero", 30, 50, -0.15, 0.15, false, 0, "grid_build", 0},
                      CloudCase{"on_cell_borders", 20, 40, -0.1, 0.1, true, 0, "grid_build", 0},
                      CloudCase{"far_from_origin", 30, 50, 100.0, 100.3, false, 0, "grid_build", 0},
                      // 64 buckets for 1500 points: every bucket mixes many cells.
                      CloudCase{"crowded_buckets", 30, 50, -0.15, 0.15, false, 64, "grid_build", 0},
                      // More buckets than one work group scans: the three-dispatch scan.
                      CloudCase{"multi_block_scan", 30, 50, -0.15, 0.15, false, 1u << 16, "grid_scan", 0},
                      // 6400 points: the lists' scan takes three dispatches too.
                      CloudCase{"large_cloud", 80, 80, -0.25, 0.25, true, 0, "grid_scan", 0},
                      // A list buffer that holds a fraction of the lists.
                      CloudCase{"lists_overflow", 30, 50, -0.15, 0.15, false, 0, "grid_build", 600}),
    [](const ::testing::TestParamInfo<CloudCase>& param) { return std::string(param.param.name); });

}  // namespace
}  // namespace drape

namespace drape {
namespace {

// A falling, folding cloth over many substeps: the lists the GPU keeps always hold every pair in range
// (brute force over the positions self_collide read), they are rebuilt far less often than every
// substep, and with a buffer too small at first, the run still equals the CPU's bit for bit while the
// grid serves the points that did not fit, until health() grows the buffer.
TEST_F(GlTest, GpuListsStayValidAndOverflowGrowsTheBuffer) {
  const Scene scene = gpu_test::standardScene("selfCollision.json");
  GpuSolver gpu(scene, {.path = GpuPath::General, .pair_capacity = 1000});
  CpuSolver<float> cpu(scene);
  std::optional<gpu_test::RoundingTwin> twin;
  if (!gpu_test::exactDevice(gpu.contextInfo())) twin.emplace(scene);
  const std::size_t n = std::size_t(gpu.topology().pointCount());
  const float range = 2.0f * float(scene.cloth.thickness);
  int checks = 0, overflowed = 0;
  for (int f = 1; f <= 120; ++f) {
    for (int s = 0; s < scene.sim.steps_per_frame; ++s) {
      gpu.forcesIntegrate();
      // Every pair in range of the positions self_collide is about to read must be listed.
      if (f % 20 == 0 && s == scene.sim.steps_per_frame - 1) {
        const auto x = gpu.readPositions();
        gpu.selfCollide();
        const GpuPairs lists = gpu.readPairs();
        std::vector<glm::vec3> p(x.begin(), x.end());
        for (const auto& [i, j] : bruteForce(p, range)) {
          if (lists.start[i + 1] > lists.capacity) continue;  // served from the grid
          const auto first = lists.list.begin() + lists.start[i], last = lists.list.begin() + lists.start[i + 1];
          ASSERT_TRUE(std::binary_search(first, last, j)) << "frame " << f << ": pair " << i << "," << j;
        }
        overflowed += lists.overflow;
        ++checks;
      } else {
        gpu.selfCollide();
      }
      gpu.limitStretch();
    }
    cpu.stepFrame();
    if (twin) twin->stepFrame();
    // Grows the buffer, the first time after 60 frames of folding served from the grid.
    if (f % 60 == 0) {
      ASSERT_TRUE(gpu.health().ok()) << "frame " << f;
    }
  }
  const GpuPairs lists = gpu.readPairs();
  const long long substeps = 120LL * scene.sim.steps_per_frame;
  EXPECT_GT(lists.capacity, 1000u) << "the buffer must have grown";
  EXPECT_LE(lists.start[n], lists.capacity);
  EXPECT_FALSE(lists.overflow);
  EXPECT_LT(lists.builds, std::uint32_t(substeps / 2)) << "the lists must outlive a substep";
  EXPECT_EQ(checks, 6);
  EXPECT_EQ(overflowed, 3) << "frames 20, 40, 60 overflow the first buffer, 80, 100, 120 fit the grown one";
  const auto xc = cpu.readPositions();
  const double bound = !twin ? 0.0 : twin->bound(xc, 1.0, double(substeps) * 4.0 * gpu_test::floatUlp(1.0));
  EXPECT_LE(gpu_test::maxComponentDifference(gpu.readPositions(), xc), bound);
  std::printf("selfCollision: %u list builds in %lld substeps, %u entries, buffer grown to %u\n", lists.builds,
              substeps, lists.start[n], lists.capacity);
}

}  // namespace
}  // namespace drape
