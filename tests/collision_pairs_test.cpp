// Self-collision by candidate lists (src/cpu/collision_pairs.hpp): every pair in range is listed at
// every substep, whenever the list was built, and the sum visits the pairs in the order of the 27-cell
// grid query it replaced, so the bytes are those of the grid query.
#include "cpu/collision_pairs.hpp"
#include "core/colouring.hpp"
#include "core/scene.hpp"
#include "cpu/cpu_solver.hpp"
#include "cpu/grid_kernels.hpp"
#include "cpu/parallel.hpp"
#include "kernel_sets.hpp"
#include "test_paths.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <set>
#include <utility>
#include <vector>

namespace drape {
namespace {

using vec3 = glm::vec3;

Scene cs184Scene(const std::string& name) {
  Scene scene = loadScene(std::string(drape::test::sourceDir()) + "/scenes/" + name);
  scene.sim.self_collision = true;  // as CS184 runs every scene
  return scene;
}

// The grid query the lists replaced: all 27 cells of a grid of cell size 2*thickness, cells in z, y, x
// order, ascending index within a cell. Its sum is the reference the lists must reproduce bit for bit.
vec3 gridQueryCorrection(const HashGrid<float>& grid, const std::vector<vec3>& x, std::size_t i, float thickness,
                         float steps) {
  vec3 sum(0);
  int count = 0;
  grid.forEachCandidate(i, [&](std::uint32_t j) {
    const vec3 c = physics::selfCollisionCorrection(x[i], x[j], thickness);
    if (c != vec3(0)) {
      sum += c;
      ++count;
    }
  });
  return count > 0 ? sum / (float(count) * steps) : vec3(0);
}

vec3 listCorrection(const CollisionPairs<float>& pairs, const std::vector<vec3>& x, std::size_t i, float thickness,
                    float steps) {
  vec3 sum(0);
  int count = 0;
  forEachOrderedPair(pairs, i, x, thickness, 1.0f / (2.0f * thickness), [&](vec3 c) {
    sum += c;
    ++count;
  });
  return count > 0 ? sum / (float(count) * steps) : vec3(0);
}

bool sameBits(vec3 a, vec3 b) {
  return std::memcmp(&a, &b, sizeof(vec3)) == 0;
}

struct PairCase {
  const char* name;
  const char* scene;
  double margin;  // in units of 2*thickness
  int warmup;     // frames run before the checks start
  int frames;     // frames checked, every substep
};

class CollisionPairsCase : public ::testing::TestWithParam<PairCase> {};

// Every substep of a falling, folding and crumpling cloth: the pairs in range are all listed (checked
// against brute force over all pairs), and each point's correction equals the grid query's, bit for bit,
// both the ordered sweep's and the solver's own (CpuSolver::selfCollide sums a pair at a time).
TEST_P(CollisionPairsCase, ListsEveryPairInRangeAndSumsInTheGridOrder) {
  const PairCase pc = GetParam();
  const Scene scene = cs184Scene(pc.scene);
  CpuSolver<float> solver(scene,
                          CpuSolverOptions{.threads = 1, .pair_margin = pc.margin, .keep_self_corrections = true});
  const float thickness = float(scene.cloth.thickness);
  const float range = 2.0f * thickness;
  const float steps = float(scene.sim.steps_per_frame);
  CollisionPairs<float> pairs;
  pairs.configure(range, range * float(pc.margin));
  HashGrid<float> grid;
  for (int f = 0; f < pc.warmup; ++f)
    solver.stepFrame();
  long long checked = 0, before_rebuild = 0, pairs_in_range = 0;
  bool previous_checked_without_rebuild = false;
  std::vector<std::uint32_t> by_x;
  for (int s = 0; s < pc.frames * scene.sim.steps_per_frame; ++s) {
    solver.accumulateForces();
    solver.integrate();
    const std::vector<vec3>& x = solver.positions();
    const bool rebuilt = pairs.update(x, 1);
    // The substep before this one used a list that was about to be rebuilt: the oldest a list gets.
    if (rebuilt && previous_checked_without_rebuild) ++before_rebuild;
    previous_checked_without_rebuild = !rebuilt;
    grid.build(x, range);
    // Every pair in range, by a sweep along x instead of all n^2 pairs (the same pairs: two points in range
    // are in range along x; under ASan the n^2 loop took 6 of CI's minutes), each end's list holding the other.
    by_x.resize(x.size());
    for (std::uint32_t i = 0; i < by_x.size(); ++i)
      by_x[i] = i;
    std::sort(by_x.begin(), by_x.end(), [&](std::uint32_t a, std::uint32_t b) { return x[a].x < x[b].x; });
    const auto listed = [&](std::uint32_t i, std::uint32_t j) {
      return std::find(pairs.begin(i), pairs.end(i), j) != pairs.end(i);
    };
    for (std::size_t a = 0; a < by_x.size(); ++a)
      for (std::size_t b = a + 1; b < by_x.size() && x[by_x[b]].x - x[by_x[a]].x <= range; ++b) {
        const std::uint32_t i = by_x[a], j = by_x[b];
        if (physics::selfCollisionCorrection(x[i], x[j], thickness) == vec3(0)) continue;
        pairs_in_range += 2;
        ASSERT_TRUE(listed(i, j) && listed(j, i)) << "substep " << s << ": pair " << i << "-" << j << " in range "
                                                  << "but not listed (list built " << pairs.rebuilds() << " times)";
      }
    std::vector<vec3> expected_all(x.size());  // what the solver's own pass must add: the grid query's sum
    for (std::size_t i = 0; i < x.size(); ++i) {
      const vec3 expected = gridQueryCorrection(grid, x, i, thickness, steps);
      const vec3 got = listCorrection(pairs, x, i, thickness, steps);
      ASSERT_TRUE(sameBits(expected, got)) << "substep " << s << ", point " << i;
      expected_all[i] = expected;
    }
    ++checked;
    solver.selfCollide();  // its lists, stencil and pair-at-a-time sum
    for (std::size_t i = 0; i < x.size(); ++i)
      ASSERT_TRUE(sameBits(solver.selfCorrections()[i], expected_all[i]))
          << "the solver's sum, substep " << s << ", point " << i;
    solver.collide();
    solver.limitStretch();
  }
  EXPECT_GT(pairs_in_range, 0) << "the case must bring points into range";
  EXPECT_GT(before_rebuild, 0) << "the case must check lists just before their rebuild";
  EXPECT_LT(pairs.rebuilds(), checked) << "the lists must outlive a substep";
  std::printf("[ %s ] %lld substeps, %lld rebuilds, %lld pairs in range\n", pc.name, checked, pairs.rebuilds(),
              pairs_in_range);
}

// selfCollision falls and crumples onto the plane (its first 40 frames), settles in folds, then lies
// folded on it; a thin skin rebuilds almost every substep.
INSTANTIATE_TEST_SUITE_P(Cloths, CollisionPairsCase,
                         ::testing::Values(PairCase{"falling_crumpling", "selfCollision.json", kDefaultPairMargin, 0,
                                                    40},
                                           PairCase{"folded", "selfCollision.json", kDefaultPairMargin, 150, 10},
                                           PairCase{"settling", "selfCollision.json", kDefaultPairMargin, 60, 10},
                                           PairCase{"thin_margin", "selfCollision.json", 0.1, 20, 20}),
                         [](const auto& test) { return std::string(test.param.name); });

// A build by cell (the grid's order, a cell's candidates copied into one run) lists the pairs a build by point
// does: the folding selfCollision cloth and pinned2 refined to 100 x 100 with CS184's thickness (many points a
// cell), without the kernels and with each instruction set's, at several substeps.
TEST(CollisionPairs, ABuildByCellListsWhatABuildByPointDoes) {
  Scene folding = cs184Scene("selfCollision.json");
  Scene fine = cs184Scene("pinned2.json");
  fine.cloth.num_width_points = fine.cloth.num_height_points = 100;
  fine.cloth.pinned = {{0, 0}, {99, 0}};
  for (const Scene* scene : {&folding, &fine}) {
    CpuSolver<float> solver(*scene, CpuSolverOptions{.threads = 1});
    const float range = 2.0f * float(scene->cloth.thickness);
    const std::vector<vec3> rest(solver.topology().initial_positions.begin(),
                                 solver.topology().initial_positions.end());
    int compared = 0;
    for (int f = 0; f < 40; ++f) {
      solver.stepFrame();
      if (f % 8 != 7) continue;
      const std::vector<vec3>& x = solver.positions();
      const auto lists = [&](CollisionPairs<float>::BuildOrder order, const GridKernels* kernels) {
        CollisionPairs<float> pairs;
        pairs.setRest(rest);
        pairs.setGrid(solver.topology().W, solver.topology().H);
        pairs.setKernels(kernels);
        pairs.setBuildOrder(order);
        pairs.configure(range, 0.75f * range);
        EXPECT_TRUE(pairs.update(x, 1));
        // A point's entries in the order its pairs were found, which the sums do not depend on: as a set, each
        // with its part. A near entry is closer than the range and half the skin, a far one not (farNeeded's
        // proof), and every entry is its owner's, with a partner above it.
        const float near2 = (range + 0.5f * pairs.margin()) * (range + 0.5f * pairs.margin());
        std::vector<std::array<std::uint32_t, 3>> out;
        for (std::uint32_t far = 0; far < 2; ++far) {
          const auto& part = far ? pairs.farEntries() : pairs.nearEntries();
          for (std::size_t i = 0; i < x.size(); ++i)
            for (std::uint32_t k = part.start[i]; k < part.start[i + 1]; ++k) {
              const std::uint32_t j = part.partner[k];
              EXPECT_EQ(part.owner[k], i);
              EXPECT_GT(j, i);
              EXPECT_EQ(glm::dot(x[i] - x[j], x[i] - x[j]) >= near2, far != 0) << i << "-" << j;
              out.push_back({std::uint32_t(i), j, far});
            }
        }
        std::sort(out.begin(), out.end());
        return out;
      };
      // Against the build point by point without the kernels: by cell without them, and both ways with each set
      const auto by_point = lists(CollisionPairs<float>::BuildOrder::ByPoint, nullptr);
      EXPECT_EQ(lists(CollisionPairs<float>::BuildOrder::ByCell, nullptr), by_point) << "frame " << f;
      for (const GridKernels* kernels : test::kernelSets())
        for (const auto order : {CollisionPairs<float>::BuildOrder::ByPoint, CollisionPairs<float>::BuildOrder::ByCell})
          EXPECT_EQ(lists(order, kernels), by_point) << kernels->name << ", frame " << f;
      compared += by_point.empty() ? 0 : 1;
    }
    EXPECT_GT(compared, 0) << "no build listed a pair: the case compares nothing";
  }
}

TEST(CollisionPairs, MarginZeroRebuildsEverySubstep) {
  CollisionPairs<float> pairs;
  pairs.configure(0.02f, 0.0f);
  std::vector<vec3> x = {{0, 0, 0}, {0.01f, 0, 0}};
  EXPECT_TRUE(pairs.update(x, 1));
  EXPECT_TRUE(pairs.update(x, 1)) << "no skin: nothing may be reused";
}

// The list is reused while no two points can have drawn together by the margin since it was built: a
// motion all points share costs nothing, a motion of some against the others does.
TEST(CollisionPairs, ReusesTheListUntilTwoPointsMayHaveDrawnTogetherByTheMargin) {
  CollisionPairs<float> pairs;
  pairs.configure(0.02f, 0.01f);
  std::vector<vec3> x = {{0, 0, 0}, {0.025f, 0, 0}, {1, 0, 0}};
  ASSERT_TRUE(pairs.update(x, 1));
  EXPECT_EQ(pairs.pairCount(), 2u) << "0 and 1 are within range + margin (0.03), 2 is not";
  for (vec3& p : x)
    p += vec3(0.003f, 0.007f, -0.004f);  // 8.6 mm, all together: over half the margin, yet no pair moved
  EXPECT_FALSE(pairs.update(x, 1));
  x[1].x += 0.004f;  // 4 mm against the others
  EXPECT_FALSE(pairs.update(x, 1));
  x[2].x -= 0.0061f;  // 1 and 2 now 10.1 mm apart in their displacements: over the margin
  EXPECT_TRUE(pairs.update(x, 1));
  EXPECT_FALSE(pairs.update(x, 1)) << "rebuilt where the points are";
  x[0].x = std::numeric_limits<float>::quiet_NaN();  // a blown-up point forces a rebuild
  EXPECT_TRUE(pairs.update(x, 1));
}

// A pair listed further apart than the range and half the margin (a far entry) is passed over by the solver's
// sweep only while no two points can have come that much closer: here two points drawn together from just beyond
// that to just within range, as far as the check lets them without a rebuild, must make the far entries needed.
TEST(CollisionPairs, TheFarEntriesAreNeededOnceAPairCanHaveComeWithinRange) {
  CollisionPairs<float> pairs;
  const float range = 0.02f, margin = 0.015f;
  pairs.configure(range, margin);
  const float apart = range + 0.55f * margin;  // within range + margin (listed), beyond range + margin / 2 (far)
  std::vector<vec3> x = {{0, 0, 0}, {apart, 0, 0}, {1, 0, 0}};
  ASSERT_TRUE(pairs.update(x, 1));
  ASSERT_EQ(pairs.pairCount(), 2u);
  ASSERT_EQ(pairs.farEntries().start.back(), 1u) << "the pair is a far entry";
  EXPECT_FALSE(pairs.farNeeded(true)) << "at the build no far entry is within range";
  EXPECT_FALSE(pairs.update(x, 1));
  EXPECT_FALSE(pairs.farNeeded(false)) << "nothing moved";
  const float close = apart - 0.99f * range;  // the two ends drawn together by this much: 0.99 of the range apart
  x[0].x += 0.5f * close;
  x[1].x -= 0.5f * close;
  ASSERT_FALSE(pairs.update(x, 1)) << "the check keeps the list (the motion is under the margin)";
  EXPECT_TRUE(pairs.farNeeded(false)) << "the pair is within range now: its entry must be tested";
  x[0].x -= 0.3f * close;  // back to 0.4 of the motion: the range and that do not reach range + margin / 2
  x[1].x += 0.3f * close;
  ASSERT_FALSE(pairs.update(x, 1));
  EXPECT_FALSE(pairs.farNeeded(false)) << "no far entry can be within range: passed over again";
}

// A bump raised at a corner of a 64 x 64 grid, higher than the skin: the boxes of the corner's tiles and of their
// neighbours span more than that, but its slope moves no two points within reach of each other apart by the skin.
// A closer look at those tiles (CollisionPairs::tilesHold) keeps the lists; the same bump raised steeply, where two
// such points do move apart by the skin, is rebuilt. With the kernels and without.
TEST(CollisionPairs, ACloserLookKeepsTheListsUnderAGentleBumpAndNotUnderASteepOne) {
  constexpr int n = 64;  // tiles of 8 x 8 points
  const float spacing = 0.01f, range = 0.019f, margin = 0.006f, height = 0.012f;
  std::vector<vec3> rest;
  for (int v = 0; v < n; ++v)
    for (int u = 0; u < n; ++u)
      rest.push_back(vec3(float(u) * spacing, 0.0f, float(v) * spacing));
  const auto bump = [&](float radius) {  // a cone over point (0, 0), `radius` spacings wide
    std::vector<vec3> x = rest;
    for (int v = 0; v < n; ++v)
      for (int u = 0; u < n; ++u)
        x[std::size_t(v * n + u)].y += height * std::max(0.0f, 1.0f - std::hypot(float(u), float(v)) / radius);
    return x;
  };
  for (const bool kernels : {false, true}) {
    SCOPED_TRACE(kernels ? "kernels" : "scalar");
    const auto built = [&](CollisionPairs<float>& pairs) {
      pairs.configure(range, margin);
      pairs.setRest(rest);
      pairs.setGrid(n, n);
      if (kernels) pairs.setKernels(&gridKernels(GridIsa::Auto));
      ASSERT_TRUE(pairs.update(rest, 1));
    };
    // 20 spacings wide: 0.6 mm a spacing, 1.4 mm between points within reach (22 mm), 7.7 mm across tiles 0 and 1
    CollisionPairs<float> gentle;
    built(gentle);
    EXPECT_FALSE(gentle.update(bump(20), 1)) << "no two points within reach moved apart by the skin";
    EXPECT_EQ(gentle.closerLooksKept(), 1) << "the tiles' boxes called for a build, the closer look spared it";
    EXPECT_FALSE(gentle.update(bump(20), 1));
    EXPECT_EQ(gentle.closerLooksKept(), 2);
    // 2 spacings wide: points (0, 0) and (1, 1), 16.5 mm apart, moved 8.5 mm against each other
    CollisionPairs<float> steep;
    built(steep);
    EXPECT_TRUE(steep.update(bump(2), 1)) << "two points within reach moved apart by more than the skin";
    EXPECT_EQ(steep.closerLooksKept(), 0);
  }
}

TEST(CollisionPairs, CellOrderFollowsTheQueryAndDropsCellsOutsideIt) {
  EXPECT_EQ(cellOrder({5, 5, 5}, {4, 4, 4}), 0);
  EXPECT_EQ(cellOrder({5, 5, 5}, {5, 5, 5}), 13);
  EXPECT_EQ(cellOrder({5, 5, 5}, {6, 5, 5}), 14);
  EXPECT_EQ(cellOrder({5, 5, 5}, {5, 6, 5}), 16);
  EXPECT_EQ(cellOrder({5, 5, 5}, {6, 6, 6}), 26);
  EXPECT_EQ(cellOrder({5, 5, 5}, {7, 5, 5}), -1);
}

TEST(HashGridCells, NonFiniteAndHugeCoordinatesStayInsideInt) {
  const float inf = std::numeric_limits<float>::infinity();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(HashGrid<float>::cellOf({nan, inf, -inf}, 50.0f), glm::ivec3(0, 1 << 30, -(1 << 30)));
  EXPECT_EQ(HashGrid<float>::cellOf({3e38f, -3e38f, 0.0f}, 50.0f), glm::ivec3(1 << 30, -(1 << 30), 0));
}

// A point with more terms than forEachOrderedPair holds (a cloth crushed into a ball) is summed by its sweep
// per cell order: the same bytes as the grid query.
TEST(CollisionPairs, PointsWithManyTermsSumInTheGridOrderToo) {
  const float thickness = 0.01f, range = 2.0f * thickness;
  std::vector<vec3> x;
  for (int k = 0; k < 60;
       ++k)  // 60 points spread over a few cells of edge `range`, straddling cell borders, all in range
    x.emplace_back(0.51f + 0.004f * float(k % 4), 0.295f + 0.003f * float(k / 4 % 4), 0.695f + 0.002f * float(k / 16));
  CollisionPairs<float> pairs;
  pairs.configure(range, range * float(kDefaultPairMargin));
  pairs.update(x, 1);
  HashGrid<float> grid;
  grid.build(x, range);
  int many = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    int terms = 0;
    forEachOrderedPair(pairs, i, x, thickness, 1.0f / range, [&](vec3) { ++terms; });
    many += terms > 24;
    EXPECT_TRUE(
        sameBits(gridQueryCorrection(grid, x, i, thickness, 30.0f), listCorrection(pairs, x, i, thickness, 30.0f)))
        << "point " << i;
  }
  EXPECT_EQ(many, 60) << "every point must have more terms than are held";
}

// The solver's own sum on the same crushed ball, in float and double: every point has dozens of terms, many
// in one cell, so their order within a cell (ascending partner) decides the bits as much as the cells' order.
template <class T>
void expectTheSolversSumIsTheGridQuerys() {
  using v3 = glm::vec<3, T>;
  Scene scene;
  scene.cloth.num_width_points = 6;  // 60 points 0.11 m or more apart at rest: no pair held, no stencil
  scene.cloth.num_height_points = 10;
  scene.cloth.thickness = 0.01;
  scene.sim.self_collision = true;
  scene.sim.steps_per_frame = 30;
  std::vector<glm::dvec3> x;
  for (int k = 0; k < 60; ++k)  // the ball above, off its lattice (a lattice's terms cancel in any order)
    x.emplace_back(0.51 + 0.004 * (k % 4) + 0.0007 * std::sin(1.3 * k),
                   0.295 + 0.003 * (k / 4 % 4) + 0.0005 * std::cos(0.7 * k),
                   0.695 + 0.002 * (k / 16) + 0.0003 * std::sin(2.9 * k));
  CpuSolver<T> solver(scene, CpuSolverOptions{.threads = 1, .keep_self_corrections = true});
  solver.setState(x, std::vector<glm::dvec3>(x.size(), glm::dvec3(0)));
  const std::vector<v3> before = solver.positions();
  HashGrid<T> grid;
  grid.build(before, T(0.02));
  solver.selfCollide();
  for (std::size_t i = 0; i < before.size(); ++i) {
    v3 sum(0);
    int count = 0;
    grid.forEachCandidate(i, [&](std::uint32_t j) {
      const v3 c = physics::selfCollisionCorrection(before[i], before[j], T(0.01));
      if (c != v3(0)) {
        sum += c;
        ++count;
      }
    });
    ASSERT_GT(count, 24);
    const v3 expected = sum / (T(count) * T(30));
    EXPECT_EQ(std::memcmp(&expected, &solver.selfCorrections()[i], sizeof(v3)), 0) << "point " << i;
    const v3 moved = before[i] + expected;
    EXPECT_EQ(std::memcmp(&moved, &solver.positions()[i], sizeof(v3)), 0) << "point " << i;
  }
  // Without keep_self_corrections nothing is kept, and the points move the same
  CpuSolver<T> plain(scene, CpuSolverOptions{.threads = 1});
  plain.setState(x, std::vector<glm::dvec3>(x.size(), glm::dvec3(0)));
  plain.selfCollide();
  EXPECT_TRUE(plain.selfCorrections().empty());
  EXPECT_EQ(std::memcmp(plain.positions().data(), solver.positions().data(), sizeof(v3) * x.size()), 0);
}

TEST(CollisionPairs, TheSolversSumOrdersManyTermsAsTheGridQuery) {
  expectTheSolversSumIsTheGridQuerys<float>();
  expectTheSolversSumIsTheGridQuerys<double>();
}

// Threads share the per-point loops; each point's arithmetic is the same whoever runs it.
TEST(CpuSolverThreads, OneAndTwoThreadsComputeTheSameBytes) {
  for (const char* name : {"selfCollision.json", "sphere.json", "wind.json"}) {
    // 182 x 182 points: every per-point loop is long enough to be split between threads (kParallelItems).
    Scene scene = cs184Scene(name);
    scene.cloth.num_width_points = scene.cloth.num_height_points = 182;
    scene.cloth.pinned.clear();
    scene.cloth.thickness = 0.0025;  // under half the spacing, as bench's resampling keeps it
    ASSERT_GE(182 * 182, kParallelItems);
    CpuSolver<float> one(scene, CpuSolverOptions{.threads = 1});
    CpuSolver<float> two(scene, CpuSolverOptions{.threads = 2});
    for (int f = 0; f < 3; ++f) {
      one.stepFrame();
      two.stepFrame();
    }
    ASSERT_EQ(one.positions().size(), two.positions().size());
    EXPECT_EQ(std::memcmp(one.positions().data(), two.positions().data(), one.positions().size() * sizeof(vec3)), 0)
        << name;
    EXPECT_EQ(
        std::memcmp(one.displacements().data(), two.displacements().data(), one.positions().size() * sizeof(vec3)), 0)
        << name;
  }
}

// A grid's colouring by direction and parity is optimal: an interior point has 12 springs, and 12
// colours suffice. A mesh cloth's greedy colouring is held to the same rule.
TEST(SpringColouring, SpringsOfAColourShareNoPointAndAGridTakesTwelve) {
  Scene scene = cs184Scene("pinned2.json");
  const Topology topo = buildTopology(scene.cloth);
  const SpringColouring colouring = colourSprings(topo);
  EXPECT_EQ(colouring.colourCount(), 12);
  ASSERT_EQ(colouring.springs.size(), topo.springs.size());
  std::vector<int> seen(topo.springs.size(), 0);
  for (int c = 0; c < colouring.colourCount(); ++c) {
    std::set<std::uint32_t> points;
    for (std::uint32_t k = colouring.start[std::size_t(c)]; k < colouring.start[std::size_t(c) + 1]; ++k) {
      const Spring& s = topo.springs[colouring.springs[k]];
      EXPECT_TRUE(points.insert(s.a).second) << "colour " << c << " touches point " << s.a << " twice";
      EXPECT_TRUE(points.insert(s.b).second) << "colour " << c << " touches point " << s.b << " twice";
      ++seen[colouring.springs[k]];
    }
  }
  EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](int n) { return n == 1; })) << "each spring exactly once";
}

// gridColourReach is what the tiled stretch kernel copies around a block, so it must bound how far a
// change travels through the Gauss-Seidel passes: a point moved before them changes no point further
// away. Every spring is over the limit here (the grid scaled by 1.3), so each one carries changes on.
TEST(SpringColouring, GridReachBoundsHowFarTheStretchPassesCarryAChange) {
  Scene scene = cs184Scene("pinned2.json");
  scene.sim.self_collision = false;
  scene.cloth.num_width_points = scene.cloth.num_height_points = 40;
  scene.cloth.pinned = {{0, 0}, {39, 0}};  // the file's are for 50 x 50
  const Topology topo = buildTopology(scene.cloth);
  const SpringColouring colouring = colourSprings(topo);
  for (const int passes : {1, 2}) {
    scene.sim.stretch_passes = passes;
    const int reach = gridColourReach(topo, colouring, passes, 0b111);
    // Interior springs take 2 colours per direction; a colour carries a change one spring length on:
    // 1 step for structural and shearing springs, 2 for bending ones, in x: 2 + 4 + 4 = 10 a pass.
    if (passes == 1) {
      EXPECT_EQ(reach, 10);
    }
    CpuSolver<double> cpu(scene);
    std::vector<glm::dvec3> x = topo.initial_positions, v(x.size(), glm::dvec3(0.0));
    for (glm::dvec3& p : x)
      p *= 1.3;
    cpu.setState(x, v);
    cpu.limitStretch();
    const std::vector<glm::dvec3> base = cpu.readPositions();
    int farthest = 0;
    std::vector<glm::ivec2> sources = {{2, 30}, {39, 39}, {20, 1}};
    for (int sy = 20; sy < 24; ++sy)  // every phase of the colouring's period (bending springs: 4 points)
      for (int sx = 20; sx < 24; ++sx)
        sources.emplace_back(sx, sy);
    for (const glm::ivec2 at : sources) {
      std::vector<glm::dvec3> moved = x;
      moved[std::size_t(at.y * topo.W + at.x)] += glm::dvec3(1e-3, -2e-3, 1e-3);
      cpu.setState(moved, v);
      cpu.limitStretch();
      const std::vector<glm::dvec3> after = cpu.readPositions();
      for (int i = 0; i < topo.pointCount(); ++i) {
        if (after[std::size_t(i)] == base[std::size_t(i)]) continue;
        const int d = std::max(std::abs(i % topo.W - at.x), std::abs(i / topo.W - at.y));
        EXPECT_LE(d, reach) << "moving (" << at.x << ", " << at.y << ") changed point " << i;
        farthest = std::max(farthest, d);
      }
    }
    std::printf("%d stretch passes: reach %d, farthest change seen %d\n", passes, reach, farthest);
    EXPECT_EQ(farthest, reach) << "the bound is reached: one further out would copy points for nothing";
  }
}

}  // namespace
}  // namespace drape
