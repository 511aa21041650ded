// The blow-up check both solvers share (src/core/health.hpp), on hand-made states of a 4 x 4 cloth
// (spacing 1/3 m, so a structural spring rests at 1/3 m), and the CPU solver's health() built on it.
#include "core/health.hpp"
#include "cpu/cpu_solver.hpp"
#include "cpu/grid_path.hpp"
#include "kernel_sets.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <utility>
#include <vector>

namespace drape {
namespace {

struct Grid {
  ClothSpec cloth;
  Topology topo;
  std::vector<glm::dvec3> x, v;
  Grid() {
    cloth.num_width_points = 4;
    cloth.num_height_points = 4;
    topo = buildTopology(cloth);
    x = topo.initial_positions;
    v.assign(x.size(), glm::dvec3(0));
  }
};

TEST(Health, ARestingClothIsHealthy) {
  const Grid g;
  const Health h = scanHealth(g.topo, g.cloth, g.x, g.v);
  EXPECT_TRUE(h.ok());
  EXPECT_EQ(h.first_point, -1);
  EXPECT_EQ(h.describe(), "");
}

TEST(Health, NonFiniteDisplacementAloneIsFlagged) {
  Grid g;
  g.v[9].y = std::numeric_limits<double>::quiet_NaN();
  const Health h = scanHealth(g.topo, g.cloth, g.x, g.v);
  EXPECT_EQ(h.flags, Health::kNonFinite);
  EXPECT_EQ(h.first_point, 9);
  EXPECT_NE(h.describe().find("non-finite"), std::string::npos) << h.describe();
}

TEST(Health, TheSaneBoundIsPerAxisAndExclusive) {
  Grid g;
  const HealthLimits limits{.sane_bound = 2.0, .max_strain = 1e9};  // strain out of the way
  g.x[5].z = -2.0;                                                  // on the bound: sane
  EXPECT_TRUE(scanHealth(g.topo, g.cloth, g.x, g.v, limits).ok());
  g.x[5].z = -2.001;
  const Health h = scanHealth(g.topo, g.cloth, g.x, g.v, limits);
  EXPECT_EQ(h.flags, Health::kOutOfBounds);
  EXPECT_EQ(h.first_point, 5);
}

// Point 15 (grid corner (3, 3), at x = 1 m) moved along +x, away from point 14 (its structural
// neighbour on the left, rest 1/3 m): at 10.9 rest lengths the spring is inside 1 + 10, at 11.1 beyond.
TEST(Health, ASpringBeyondElevenRestLengthsFlagsBothEnds) {
  Grid g;
  const double rest = 1.0 / 3.0;
  g.x[15].x = g.x[14].x + 10.9 * rest;
  EXPECT_TRUE(scanHealth(g.topo, g.cloth, g.x, g.v).ok());
  g.x[15].x = g.x[14].x + 11.1 * rest;
  Health h = scanHealth(g.topo, g.cloth, g.x, g.v);
  EXPECT_EQ(h.flags, Health::kOverstretched);
  // Only 14-15 is beyond: 15 sits 10.1 rest lengths right of 11 and 7, so 15-11 is sqrt(10.1^2 + 1) = 10.15
  // rest lengths, the diagonal 15-10 sqrt(11.1^2 + 1) / sqrt(2) = 7.9, the bending springs 6.05 and 5.1.
  EXPECT_EQ(h.first_point, 14);
  // The same spring, its type disabled, is not checked.
  g.cloth.enable_structural = false;
  g.topo = buildTopology(g.cloth);
  h = scanHealth(g.topo, g.cloth, g.x, g.v);
  EXPECT_TRUE(h.ok()) << h.describe();
}

TEST(Health, TheCpuSolverReportsTheStateItHolds) {
  Scene scene;
  scene.cloth.num_width_points = 4;
  scene.cloth.num_height_points = 4;
  CpuSolver<float> cpu(scene);
  EXPECT_TRUE(cpu.health().ok());
  std::vector<glm::dvec3> x = cpu.topology().initial_positions, v(x.size(), glm::dvec3(0));
  x[3].y = std::numeric_limits<double>::quiet_NaN();  // NaN: no spring compares as longer, only 3 is flagged
  cpu.setState(x, v);
  EXPECT_EQ(cpu.health().flags, Health::kNonFinite);
  EXPECT_EQ(cpu.health().first_point, 3);
  EXPECT_EQ(cpu.deviceMemoryBytes(), -1);
}

// A cloth large enough that health() splits its scan between two threads: the parts merge to the answer of
// scanHealth over the state read back, flag by flag and first point, whichever part found what.
TEST(Health, ASplitScanMergesToTheWholeScansAnswer) {
  Scene scene;
  scene.cloth.num_width_points = 128;
  scene.cloth.num_height_points = 128;
  CpuSolver<float> cpu(scene, CpuSolverOptions{.threads = 2});
  const std::vector<glm::dvec3> rest = cpu.topology().initial_positions;
  const auto check = [&](const std::vector<glm::dvec3>& x, const std::vector<glm::dvec3>& v, unsigned flags,
                         long long first) {
    cpu.setState(x, v);
    const Health split = cpu.health(),
                 whole = scanHealth(cpu.topology(), scene.cloth, cpu.readPositions(), cpu.readDisplacements());
    EXPECT_EQ(split.flags, flags);
    EXPECT_EQ(split.first_point, first);
    EXPECT_EQ(split.flags, whole.flags);
    EXPECT_EQ(split.first_point, whole.first_point);
    EXPECT_EQ(split.substeps, cpu.substeps());
  };
  std::vector<glm::dvec3> x = rest, v(x.size(), glm::dvec3(0));
  check(x, v, 0, -1);
  // Only in the second half of the points and springs: the first part finds nothing. The point beyond the
  // bound also stretches its springs, the first of them from two rows above it (a bending spring).
  const std::size_t late = x.size() - 200;
  v[late].x = std::numeric_limits<double>::infinity();
  check(x, v, Health::kNonFinite, (long long)late);
  x[late + 50].z = 2e5;
  check(x, v, Health::kNonFinite | Health::kOutOfBounds | Health::kOverstretched, (long long)(late + 50 - 2 * 128));
  // Point 10 of the first row moved 5 m: its springs (the first from 8, a bending spring) flag both ends.
  x[10] += glm::dvec3(0, 5.0, 0);
  check(x, v, Health::kNonFinite | Health::kOutOfBounds | Health::kOverstretched, 8);
}

// The float quick look says healthy only where the scan finds nothing: states around each limit (a spring a
// few float steps either side of eleven rest lengths, a coordinate either side of the bound, NaN and infinity),
// and the resting cloth, which it must pass.
TEST(Health, TheQuickLookPassesOnlyWhatTheScanFindsHealthy) {
  Grid g;
  const QuickHealth q = quickHealth(g.topo, g.cloth);
  ASSERT_TRUE(q.usable);
  const auto floats = [](const std::vector<glm::dvec3>& p) { return std::vector<glm::vec3>(p.begin(), p.end()); };
  const auto agrees = [&](const std::vector<glm::dvec3>& x, const std::vector<glm::dvec3>& v) {
    const std::vector<glm::vec3> xf = floats(x), vf = floats(v);
    const Health scan = scanHealthPart(g.topo, g.cloth, xf, vf, HealthLimits{}, 0, xf.size(), 0, g.topo.springs.size());
    const bool quick = quickHealthy(q, xf, vf, 0, xf.size(), 0, g.topo.springs.size());
    return !quick || scan.ok();
  };
  EXPECT_TRUE(quickHealthy(q, floats(g.x), floats(g.v), 0, g.x.size(), 0, g.topo.springs.size()));
  int passed = 0, flagged = 0;
  const double most = 11.0 / 3.0;  // structural spring 14-15 at eleven rest lengths
  for (int step = -40; step <= 40; ++step) {
    Grid s;
    s.x[15].x = double(std::nextafter(float(s.x[14].x + most), step < 0 ? 0.0f : 100.0f));
    for (int k = 1; k < std::abs(step); ++k)
      s.x[15].x = double(std::nextafter(float(s.x[15].x), step < 0 ? 0.0f : 100.0f));
    ASSERT_TRUE(agrees(s.x, s.v)) << "step " << step;
    const std::vector<glm::vec3> xf = floats(s.x), vf = floats(s.v);
    passed += quickHealthy(q, xf, vf, 0, xf.size(), 0, s.topo.springs.size());
    flagged += !scanHealthPart(s.topo, s.cloth, xf, vf, HealthLimits{}, 0, xf.size(), 0, s.topo.springs.size()).ok();
  }
  EXPECT_GT(flagged, 0) << "the steps must cross the limit";
  const double bound = HealthLimits{}.sane_bound;
  for (const double at : {bound, std::nextafter(bound, 2 * bound), 2 * bound, std::numeric_limits<double>::infinity(),
                          std::numeric_limits<double>::quiet_NaN()}) {
    Grid s;
    s.x[5].z = -at;
    ASSERT_TRUE(agrees(s.x, s.v)) << at;
    s = Grid();
    s.v[5].y = at;
    ASSERT_TRUE(agrees(s.x, s.v)) << at;
  }
  // Far from the limit the quick look does pass a stretched cloth: it is not the scan in disguise
  Grid s;
  s.x[15].x = s.x[14].x + 5.0 / 3.0;
  EXPECT_TRUE(quickHealthy(q, floats(s.x), floats(s.v), 0, s.x.size(), 0, s.topo.springs.size()));
  EXPECT_GT(passed, 0) << "springs a few dozen float steps inside the limit must pass: the margin is 2^-20";
}

// The quick look's runs on a vertical cloth (its jitter spreads the rest lengths) with its shearing springs off:
// every enabled spring in exactly one run, in order, each run's limit the least of its springs' and within
// kRunSpread of every one; a grid's direction along a row is one run. Split into parts anywhere, the look agrees
// with the whole, and one spring of a run just beyond its own limit, in any part, fails the part that holds it.
TEST(Health, TheQuickLooksRunsHoldEveryEnabledSpringOnceUnderItsOwnLimit) {
  ClothSpec cloth;
  cloth.num_width_points = 12;
  cloth.num_height_points = 9;
  cloth.orientation = Orientation::Vertical;
  cloth.enable_shearing = false;
  const Topology topo = buildTopology(cloth);
  const QuickHealth q = quickHealth(topo, cloth);
  ASSERT_TRUE(q.usable);
  std::size_t next = 0;  // the next enabled spring
  const auto limit2 = [&](const Spring& s) { return float(11.0 * s.rest * 11.0 * s.rest * (1.0 - 0x1p-20)); };
  for (const QuickHealth::Run& run : q.runs) {
    while (next < topo.springs.size() && !cloth.springEnabled(topo.springs[next].type))
      ++next;
    ASSERT_EQ(run.first, next);
    ASSERT_GE(run.count, 1u);
    for (std::uint32_t k = 0; k < run.count; ++k) {
      const Spring& s = topo.springs[run.first + k];
      ASSERT_TRUE(cloth.springEnabled(s.type));
      EXPECT_EQ(s.a, run.a + k);
      EXPECT_EQ(std::int64_t(s.b), std::int64_t(s.a) + run.step);
      EXPECT_LE(run.limit2, limit2(s));
      EXPECT_LE(double(limit2(s)), double(run.limit2) * (1 + QuickHealth::kRunSpread));
    }
    next = run.first + run.count;
  }
  while (next < topo.springs.size() && !cloth.springEnabled(topo.springs[next].type))
    ++next;
  EXPECT_EQ(next, topo.springs.size());
  // The horizontal structural and bending springs a run a row (the next row's first end is not the last's next
  // point); the vertical ones go on from row to row: one run each
  EXPECT_EQ(q.runs.size(), std::size_t(9 + 1 + 9 + 1));
  std::vector<glm::vec3> x(topo.initial_positions.begin(), topo.initial_positions.end()), v(x.size(), glm::vec3(0));
  const std::size_t n = x.size(), springs = topo.springs.size();
  for (std::size_t cut = 0; cut <= springs; cut += 7)
    EXPECT_TRUE(quickHealthy(q, x, v, 0, n, 0, cut) && quickHealthy(q, x, v, 0, n, cut, springs)) << cut;
  // Spring 40's end b moved along it to 11 rest lengths from a: beyond its limit, which the run's holds too
  const Spring& s = topo.springs[40];
  ASSERT_TRUE(cloth.springEnabled(s.type));
  x[s.b] = x[s.a] + (x[s.b] - x[s.a]) * 11.0f;
  EXPECT_FALSE(quickHealthy(q, x, v, 0, n, 0, springs));
  for (std::size_t cut = 0; cut <= springs; cut += 5) {
    const bool low = quickHealthy(q, x, v, 0, n, 0, cut), high = quickHealthy(q, x, v, 0, n, cut, springs);
    EXPECT_EQ(low, cut <= 40) << cut;
    EXPECT_EQ(high, cut > 40) << cut;
  }
}

// The grid path's quick look (GridPath::healthy, each instruction set) on cloths of 4 x 4 and 37 x 23 points, their
// bending springs on and off: where it passes a state the scan finds nothing, and it passes every state the look on
// the vec3s passes (its limits are each spring's own, the runs' the least of theirs). States: one point moved up to
// twelve spacings along x (either side of eleven rest lengths), a coordinate past the bound, NaN and infinity in a
// position or a displacement, each at a random point (the rows' ends and the last rows too), over a jittered cloth.
TEST(Health, TheGridPathsQuickLookPassesOnlyWhatTheScanFindsHealthy) {
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  for (const auto& [w, h] : {std::pair{4, 4}, std::pair{37, 23}})
    for (const bool bending : {true, false}) {
      ClothSpec cloth;
      cloth.num_width_points = w;
      cloth.num_height_points = h;
      cloth.enable_bending = bending;
      const Topology topo = buildTopology(cloth);
      const QuickHealth q = quickHealth(topo, cloth);
      ASSERT_TRUE(q.usable);
      std::vector<float> rest(topo.springs.size());
      for (std::size_t k = 0; k < rest.size(); ++k)
        rest[k] = float(topo.springs[k].rest);
      const double spacing = 1.0 / double(w - 1);
      for (const GridIsa isa : test::cpuIsas()) {
        GridPath path(topo, rest, isa);
        path.setHealthLimits(topo, cloth);
        std::mt19937 random(7);
        std::uniform_int_distribution<std::size_t> point(0, topo.initial_positions.size() - 1);
        std::uniform_real_distribution<double> unit(-1.0, 1.0), stretch(0.5, 12.0);
        int passed = 0, failed = 0;
        for (int trial = 0; trial < 400; ++trial) {
          std::vector<glm::vec3> x(topo.initial_positions.size()), v(x.size(), glm::vec3(0));
          for (std::size_t i = 0; i < x.size(); ++i)
            x[i] = glm::vec3(topo.initial_positions[i] +
                             0.05 * spacing * glm::dvec3(unit(random), unit(random), unit(random)));
          const std::size_t at = point(random);
          switch (trial % 6) {
            case 0:
              x[at].x += float(stretch(random) * spacing);
              break;
            case 1:
              x[at].y = float(HealthLimits{}.sane_bound * (1.0 + 1e-6 * unit(random)));
              break;
            case 2:
              x[at].z = float(trial % 12 < 6 ? nan : -inf);
              break;
            case 3:
              v[at].x = float(trial % 12 < 6 ? nan : inf);
              break;
            case 4:
              v[at].y = 1e30f;
              break;
            default:
              break;  // the jittered cloth alone
          }
          path.loadState(x, v);
          const bool grid = path.healthy(q.bound);
          const bool vec3s = quickHealthy(q, x, v, 0, x.size(), 0, topo.springs.size());
          const Health scan = scanHealthPart(topo, cloth, x, v, HealthLimits{}, 0, x.size(), 0, topo.springs.size());
          ASSERT_TRUE(!grid || scan.ok()) << w << " x " << h << ", trial " << trial << ", point " << at;
          ASSERT_TRUE(!vec3s || grid) << w << " x " << h << ", trial " << trial << ", point " << at;
          (grid ? passed : failed) += 1;
        }
        EXPECT_GT(passed, 100) << w << " x " << h;
        EXPECT_GT(failed, 100) << w << " x " << h;
      }
    }
}

// A cloth that blows up (CS184's pinned2 at 40 x 40, ks 10^8, 3 substeps a frame): health() on the grid path, which
// looks at the arrays first and falls back to the scan, answers frame by frame as the general path's scan, flags and
// first point, through the frames where it first flags.
TEST(Health, TheGridPathAnswersAsTheScanThroughABlowUp) {
  Scene scene;
  scene.cloth.num_width_points = scene.cloth.num_height_points = 40;
  scene.cloth.ks = 1e8;
  scene.cloth.pinned = {{0, 0}, {39, 0}};
  scene.sim.steps_per_frame = 3;
  CpuSolver<float> grid(scene, CpuSolverOptions{.threads = 1}),
      general(scene, CpuSolverOptions{.threads = 1, .grid_path = false});
  int flagged = 0, in_arrays = 0;
  for (int frame = 0; frame < 60 && flagged < 3; ++frame) {
    grid.stepFrame();
    general.stepFrame();
    in_arrays += grid.positionsInArrays();
    const Health g = grid.health(), s = general.health();
    ASSERT_EQ(g.flags, s.flags) << "frame " << frame;
    ASSERT_EQ(g.first_point, s.first_point) << "frame " << frame;
    flagged += !s.ok();
  }
  EXPECT_GT(flagged, 0) << "the cloth must blow up";
  EXPECT_GT(in_arrays, 0) << "the grid path must leave the points in its arrays";
}

}  // namespace
}  // namespace drape
