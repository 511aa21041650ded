// The self-collision stencil of a grid cloth (cpu/collision_pairs.hpp): the unheld pairs at the grid offsets
// just beyond the contact distance at rest are tested by offset every substep instead of listed. Nothing may
// fall between the stencil and the list, and the bytes are those of the list alone.
#include "core/scene.hpp"
#include "cpu/collision_pairs.hpp"
#include "cpu/cpu_solver.hpp"
#include "test_paths.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

namespace drape {
namespace {

using vec3 = glm::vec3;

// CS184's selfCollision scene (a cloth falling flat onto a plane, where it crumples) at n x n points with a
// contact distance of two spacings: the pairs two apart along a row sit exactly at the range at rest, where
// each pair's rounding decides whether it is held, and the knight's-move pairs (2.24 spacings) are the ring
// just beyond it.
Scene crumplingCloth(int n, double spacings = 1.0) {
  Scene scene = loadScene(std::string(drape::test::sourceDir()) + "/scenes/selfCollision.json");
  scene.sim.self_collision = true;
  scene.cloth.num_width_points = scene.cloth.num_height_points = n;
  scene.cloth.thickness = spacings * scene.cloth.width / double(n - 1);
  return scene;
}

// A flat cloth at rest with nothing to move it (every pair at an offset as far apart as the next), of 24 x 24 points
// in squares of 8 and a contact distance of 2.2 spacings
Scene stillFlatCloth() {
  Scene scene = crumplingCloth(24, 1.1);
  scene.cloth.orientation = Orientation::Horizontal;
  scene.sim.gravity = glm::dvec3(0);
  scene.cloth.damping = 0;
  scene.planes.clear();
  return scene;
}

// The lists built and the squares recorded at rest, then one substep in which only the points given a v move by it
void moveOnce(CpuSolver<float>& solver, const std::vector<glm::dvec3>& v) {
  solver.setState(solver.topology().initial_positions, v);
  solver.selfCollide();
  solver.accumulateForces();
  solver.integrate();
  solver.selfCollide();
}

bool onStencil(const CollisionPairs<float>& pairs, std::size_t i, std::size_t j) {
  const int w = pairs.gridWidth();
  const int du = int(j % std::size_t(w)) - int(i % std::size_t(w)),
            dv = int(j / std::size_t(w)) - int(i / std::size_t(w));
  const auto& s = pairs.stencil();
  return std::any_of(s.begin(), s.end(), [&](const auto& o) { return o.du == du && o.dv == dv; });
}

// Every substep of the fall and the crumpling: each pair in range that the springs do not hold at rest is on
// the stencil or in the list, checked against every pair of points.
TEST(PairStencil, TheStencilAndTheListHoldEveryUnheldPairInRange) {
  const Scene scene = crumplingCloth(36);
  CpuSolver<float> solver(scene, CpuSolverOptions{.threads = 1});
  const float thickness = float(scene.cloth.thickness), range = 2.0f * thickness;
  const std::vector<glm::dvec3>& rest = solver.topology().initial_positions;
  long long on_stencil = 0, listed = 0, held_in_range = 0;
  for (int s = 0; s < 70 * scene.sim.steps_per_frame; ++s) {
    solver.accumulateForces();
    solver.integrate();
    const std::vector<vec3> x = solver.positions();  // what selfCollide tests
    solver.selfCollide();
    const CollisionPairs<float>& pairs = solver.collisionPairs();
    if (s % 7 == 0)  // every pair of every seventh substep
      for (std::size_t i = 0; i < x.size(); ++i)
        for (std::size_t j = i + 1; j < x.size(); ++j) {
          if (physics::selfCollisionCorrection(x[i], x[j], thickness) == vec3(0)) continue;
          if (physics::heldAtRest(vec3(rest[i]), vec3(rest[j]), range)) {
            ++held_in_range;
            continue;
          }
          if (onStencil(pairs, i, j)) {
            ++on_stencil;
            continue;
          }
          ASSERT_TRUE(std::binary_search(pairs.begin(i), pairs.end(i), std::uint32_t(j)))
              << "substep " << s << ": pair " << i << "-" << j << " in range, neither on the stencil nor listed";
          ++listed;
        }
    solver.collide();
    solver.limitStretch();
  }
  // The knight's moves, and the pairs two apart along a row or column if rounding holds none of them.
  EXPECT_GE(solver.collisionPairs().stencil().size(), 8u);
  EXPECT_GT(on_stencil, 0) << "the case must bring stencil pairs into range";
  EXPECT_GT(listed, 0) << "the case must bring listed pairs into range (the folds)";
  EXPECT_GT(held_in_range, 0);
  // Some checks' tiles' boxes called for a build that a closer look spared: every pair was still found
  EXPECT_GT(solver.collisionPairs().closerLooksKept(), 0);
  std::printf(
      "[ pairs in range ] stencil %lld, list %lld, held %lld; lists built %lld times, kept %lld by a closer look\n",
      on_stencil, listed, held_in_range, solver.collisionPairs().rebuilds(), solver.collisionPairs().closerLooksKept());
}

template <class T>
void expectSameRun(const Scene& scene, CpuSolverOptions a, CpuSolverOptions b, int frames, const char* what) {
  CpuSolver<T> one(scene, a), two(scene, b);
  for (int f = 0; f < frames; ++f) {
    one.stepFrame();
    two.stepFrame();
  }
  EXPECT_EQ(one.readPositions(), two.readPositions()) << what;
  EXPECT_EQ(one.readDisplacements(), two.readDisplacements()) << what;
}

// The stencil changes what is listed, never a byte of the result: float (the vectorised test) and double (the
// scalar one), one thread and a team of two.
TEST(PairStencil, TheBytesAreTheListsAlone) {
  const Scene scene = crumplingCloth(36);
  const CpuSolverOptions list_only{.threads = 1, .pair_stencil = false};
  expectSameRun<float>(scene, list_only, CpuSolverOptions{.threads = 1}, 60, "float");
  expectSameRun<double>(scene, list_only, CpuSolverOptions{.threads = 1}, 60, "double");
  expectSameRun<float>(scene, list_only, CpuSolverOptions{.threads = 2, .team_min_points = 0}, 60, "float, 2 threads");
  expectSameRun<float>(scene, list_only, CpuSolverOptions{.threads = 1, .grid_isa = GridIsa::Sse2}, 60, "float, SSE2");
}

// The squares' bound, tight (CollisionPairs::stencilTiles): on a flat cloth at rest one end of a knight's-move pair
// (2.236 spacings apart against a range of 2.2) moves straight towards the other, by half or one and a half times the
// distance the pair stood beyond the range. Every other displacement is zero, so the box of the displacements
// around the square spans exactly that move: the square may pass over the offset only while the move is shorter
// than that distance. (A bound of half the box passes over the pair in range.) The pair within a square of 8 x 8
// points, then across its edges: the partner in the square beside it, below it, or both, on either side, whose
// displacements the bound must take in (a bound of the square's own box alone passes over the pairs in range).
TEST(PairStencil, ASquarePassesOverAnOffsetOnlyWhileNoPairThereCanBeInRange) {
  const Scene scene = stillFlatCloth();
  const int w = scene.cloth.num_width_points;
  struct Case {
    int u, v, du, dv;  // the pair's lower end and the offset to the other
    bool partner;      // the other end moves, not the lower one
  };
  for (const Case c : {Case{10, 10, 2, 1, false}, Case{7, 10, 2, 1, true}, Case{8, 10, -2, 1, true},
                       Case{10, 7, 2, 1, true}, Case{7, 7, 2, 1, true}, Case{8, 7, -2, 1, true}})
    for (const double share : {0.5, 1.5}) {
      SCOPED_TRACE(::testing::Message() << "pair from (" << c.u << ", " << c.v << ") by (" << c.du << ", " << c.dv
                                        << "), " << (c.partner ? "partner" : "lower end") << " moved, " << share);
      CpuSolver<float> solver(scene, CpuSolverOptions{.threads = 1, .keep_self_corrections = true});
      const std::vector<glm::dvec3> rest = solver.topology().initial_positions;
      const std::size_t i = std::size_t(c.v * w + c.u), j = std::size_t((c.v + c.dv) * w + c.u + c.du);
      const std::size_t mover = c.partner ? j : i, other = c.partner ? i : j;
      const glm::dvec3 towards = rest[other] - rest[mover];
      const double beyond = glm::length(towards) - 2 * scene.cloth.thickness;
      ASSERT_GT(beyond, 0);
      std::vector<glm::dvec3> v(rest.size(), glm::dvec3(0));
      v[mover] = glm::normalize(towards) * beyond * share;
      moveOnce(solver, v);
      const CollisionPairs<float>& pairs = solver.collisionPairs();
      ASSERT_EQ(pairs.rebuilds(), 1) << "the move is within the lists' travel";
      EXPECT_GT(pairs.squaresRuledOut(), 0.5);
      EXPECT_EQ(solver.selfCorrections()[i] != vec3(0), share > 1);
      EXPECT_EQ(solver.selfCorrections()[j] != vec3(0), share > 1);
    }
}

// Sixteen lanes cross three squares where a square is 9 to 15 points wide: a grid of 40 x 144 points has squares of 9
// (144 / 16), and the vector of columns 16 to 31 lies in squares 1, 2 and 3 of its row. A point of the middle square
// moves straight down towards a point three rows below it in the same square (3 spacings against a range of 2.98):
// only that square, and the one above it, test that offset, so the vector must take the middle square's offsets (and
// at the build record its least distances) as well as those of the squares at its ends. Every instruction set here.
TEST(PairStencil, AVectorAcrossThreeSquaresTestsTheMiddleOnesOffsets) {
  Scene scene = stillFlatCloth();
  const int w = 40, h = 144;
  scene.cloth.num_width_points = w;
  scene.cloth.num_height_points = h;
  scene.cloth.height = scene.cloth.width * double(h - 1) / double(w - 1);  // square spacings
  scene.cloth.thickness = 1.49 * scene.cloth.width / double(w - 1);        // a range of 2.98 spacings
  std::vector<GridIsa> isas = {GridIsa::Sse2};
  if (cpuHasAvx2()) isas.push_back(GridIsa::Avx2);
  if (cpuHasAvx512()) isas.push_back(GridIsa::Avx512);
  for (const GridIsa isa : isas) {
    CpuSolver<float> solver(scene, CpuSolverOptions{.threads = 1, .grid_isa = isa, .keep_self_corrections = true});
    SCOPED_TRACE(solver.gridKernels());
    const std::vector<glm::dvec3> rest = solver.topology().initial_positions;
    const std::size_t i = std::size_t(50 * w + 22), j = std::size_t(53 * w + 22);  // both in square (2, 5)
    const glm::dvec3 towards = rest[j] - rest[i];
    const double beyond = glm::length(towards) - 2 * scene.cloth.thickness;
    ASSERT_GT(beyond, 0);
    std::vector<glm::dvec3> v(rest.size(), glm::dvec3(0));
    v[i] = glm::normalize(towards) * beyond * 1.5;
    moveOnce(solver, v);
    const CollisionPairs<float>& pairs = solver.collisionPairs();
    ASSERT_EQ(pairs.rebuilds(), 1) << "the move is within the lists' travel";
    EXPECT_GT(pairs.squaresRuledOut(), 0.5);
    EXPECT_NE(solver.selfCorrections()[i], vec3(0));
    EXPECT_NE(solver.selfCorrections()[j], vec3(0));
  }
}

// The squares' bound takes in only the squares an offset's partners lie in: the square, and beside it and below it
// on the offset's side. One point of the square below and left of square (1, 1) moves by 0.3 spacings: (1, 1) then
// tests its down-left offsets whose pairs stood at most the range and the move apart at rest (a box of all nine
// squares around it would test every offset within that distance), and none of the others, whose squares did not move.
TEST(PairStencil, ASquareTestsOnlyTheOffsetsWhosePartnersMoved) {
  const Scene scene = stillFlatCloth();
  const int w = scene.cloth.num_width_points;
  CpuSolver<float> solver(scene, CpuSolverOptions{.threads = 1});
  const double spacing = scene.cloth.width / double(w - 1);
  std::vector<glm::dvec3> v(solver.topology().initial_positions.size(), glm::dvec3(0));
  v[std::size_t(20 * w + 4)] = glm::dvec3(0.3 * spacing, 0, 0);  // in square (0, 2)
  moveOnce(solver, v);
  const CollisionPairs<float>& pairs = solver.collisionPairs();
  ASSERT_EQ(pairs.rebuilds(), 1);
  ASSERT_TRUE(pairs.squaresUsed());
  const auto& stencil = pairs.stencil();
  const std::size_t half = stencil.size() / 2, across = std::size_t((w + 7) / 8);
  ASSERT_EQ(across, 3u) << "squares of 8 points";
  const std::uint64_t tested = pairs.squareOffsetsTested(1 * across + 1);
  int down_left = 0;
  for (std::size_t k = 0; half + k < stencil.size(); ++k) {
    const auto& o = stencil[half + k];
    const bool bit = (tested >> k) & 1;
    const double nominal = spacing * std::hypot(double(o.du), double(o.dv));
    SCOPED_TRACE(::testing::Message() << "offset (" << o.du << ", " << o.dv << ")");
    if (o.dv > 0 && o.du < 0 && nominal < 2 * scene.cloth.thickness + 0.29 * spacing) {
      EXPECT_TRUE(bit);
      ++down_left;
    } else if (o.dv == 0 || o.du >= 0) {
      EXPECT_FALSE(bit);
    }
  }
  EXPECT_GT(down_left, 0);
}

// The squares pass over tests, never a pair in range: a cloth folding onto itself with a contact distance of 2.5
// spacings (a ring of 24 offsets), the squares on and off, one thread, a team of two (which splits the squares'
// rows), SSE2.
TEST(PairStencil, TheSquaresKeepTheBytes) {
  const Scene scene = crumplingCloth(48, 1.25);
  const CpuSolverOptions every_test{.threads = 1, .stencil_squares = false};
  CpuSolver<float> probe(scene, CpuSolverOptions{.threads = 1});
  double ruled_out = 0;
  for (int s = 0; s < 40 * scene.sim.steps_per_frame; ++s) {
    probe.step();
    ruled_out += probe.collisionPairs().squaresRuledOut();
  }
  EXPECT_GT(ruled_out / (40 * scene.sim.steps_per_frame), 0.3) << "the squares must pass over tests";
  expectSameRun<float>(scene, every_test, CpuSolverOptions{.threads = 1}, 40, "float");
  expectSameRun<float>(scene, every_test, CpuSolverOptions{.threads = 2, .team_min_points = 0}, 40, "2 threads");
  expectSameRun<float>(scene, every_test, CpuSolverOptions{.threads = 1, .grid_isa = GridIsa::Sse2}, 40, "SSE2");
  if (cpuHasAvx2() && cpuHasAvx512())  // the default is AVX-512: AVX2 too
    expectSameRun<float>(scene, every_test, CpuSolverOptions{.threads = 1, .grid_isa = GridIsa::Avx2}, 40, "AVX2");
}

// A team's threads find the pairs of one share of the points (the stencil's of their rows, whole rows of squares at a
// build, the lists' of their points) and sum the terms of another (CpuSolver::fixPairShares): each end's term goes to
// the thread that sums it, and the bytes are one thread's. Shares as uneven as the balance allows, either way round,
// through the fold; between builds the finding threads split a row of squares (48 / 16 = 3 rows and 45 rows, squares
// of 8), each with its own copy of the row's offsets to test. With 21 and 27 rows, both over a square's edge, they
// split it at builds too, the second recording its part of the row apart for the first to merge.
TEST(PairStencil, ThreadsFindingOneShareAndSummingAnotherGiveOneThreadsBytes) {
  const Scene scene = crumplingCloth(48, 1.25);
  const long long n = 48 * 48;
  for (const auto& [find, sum] : {std::pair{1LL, 15LL}, std::pair{15LL, 1LL}, std::pair{7LL, 9LL}}) {
    SCOPED_TRACE(::testing::Message() << "finding " << find << "/16, summing " << sum << "/16");
    CpuSolver<float> one(scene, CpuSolverOptions{.threads = 1});
    CpuSolver<float> team(scene, CpuSolverOptions{.threads = 2, .team_min_points = 0});
    const std::vector<long long> finds = {0, n * find / 16, n}, sums = {0, n * sum / 16, n};
    team.fixPairShares(sums, finds);
    double ruled_out = 0;
    for (int f = 0; f < 40; ++f) {
      one.stepFrame();
      team.stepFrame();
      ruled_out += team.collisionPairs().squaresRuledOut();
    }
    EXPECT_EQ(one.readPositions(), team.readPositions());
    EXPECT_EQ(one.readDisplacements(), team.readDisplacements());
    EXPECT_EQ(team.findShares(), finds);
    EXPECT_EQ(team.pairShares(), sums);
    EXPECT_EQ(team.pairTerms(), one.pairTerms());
    EXPECT_GT(one.pairTerms(), 100000) << "the cloth must be in contact with itself";
    EXPECT_GT(ruled_out, 0) << "the squares must take part";
  }
}

// A grid whose rows do not fill its last row of squares (42 rows in squares of 8: two rows in the last), as most
// sizes do: the stencil's rows, split between threads in whole rows of squares, still end at the last row. A flat
// cloth at rest, one pair of its last row (three columns apart, 3 spacings against a range of 2.9) brought within
// range: both ends move, at a build (the squares record) and at a substep after it (the squares' masks), and at a
// build on a team (a whole substep, whose share of the stencil's rows is the second thread's last).
TEST(PairStencil, TheLastRowOfAGridOfPartRowsOfSquaresIsTested) {
  Scene scene = crumplingCloth(42, 1.45);
  scene.cloth.orientation = Orientation::Horizontal;
  scene.sim.gravity = glm::dvec3(0);
  scene.cloth.damping = 0;
  scene.planes.clear();
  const int w = scene.cloth.num_width_points;
  ASSERT_NE(w % 8, 0);
  const std::size_t i = std::size_t(41 * w + 10), j = i + 3;
  for (const int threads : {1, 2})
    for (const bool at_build : {true, false}) {
      if (threads == 2 && !at_build) continue;  // selfCollide() alone runs outside a team
      SCOPED_TRACE(::testing::Message() << threads << " threads, " << (at_build ? "at the build" : "after it"));
      CpuSolver<float> solver(
          scene, CpuSolverOptions{.threads = threads, .team_min_points = 0, .keep_self_corrections = true});
      std::vector<glm::dvec3> x = solver.topology().initial_positions;
      const glm::dvec3 towards = x[j] - x[i];
      const glm::dvec3 move = glm::normalize(towards) * (glm::length(towards) - 2 * scene.cloth.thickness) * 1.5;
      std::vector<glm::dvec3> v(x.size(), glm::dvec3(0));
      (at_build ? x[i] : v[i]) += move;
      solver.setState(x, v);
      if (threads == 2)
        solver.step();  // on the team: forces and integrate move the point a little, the build finds the pair
      else
        solver.selfCollide();  // the lists built, the squares recorded
      if (!at_build) {
        EXPECT_EQ(solver.selfCorrections()[i], vec3(0)) << "out of range at the build";
        solver.accumulateForces();
        solver.integrate();  // the one point moves by its v
        solver.selfCollide();
        EXPECT_EQ(solver.collisionPairs().rebuilds(), 1) << "the move is within the lists' travel";
        EXPECT_TRUE(solver.collisionPairs().squaresUsed());
      }
      ASSERT_TRUE(onStencil(solver.collisionPairs(), i, j));
      EXPECT_NE(solver.selfCorrections()[i], vec3(0));
      EXPECT_NE(solver.selfCorrections()[j], vec3(0));
    }
}

// A contact distance of ten spacings: a ring of more offsets than a mask has bits, the last bit standing for
// every offset from 63 on (CollisionPairs::stencilBit). Those partners are tested whenever the bit is set.
TEST(PairStencil, AStencilOfMoreOffsetsThanBitsGivesTheListsBytes) {
  const Scene scene = crumplingCloth(28, 5.0);
  CpuSolver<float> probe(scene, CpuSolverOptions{.threads = 1});
  probe.stepFrame();
  ASSERT_GT(probe.collisionPairs().stencil().size(), 64u);
  const CpuSolverOptions list_only{.threads = 1, .pair_stencil = false};
  expectSameRun<float>(scene, list_only, CpuSolverOptions{.threads = 1}, 25, "float");
  expectSameRun<float>(scene, list_only, CpuSolverOptions{.threads = 2, .team_min_points = 0}, 25, "float, 2 threads");
  expectSameRun<double>(scene, list_only, CpuSolverOptions{.threads = 1}, 25, "double");
}

// The adaptive skin (CpuSolverOptions::adaptive_skin): the lists of a cloth that falls flat onto a plane and
// lies there never wear out, so once one has lasted 256 substeps the skin narrows (a rebuild); a cloth that
// falls onto a sphere narrows it during the fall, and widens it again once its lists wear out within a few
// substeps, draped and sliding. Each run gives the bytes of the fixed skin.
TEST(PairSkin, FollowsTheClothAndKeepsTheBytes) {
  const auto bundled = [](const char* name) {
    Scene scene = loadScene(std::string(drape::test::sourceDir()) + "/scenes/" + name);
    scene.sim.self_collision = true;  // as CS184's files run
    return scene;
  };
  const CpuSolverOptions fixed_skin{.threads = 1, .adaptive_skin = false};
  const Scene still = bundled("plane.json");
  CpuSolver<float> adaptive(still, CpuSolverOptions{.threads = 1}), fixed(still, fixed_skin);
  for (int f = 0; f < 12; ++f) {  // 360 substeps
    adaptive.stepFrame();
    fixed.stepFrame();
  }
  EXPECT_FALSE(adaptive.wideSkin());
  EXPECT_EQ(adaptive.skinSwitches(), 1);
  EXPECT_TRUE(fixed.wideSkin());
  EXPECT_EQ(fixed.skinSwitches(), 0);
  EXPECT_EQ(adaptive.readPositions(), fixed.readPositions());
  EXPECT_EQ(adaptive.readDisplacements(), fixed.readDisplacements());

  const Scene draping = bundled("sphere.json");
  CpuSolver<float> follows(draping, CpuSolverOptions{.threads = 1});
  int narrowed = 0, widened = 0;
  bool wide = true;
  for (int f = 0; f < 90; ++f) {
    follows.stepFrame();
    narrowed += wide && !follows.wideSkin();
    widened += !wide && follows.wideSkin();
    wide = follows.wideSkin();
  }
  std::printf("[ sphere ] skin narrowed %d and widened %d times (%d switches)\n", narrowed, widened,
              follows.skinSwitches());
  EXPECT_GE(narrowed, 1) << "the fall: lists that do not wear out";
  EXPECT_GE(widened, 1) << "on the sphere: lists that wear out";
  expectSameRun<float>(draping, fixed_skin, CpuSolverOptions{.threads = 1}, 90, "sphere, adaptive skin");
  expectSameRun<float>(draping, fixed_skin, CpuSolverOptions{.threads = 2, .team_min_points = 0}, 90,
                       "sphere, adaptive skin, 2 threads");
}

// A skin that changes is a build: lists made with a narrow skin do not hold every pair a wide one's check lets
// come into range (the adaptive skin switches by configure).
TEST(PairSkin, ANewSkinRebuildsTheLists) {
  CollisionPairs<float> pairs;
  std::vector<vec3> x;
  for (int k = 0; k < 64; ++k)
    x.emplace_back(0.01f * float(k % 8), 0.01f * float(k / 8), 0.0f);
  pairs.configure(0.02f, 0.01f);
  ASSERT_TRUE(pairs.update(x, 1));
  EXPECT_FALSE(pairs.update(x, 1)) << "nothing moved";
  pairs.configure(0.02f, 0.015f);
  EXPECT_TRUE(pairs.update(x, 1)) << "a wider skin";
  pairs.configure(0.02f, 0.01f);
  EXPECT_TRUE(pairs.update(x, 1)) << "a narrower skin";
  EXPECT_FALSE(pairs.update(x, 1));
}

// pinned2 refined to 192 x 192 with CS184's thickness (19 mm of contact distance over 5.2 mm spacing): the ring
// of unheld pairs just beyond 19 mm was most of the list; on the stencil, the list keeps what folds bring in.
TEST(PairStencil, AFineClothListsAFractionOfWhatItDidWithoutTheStencil) {
  Scene scene = loadScene(std::string(drape::test::sourceDir()) + "/scenes/pinned2.json");
  scene.sim.self_collision = true;
  scene.cloth.num_width_points = scene.cloth.num_height_points = 192;
  scene.cloth.pinned = {{0, 0}, {191, 0}};
  auto entries = [&](bool stencil) {
    CpuSolver<float> cpu(scene, CpuSolverOptions{.threads = 1, .pair_stencil = stencil});
    for (int f = 0; f < 4; ++f)
      cpu.stepFrame();
    const auto& p = cpu.collisionPairs();
    return double(p.entriesBuilt()) / double(p.rebuilds()) / double(cpu.positions().size());
  };
  const double with = entries(true), without = entries(false);
  std::printf("[ list entries a point ] %.2f with the stencil, %.2f without\n", with, without);
  EXPECT_GT(without, 8.0);
  EXPECT_LT(with, 0.1 * without);
}

// needsBuild() by tiles: two clusters of points far apart may move against each other freely; once they come
// within reach of each other, the lists are rebuilt.
TEST(PairStencil, ListsOutliveTheMotionOfFarRegionsAgainstEachOther) {
  CollisionPairs<float> pairs;
  pairs.configure(0.02f, 0.01f);
  std::vector<vec3> x;
  for (int k = 0; k < 512; ++k)  // runs of 64 points a tile: 4 tiles a cluster
    x.emplace_back(float(k / 256) * 1.0f + 0.001f * float(k % 16), 0.001f * float(k % 256 / 16), 0.0f);
  ASSERT_TRUE(pairs.update(x, 1));
  for (std::size_t k = 256; k < x.size(); ++k)
    x[k] += vec3(-0.3f, 0.05f, 0.0f);  // 30 cm against the other cluster, still far from it
  EXPECT_FALSE(pairs.update(x, 1)) << "the clusters are far apart: nothing they hold can come into range";
  for (std::size_t k = 256; k < x.size(); ++k)
    x[k] += vec3(-0.68f, -0.05f, 0.0f);  // 5 mm beyond the first cluster's last column: within reach
  EXPECT_TRUE(pairs.update(x, 1));
  x[0].x += 0.011f;  // one point against its own tile, over the margin
  EXPECT_TRUE(pairs.update(x, 1));
}

}  // namespace
}  // namespace drape
