// The float solver's grid path (SIMD across points, cpu/grid_path.hpp) against its general path (gathers over
// the adjacency and the colouring), byte for byte: per pass (forces, the stretch limit, XPBD's and VBD's sweeps)
// from a disturbed state, and over whole runs (Verlet, XPBD, VBD); with
// each instruction set this CPU has; and a substep's team of two threads against one thread.
#include "cpu/grid_path.hpp"
#include "cpu/cpu_solver.hpp"
#include "kernel_sets.hpp"
#include "same_bytes.hpp"
#include "test_paths.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace drape {
namespace {

struct GridCase {
  std::string name;
  std::string file;  // a bundled scene, or "" for a small free cloth
  int w = 0, h = 0;  // resample to w x h (0: as the file has it)
  bool vertical = false;
  bool structural = true, shearing = true, bending = true;
  int stretch_passes = 1;
  VerletForm form = VerletForm::Displacement;
  Integrator integrator = Integrator::Verlet;
  int iterations = 1;  // XPBD's sweeps (more than one keep the gathers)
  double ks = 0;       // 0: the scene's
};

Scene sceneFor(const GridCase& c) {
  Scene s;
  if (!c.file.empty()) {
    s = loadScene(std::string(drape::test::sourceDir()) + "/scenes/" + c.file);
  } else {
    s.path = "test";
    s.cloth.density = 150;
    s.cloth.pinned = {{0, 0}, {c.w - 1, 0}, {c.w / 2, c.h - 1}};
  }
  if (c.w > 0) {
    s.cloth.num_width_points = c.w;
    s.cloth.num_height_points = c.h;
    s.cloth.pinned.erase(std::remove_if(s.cloth.pinned.begin(), s.cloth.pinned.end(),
                                        [&](glm::ivec2 p) { return p.x >= c.w || p.y >= c.h; }),
                         s.cloth.pinned.end());
  }
  if (c.vertical) s.cloth.orientation = Orientation::Vertical;
  s.cloth.enable_structural = c.structural;
  s.cloth.enable_shearing = c.shearing;
  s.cloth.enable_bending = c.bending;
  s.sim.stretch_passes = c.stretch_passes;
  s.sim.integrator = c.integrator;
  s.sim.iterations = c.iterations;
  if (c.ks > 0) s.cloth.ks = c.ks;
  return s;
}

using test::sameBytes;

const char* isaName(GridIsa isa) {
  return isa == GridIsa::Avx512 ? "avx512" : isa == GridIsa::Avx2 ? "avx2" : "sse2";
}

class GridPathEquality : public ::testing::TestWithParam<GridCase> {};

// A state far from rest: every point moved by up to a third of the spacing, so that many springs are beyond
// the stretch limit and the forces are large.
void disturb(CpuSolver<float>& s, unsigned seed) {
  std::mt19937 rng(seed);
  const double spacing = s.scene().cloth.width / (s.topology().W - 1);
  std::uniform_real_distribution<double> u(-spacing / 3, spacing / 3);
  std::vector<glm::dvec3> x = s.readPositions(), v(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (s.topology().pinned[i]) continue;
    x[i] += glm::dvec3(u(rng), u(rng), u(rng));
    v[i] = glm::dvec3(u(rng), u(rng), u(rng)) * 0.1;
  }
  s.setState(x, v);
}

TEST_P(GridPathEquality, EachPassGivesTheGeneralPathsBytes) {
  const Scene scene = sceneFor(GetParam());
  for (GridIsa isa : test::cpuIsas()) {
    CpuSolver<float> general(scene, CpuSolverOptions{.form = GetParam().form, .threads = 1, .grid_path = false});
    CpuSolver<float> grid(scene, CpuSolverOptions{.form = GetParam().form, .threads = 1, .grid_isa = isa});
    ASSERT_EQ(general.gridKernels(), "");
    ASSERT_EQ(grid.gridKernels(), isaName(isa));
    disturb(general, 7);
    disturb(grid, 7);
    general.accumulateForces();
    grid.accumulateForces();
    EXPECT_TRUE(sameBytes(general.forces(), grid.forces())) << grid.gridKernels();
    // A pass on both from the state they are in: it must move something, and the same bytes.
    const auto pass = [&](const char* name, auto run) {
      const std::vector<glm::vec3> before = general.positions();
      run(general);
      run(grid);
      ASSERT_FALSE(sameBytes(before, general.positions())) << name << " had nothing to do";
      EXPECT_TRUE(sameBytes(general.positions(), grid.positions())) << name << " " << grid.gridKernels();
      EXPECT_TRUE(sameBytes(general.displacements(), grid.displacements())) << name << " " << grid.gridKernels();
    };
    pass("the stretch limit", [](CpuSolver<float>& s) { s.limitStretch(); });
    // XPBD's sweep from a new state (any scene's: it reads the springs' compliances, not the integrator).
    disturb(general, 11);
    disturb(grid, 11);
    pass("XPBD", [](CpuSolver<float>& s) { s.solveXpbd(); });
    // VBD's sweep (its point colours are made for a VBD scene only).
    if (scene.sim.integrator != Integrator::Vbd) continue;
    disturb(general, 13);
    disturb(grid, 13);
    pass("VBD", [](CpuSolver<float>& s) { s.solveVbd(); });
  }
}

TEST_P(GridPathEquality, RunsGiveTheGeneralPathsBytes) {
  const Scene scene = sceneFor(GetParam());
  CpuSolver<float> general(scene, CpuSolverOptions{.form = GetParam().form, .threads = 1, .grid_path = false});
  for (int s = 0; s < 60; ++s)
    general.step();
  for (GridIsa isa : test::cpuIsas()) {
    CpuSolver<float> grid(scene, CpuSolverOptions{.form = GetParam().form, .threads = 1, .grid_isa = isa});
    for (int s = 0; s < 60; ++s)
      grid.step();
    EXPECT_TRUE(sameBytes(general.positions(), grid.positions())) << grid.gridKernels();
    EXPECT_TRUE(sameBytes(general.displacements(), grid.displacements())) << grid.gridKernels();
  }
}

// clang-format off
INSTANTIATE_TEST_SUITE_P(Cases, GridPathEquality, ::testing::Values(
    GridCase{.name = "pinned2", .file = "pinned2.json"},
    GridCase{.name = "selfCollision_vertical", .file = "selfCollision.json", .w = 21, .h = 19},
    GridCase{.name = "sphere_odd", .file = "sphere.json", .w = 23, .h = 17},
    GridCase{.name = "tiny", .file = "", .w = 3, .h = 5},
    GridCase{.name = "wide_vertical", .file = "", .w = 41, .h = 6, .vertical = true},
    GridCase{.name = "no_bending", .file = "", .w = 19, .h = 13, .bending = false},
    GridCase{.name = "structural_only", .file = "", .w = 18, .h = 11, .shearing = false, .bending = false},
    GridCase{.name = "two_passes", .file = "", .w = 26, .h = 9, .stretch_passes = 2},
    GridCase{.name = "previous_position", .file = "", .w = 17, .h = 17, .form = VerletForm::PreviousPosition},
    GridCase{.name = "xpbd", .file = "pinned2.json", .integrator = Integrator::Xpbd},
    GridCase{.name = "xpbd_stiff_sphere", .file = "sphere.json", .w = 23, .h = 17, .integrator = Integrator::Xpbd,
             .ks = 1e6},
    GridCase{.name = "xpbd_structural_only", .file = "", .w = 18, .h = 11, .shearing = false, .bending = false,
             .integrator = Integrator::Xpbd},
    GridCase{.name = "xpbd_previous_position", .file = "", .w = 17, .h = 17, .form = VerletForm::PreviousPosition,
             .integrator = Integrator::Xpbd},
    GridCase{.name = "xpbd_three_sweeps", .file = "pinned4.json", .w = 20, .h = 20, .integrator = Integrator::Xpbd,
             .iterations = 3},
    GridCase{.name = "vbd", .file = "pinned2.json", .integrator = Integrator::Vbd},
    GridCase{.name = "vbd_stiff_sphere", .file = "sphere.json", .w = 23, .h = 17, .integrator = Integrator::Vbd,
             .ks = 1e6},
    GridCase{.name = "vbd_no_bending_vertical", .file = "", .w = 19, .h = 13, .vertical = true, .bending = false,
             .integrator = Integrator::Vbd},
    GridCase{.name = "vbd_previous_position", .file = "", .w = 17, .h = 17, .form = VerletForm::PreviousPosition,
             .integrator = Integrator::Vbd},
    GridCase{.name = "vbd_three_sweeps", .file = "pinned4.json", .w = 20, .h = 20, .integrator = Integrator::Vbd,
             .iterations = 3}),
    [](const auto& test) { return test.param.name; });
// clang-format on

// A cloth at rest with some coordinates exactly -0: every spring is within the stretch limit, so the kernels
// skip the square roots and store a vector back only where adding the scalar code's +0 changes something,
// which is a -0 turning +0. The general path adds it everywhere; the bytes must be its bytes, signs of zero
// included. Gravity's x is -0 too, so that a force sum starts at -0 and keeps the sign its terms give it.
TEST(GridPathSignedZeros, AClothWithinTheLimitKeepsTheGeneralPathsSignsOfZero) {
  Scene scene = sceneFor(GridCase{.name = "zeros", .file = "", .w = 21, .h = 9});
  scene.sim.gravity = glm::dvec3(-0.0, -9.8, 0.0);
  for (GridIsa isa : test::cpuIsas()) {
    CpuSolver<float> general(scene, CpuSolverOptions{.threads = 1, .grid_path = false});
    CpuSolver<float> grid(scene, CpuSolverOptions{.threads = 1, .grid_isa = isa});
    std::vector<glm::dvec3> x = general.readPositions(), v(x.size(), glm::dvec3(0.0));
    // The cloth's first row and column lie on coordinates 0: make every other one of those -0, and one
    // displacement coordinate of every fifth point (some vectors then hold one, some not).
    int negative_zeros = 0;
    for (std::size_t i = 0; i < x.size(); ++i) {
      for (int c = 0; c < 3; ++c)
        if (x[i][c] == 0.0 && i % 2 == 0) {
          x[i][c] = -0.0;
          ++negative_zeros;
        }
      if (i % 5 == 0) {
        v[i][int(i % 3)] = -0.0;
        ++negative_zeros;
      }
    }
    general.setState(x, v);
    grid.setState(x, v);
    general.accumulateForces();
    grid.accumulateForces();
    EXPECT_TRUE(sameBytes(general.forces(), grid.forces())) << grid.gridKernels();
    const std::vector<glm::vec3> before = general.positions(), before_v = general.displacements();
    general.limitStretch();
    grid.limitStretch();
    ASSERT_FALSE(sameBytes(before, general.positions()) && sameBytes(before_v, general.displacements()))
        << "no -0 turned +0: the case does not test the skipped stores (" << negative_zeros << " set)";
    EXPECT_TRUE(sameBytes(general.positions(), grid.positions())) << grid.gridKernels();
    EXPECT_TRUE(sameBytes(general.displacements(), grid.displacements())) << grid.gridKernels();
    // XPBD at rest: every spring's move is a zero of some sign, added to the -0s as the scalar code adds it.
    general.setState(x, v);
    grid.setState(x, v);
    general.solveXpbd();
    grid.solveXpbd();
    EXPECT_TRUE(sameBytes(general.positions(), grid.positions())) << "XPBD " << grid.gridKernels();
    EXPECT_TRUE(sameBytes(general.displacements(), grid.displacements())) << "XPBD " << grid.gridKernels();
  }
}

// A cloth at rest with a -0 in two rows only, one in a position (a coordinate that was +0) and one in a
// displacement: those rows' springs take the kernels' full path, which turns the -0s to +0 as the scalar code
// does, while the other rows' springs, all within the limit, are skipped on their positions alone.
TEST(GridPathSignedZeros, RowsWithoutAMinusZeroAreSkippedAndTheOthersKeepTheGeneralPathsBytes) {
  const int w = 21, h = 12;
  const Scene scene = sceneFor(GridCase{.name = "zeros", .file = "", .w = w, .h = h});
  for (GridIsa isa : test::cpuIsas()) {
    CpuSolver<float> general(scene, CpuSolverOptions{.threads = 1, .grid_path = false});
    CpuSolver<float> grid(scene, CpuSolverOptions{.threads = 1, .grid_isa = isa});
    std::vector<glm::dvec3> x = general.readPositions(), v(x.size(), glm::dvec3(0.0));
    int placed = 0;
    for (int c = 0; c < 3 && placed == 0; ++c)  // the first column lies on a coordinate 0
      if (x[std::size_t(5 * w)][c] == 0.0) {
        x[std::size_t(5 * w)][c] = -0.0;
        ++placed;
      }
    ASSERT_EQ(placed, 1) << "the first column must lie on a coordinate plane";
    v[std::size_t(8 * w + 10)].y = -0.0;
    general.setState(x, v);
    grid.setState(x, v);
    const std::vector<glm::vec3> before = general.positions(), before_v = general.displacements();
    general.limitStretch();
    grid.limitStretch();
    ASSERT_FALSE(sameBytes(before, general.positions()) || sameBytes(before_v, general.displacements()))
        << "both -0s must turn +0 on the general path";
    EXPECT_TRUE(sameBytes(general.positions(), grid.positions())) << grid.gridKernels();
    EXPECT_TRUE(sameBytes(general.displacements(), grid.displacements())) << grid.gridKernels();
  }
}

// Points on top of their neighbours: springs of length 0, whose term springForce makes vec3(0) (its division
// would give NaN). The kernels test for them only in rows whose springs have one; here a structural, a shear
// and a bending spring in the interior, and springs on the top row and the right side, where the vectors are
// masked. The forces must be the general path's bytes, and finite.
TEST(GridPathForces, SpringsOfLengthZeroGiveTheGeneralPathsBytes) {
  const int w = 29, h = 12;
  const Scene scene = sceneFor(GridCase{.name = "coincident", .file = "", .w = w, .h = h});
  for (GridIsa isa : test::cpuIsas()) {
    CpuSolver<float> general(scene, CpuSolverOptions{.threads = 1, .grid_path = false});
    CpuSolver<float> grid(scene, CpuSolverOptions{.threads = 1, .grid_isa = isa});
    std::vector<glm::dvec3> x = general.readPositions(), v(x.size(), glm::dvec3(0.0));
    const auto onto = [&](int u, int row, int ou, int orow) {
      x[std::size_t(row * w + u)] = x[std::size_t(orow * w + ou)];
    };
    onto(13, 5, 12, 5);        // structural, interior
    onto(14, 7, 13, 6);        // shear
    onto(10, 9, 10, 7);        // bending
    onto(0, 0, 1, 0);          // the top row, the left side
    onto(w - 1, 3, w - 1, 4);  // the right side
    general.setState(x, v);
    grid.setState(x, v);
    general.accumulateForces();
    grid.accumulateForces();
    for (const glm::vec3& f : grid.forces())
      ASSERT_TRUE(std::isfinite(f.x) && std::isfinite(f.y) && std::isfinite(f.z)) << grid.gridKernels();
    EXPECT_TRUE(sameBytes(general.forces(), grid.forces())) << grid.gridKernels();
  }
}

// The folded selfCollision cloth: the vectorised test that lets a point with no pair in range skip its ordered
// sum, against the solver without it, once the cloth has folded onto itself.
TEST(GridPathSelfCollision, TheRangeTestKeepsTheGeneralPathsBytes) {
  Scene scene = loadScene(std::string(drape::test::sourceDir()) + "/scenes/selfCollision.json");
  scene.sim.self_collision = true;
  CpuSolver<float> general(scene, CpuSolverOptions{.threads = 1, .grid_path = false});
  CpuSolver<float> vectorised(scene, CpuSolverOptions{.threads = 1});
  for (int f = 0; f < 45; ++f) {
    general.stepFrame();
    vectorised.stepFrame();
  }
  const std::vector<glm::vec3>& x = vectorised.positions();
  const float thickness = float(scene.cloth.thickness);
  long long in_range = 0;
  for (std::size_t i = 0; i < x.size(); ++i)
    for (std::size_t j = i + 1; j < x.size(); ++j)
      in_range += physics::selfCollisionCorrection(x[i], x[j], thickness) != glm::vec3(0);
  ASSERT_GT(in_range, 100) << "the cloth must have folded onto itself";
  EXPECT_TRUE(sameBytes(general.positions(), vectorised.positions()));
  EXPECT_TRUE(sameBytes(general.displacements(), vectorised.displacements()));
}

// A mesh cloth keeps its gathers; only the integration runs vectorised there (it needs no neighbours).
TEST(GridPathMesh, AMeshClothGivesTheGeneralPathsBytes) {
  const Scene scene = loadScene(std::string(drape::test::sourceDir()) + "/scenes/flag.json");
  CpuSolver<float> general(scene, CpuSolverOptions{.threads = 1, .grid_path = false});
  CpuSolver<float> vectorised(scene, CpuSolverOptions{.threads = 1});
  ASSERT_EQ(vectorised.gridKernels(), "") << "a mesh has no grid";
  for (int s = 0; s < 40; ++s) {
    general.step();
    vectorised.step();
  }
  EXPECT_TRUE(sameBytes(general.positions(), vectorised.positions()));
  EXPECT_TRUE(sameBytes(general.displacements(), vectorised.displacements()));
}

// A substep on a team of two threads (one OpenMP region, a barrier between passes) gives one thread's bytes:
// every pass of the selfCollision scene (self-collision, a plane), on both paths.
TEST(GridPathTeam, TwoThreadsGiveOneThreadsBytes) {
  Scene scene = loadScene(std::string(drape::test::sourceDir()) + "/scenes/selfCollision.json");
  scene.sim.self_collision = true;
  for (bool grid : {true, false}) {
    CpuSolver<float> one(scene, CpuSolverOptions{.threads = 1, .grid_path = grid});
    CpuSolver<float> two(scene, CpuSolverOptions{.threads = 2, .grid_path = grid, .team_min_points = 0});
    ASSERT_EQ(two.teamThreads(), 2);
    for (int f = 0; f < 3; ++f) {
      one.stepFrame();
      two.stepFrame();
    }
    EXPECT_TRUE(sameBytes(one.positions(), two.positions())) << (grid ? "grid" : "general");
    EXPECT_TRUE(sameBytes(one.displacements(), two.displacements())) << (grid ? "grid" : "general");
  }
}

// pinned2 at 20 x 14 with self-collision: the grid path's passes with no collider, in a few milliseconds
Scene smallPinned2() {
  Scene scene = loadScene(std::string(drape::test::sourceDir()) + "/scenes/pinned2.json");
  scene.cloth.num_width_points = 20;
  scene.cloth.num_height_points = 14;
  // The file's pins are for 50 x 50: its (49, 0) pinned point 49 of this grid, (9, 2), until off-grid pins became an
  // error; these tests were made with that cloth
  scene.cloth.pinned = {{0, 0}, {9, 2}};
  scene.sim.self_collision = true;
  return scene;
}

// The cloth's rows pressed together (its depth a fifth of what it was): pairs within self-collision's range
void pressRows(CpuSolver<float>& s) {
  std::vector<glm::dvec3> x = s.readPositions();
  for (glm::dvec3& p : x)
    p.z = 0.2 * (p.z - x[0].z) + x[0].z;
  s.setState(x, s.readDisplacements());
}

// After a substep whose last pass to move the points is the stretch limit's copy back (pinned2: no collider), the
// next substep's forces read the positions already in the padded arrays. Whatever moves the points in between
// (a state set, a pass run on its own, a reset) must have them copied in again: each
// against the general path, which keeps no copy.
TEST(GridPathForces, PointsMovedBetweenSubstepsAreCopiedIn) {
  Scene scene = smallPinned2();
  const std::vector<std::pair<std::string, std::function<void(CpuSolver<float>&)>>> moves = {
      {"setState", [](CpuSolver<float>& s) { disturb(s, 5); }},
      {"integrate", [](CpuSolver<float>& s) { s.integrate(); }},
      {"selfCollide after setState",
       [](CpuSolver<float>& s) {
         pressRows(s);
         s.step();
         const std::vector<glm::vec3> before = s.positions();
         s.selfCollide();
         EXPECT_FALSE(sameBytes(before, s.positions())) << "self-collision must move the points";
       }},
      {"reset", [](CpuSolver<float>& s) { s.reset(); }}};
  for (const auto& [name, move] : moves) {
    CpuSolver<float> general(scene, CpuSolverOptions{.threads = 1, .grid_path = false});
    CpuSolver<float> grid(scene, CpuSolverOptions{.threads = 1});
    ASSERT_NE(grid.gridKernels(), "");
    for (CpuSolver<float>* s : {&general, &grid}) {
      for (int k = 0; k < 5; ++k)
        s->step();
      move(*s);
      for (int k = 0; k < 3; ++k)
        s->step();
    }
    EXPECT_TRUE(sameBytes(general.positions(), grid.positions())) << name;
    EXPECT_TRUE(sameBytes(general.displacements(), grid.displacements())) << name;
  }
}

// A substep with no collider but self-collision integrates on the padded arrays, where self-collision then moves
// its points, and leaves them there for the next substep (CpuSolver::syncPositions). Every reader must see them:
// the accessors, health(), a pass run on its own, a state set; and reading them between substeps changes nothing.
TEST(GridPathIntegrate, PointsLeftInThePaddedArraysReachEveryReader) {
  Scene scene = smallPinned2();
  CpuSolver<float> general(scene, CpuSolverOptions{.threads = 1, .grid_path = false});
  CpuSolver<float> grid(scene, CpuSolverOptions{.threads = 1});
  CpuSolver<float> read(scene, CpuSolverOptions{.threads = 1});  // read after every substep
  for (CpuSolver<float>* s : {&general, &grid, &read}) {
    pressRows(*s);  // pairs within range from the first substeps
    s->step();      // copies the state set in
  }
  ASSERT_TRUE(grid.keepsPointsInArrays());
  ASSERT_FALSE(general.keepsPointsInArrays()) << "the general path has no arrays";
  ASSERT_FALSE(grid.positionsInArrays()) << "a substep after a state set starts from x and v";
  const long long terms = grid.pairTerms();
  std::vector<glm::vec3> seen;
  for (int k = 0; k < 6; ++k) {
    for (CpuSolver<float>* s : {&general, &grid, &read})
      s->step();
    ASSERT_TRUE(grid.positionsInArrays()) << "substep " << k << ": pinned2 integrates on the arrays";
    ASSERT_FALSE(general.positionsInArrays());
    seen = read.positions();
    ASSERT_FALSE(read.positionsInArrays()) << "positions() copies them back";
  }
  ASSERT_GT(grid.pairTerms(), terms) << "self-collision must move points in the arrays";
  EXPECT_TRUE(sameBytes(seen, general.positions()));
  EXPECT_TRUE(sameBytes(read.displacements(), general.displacements()));
  // health() looks at the arrays where they hold the points (GridPath::healthy), copying nothing back, and answers
  // as the general path's scan of x and v
  const Health in_arrays = grid.health(), scanned = general.health();
  EXPECT_TRUE(grid.positionsInArrays()) << "a healthy look copies nothing back";
  EXPECT_EQ(in_arrays.flags, scanned.flags);
  EXPECT_EQ(in_arrays.substeps, scanned.substeps);
  EXPECT_TRUE(sameBytes(grid.positions(), general.positions()));
  EXPECT_TRUE(sameBytes(grid.displacements(), general.displacements()));
  // Each other way in, from a substep that left the points in the arrays, against the general path
  const std::vector<std::pair<std::string, std::function<void(CpuSolver<float>&)>>> readers = {
      {"readPositions", [](CpuSolver<float>& s) { s.setState(s.readPositions(), s.readDisplacements()); }},
      {"accumulateForces", [](CpuSolver<float>& s) { s.accumulateForces(); }},
      {"integrate", [](CpuSolver<float>& s) { s.integrate(); }},
      {"selfCollide", [](CpuSolver<float>& s) { s.selfCollide(); }},
      {"limitStretch", [](CpuSolver<float>& s) { s.limitStretch(); }},
      {"setState", [](CpuSolver<float>& s) { disturb(s, 3); }},
      // Live parameters (the viewer's): a substep of another integrator, or with wind, reads x_ and v_
      {"setParams to XPBD",
       [](CpuSolver<float>& s) {
         SimParams sim = s.scene().sim;
         sim.integrator = Integrator::Xpbd;
         s.setParams(s.scene().cloth, sim);
         s.step();
       }},
      {"setParams with wind", [](CpuSolver<float>& s) {
         SimParams sim = s.scene().sim;
         sim.integrator = Integrator::Verlet;
         sim.wind.enabled = true;
         s.setParams(s.scene().cloth, sim);
         s.step();
         s.step();
       }}};
  for (const auto& [name, reader] : readers) {
    for (CpuSolver<float>* s : {&general, &grid}) {
      // Fast points: the stretch limit moves many of them in the last substep's arrays
      disturb(*s, 9);
      s->step();
      s->step();
      reader(*s);
    }
    EXPECT_TRUE(sameBytes(general.forces(), grid.forces())) << name;
    EXPECT_TRUE(sameBytes(general.positions(), grid.positions())) << name;
    EXPECT_TRUE(sameBytes(general.displacements(), grid.displacements())) << name;
  }
}

// Where integrate left the points in the padded arrays, the sphere's and the plane's collisions run there too, before
// and after the stretch limit: the general path's bytes, on one thread and on a team of two.
TEST(GridPathIntegrate, CollisionsOnThePaddedArraysGiveTheGeneralPathsBytes) {
  Scene scene = smallPinned2();
  const SphereSpec sphere{.origin = {0.5, 0.95, 0.5}, .radius = 0.2, .friction = 0.3};  // through the cloth
  scene.spheres = {sphere};
  const double floor = 0.97;  // a few centimetres below it, where the falling cloth lands within the run
  scene.planes = {PlaneSpec{.point = {0, floor, 0}, .normal = {0, 1, 0}}};
  CpuSolver<float> general(scene, CpuSolverOptions{.threads = 1, .grid_path = false});
  CpuSolver<float> grid(scene, CpuSolverOptions{.threads = 1});
  CpuSolver<float> team(scene, CpuSolverOptions{.threads = 2, .team_min_points = 0});
  ASSERT_EQ(team.teamThreads(), 2);
  for (int k = 0; k < 180; ++k)
    for (CpuSolver<float>* s : {&general, &grid, &team})
      s->step();
  EXPECT_TRUE(grid.positionsInArrays());
  EXPECT_TRUE(team.positionsInArrays());
  const std::vector<glm::vec3> x = general.positions();
  int on_sphere = 0, on_floor = 0, inside = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double r = glm::distance(glm::dvec3(x[i]), sphere.origin);
    on_sphere += r < sphere.radius + 0.01;
    on_floor += x[i].y < floor + 0.002;
    inside += r < sphere.radius * 0.99 || x[i].y < floor - 1e-4;
  }
  EXPECT_GT(on_sphere, 5) << "the cloth must lie on the sphere";
  EXPECT_GT(on_floor, 3) << "and on the plane";
  EXPECT_EQ(inside, 0);
  for (const CpuSolver<float>* s : {&grid, &team}) {
    EXPECT_TRUE(sameBytes(x, s->positions())) << s->threads();
    EXPECT_TRUE(sameBytes(general.displacements(), s->displacements())) << s->threads();
  }
}

}  // namespace
}  // namespace drape
