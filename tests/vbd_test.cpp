// Vertex Block Descent on the CPU (no GL): a spring's block and the 3x3 solve worked by hand, the point
// colouring, the pass list, and the stability sweep. What VBD shares with XPBD (float against double,
// thread counts, sweeps, stiff cloth at 30 substeps) is tested for both in tests/xpbd_test.cpp.
#include "app/stability_cases.hpp"
#include "core/colouring.hpp"
#include "core/metrics.hpp"
#include "core/stability.hpp"
#include "cpu/cpu_solver.hpp"
#include "cpu/physics.hpp"
#include "test_paths.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <string>

namespace drape {
namespace {

Scene vbdScene(const std::string& name, int iterations = 1) {
  Scene s = loadScene(std::string(drape::test::sourceDir()) + "/scenes/" + name);
  s.sim.integrator = Integrator::Vbd;
  s.sim.iterations = iterations;
  return s;
}

// A spring of rest 1 and k = 2 stretched to 1.5 along x, seen from the origin: force k (1.5 - 1) = 1
// towards the other end; Hessian k along the spring and k (1 - 1/1.5) = 2/3 across it.
TEST(VbdPhysics, SpringBlockWorkedByHand) {
  glm::dvec3 f(0), diag(0), off(0);
  physics::vbdAddSpring(glm::dvec3(0), glm::dvec3(1.5, 0, 0), 1.0, 2.0, f, diag, off);
  EXPECT_DOUBLE_EQ(f.x, 1.0);
  EXPECT_EQ(f.y, 0.0);
  EXPECT_DOUBLE_EQ(diag.x, 2.0);
  EXPECT_DOUBLE_EQ(diag.y, 2.0 / 3.0);
  EXPECT_DOUBLE_EQ(diag.z, 2.0 / 3.0);
  EXPECT_EQ(off, glm::dvec3(0));
  // Compressed to 0.5: pushes away, and the negative transverse term is clamped to 0 (no uphill step).
  f = diag = off = glm::dvec3(0);
  physics::vbdAddSpring(glm::dvec3(0), glm::dvec3(0.5, 0, 0), 1.0, 2.0, f, diag, off);
  EXPECT_DOUBLE_EQ(f.x, -1.0);
  EXPECT_EQ(diag, glm::dvec3(2.0, 0, 0));
  // Along the diagonal (1, 1, 0)/sqrt(2), at rest length: k u u^T, off-diagonal xy = k / 2.
  f = diag = off = glm::dvec3(0);
  const double r = std::sqrt(0.5);
  physics::vbdAddSpring(glm::dvec3(0), glm::dvec3(r, r, 0), 1.0, 2.0, f, diag, off);
  EXPECT_NEAR(f.x, 0.0, 1e-15);
  EXPECT_NEAR(diag.x, 1.0, 1e-15);
  EXPECT_NEAR(off.x, 1.0, 1e-15);
  EXPECT_EQ(off.y, 0.0);
  // Zero length: no direction, nothing added.
  f = diag = off = glm::dvec3(0);
  physics::vbdAddSpring(glm::dvec3(1), glm::dvec3(1), 1.0, 2.0, f, diag, off);
  EXPECT_EQ(diag, glm::dvec3(0));
}

// H = [[4, 1, 2], [1, 3, 0], [2, 0, 5]] and x = (1, -2, 3): f = H x = (8, -5, 17).
TEST(VbdPhysics, StepSolvesTheBlock) {
  const glm::dvec3 x = physics::vbdStep(glm::dvec3(8, -5, 17), glm::dvec3(4, 3, 5), glm::dvec3(1, 2, 0));
  EXPECT_NEAR(x.x, 1.0, 1e-14);
  EXPECT_NEAR(x.y, -2.0, 1e-14);
  EXPECT_NEAR(x.z, 3.0, 1e-14);
  // Stiffness 1e13 in float: the pivots stay of the order of k, no k^3 to overflow.
  const glm::vec3 big =
      physics::vbdStep(glm::vec3(1e13f, 0, 0), glm::vec3(1e13f, 2e13f, 1e13f), glm::vec3(0.5e13f, 0, 0));
  EXPECT_TRUE(std::isfinite(big.x) && std::isfinite(big.y) && std::isfinite(big.z));
  EXPECT_NEAR(big.x, 2.0 / 1.75, 1e-6);
  // A block that is not positive definite (NaN, or a zero pivot) gives no step.
  EXPECT_EQ(physics::vbdStep(glm::dvec3(1), glm::dvec3(0, 1, 1), glm::dvec3(0)), glm::dvec3(0));
  EXPECT_EQ(physics::vbdStep(glm::dvec3(1), glm::dvec3(NAN, 1, 1), glm::dvec3(0)), glm::dvec3(0));
}

// Every point once, and no spring (of any type) between two points of one colour: what lets a colour's
// points move at once from their neighbours' latest positions.
TEST(VbdColouring, NoSpringJoinsTwoPointsOfAColour) {
  for (const char* file : {"pinned2.json", "sphere.json"}) {
    const Scene scene = loadScene(std::string(drape::test::sourceDir()) + "/scenes/" + file);
    const Topology topo = buildTopology(scene.cloth);
    const PointColouring c = colourPoints(topo);
    ASSERT_EQ(c.points.size(), std::size_t(topo.pointCount()));
    std::vector<int> colour(c.points.size(), -1);
    for (int k = 0; k < c.colourCount(); ++k)
      for (std::uint32_t j = c.start[std::size_t(k)]; j < c.start[std::size_t(k) + 1]; ++j) {
        ASSERT_EQ(colour[c.points[j]], -1) << "point " << c.points[j] << " twice";
        colour[c.points[j]] = k;
      }
    for (const Spring& s : topo.springs)
      EXPECT_NE(colour[s.a], colour[s.b]) << file << ": spring " << s.a << "-" << s.b;
    // A grid point has 12 neighbours: 4 structural, 4 shearing, 4 bending (two steps along a row or
    // column). The greedy order colours the grid in 7, as the lattice colouring (x + 3y) mod 7 does.
    std::printf("%s: %d point colours\n", file, c.colourCount());
    EXPECT_EQ(c.colourCount(), 7) << file;
  }
}

TEST(VbdSolver, PassesListThePointSweepOnlyForVbd) {
  EXPECT_EQ(CpuSolver<float>(vbdScene("sphere.json")).passes(),
            (std::vector<std::string>{"forces", "integrate", "vbd_solve", "self_collide", "collide", "limit_stretch",
                                      "collide_last"}));
  Scene scene = vbdScene("pinned2.json");
  EXPECT_TRUE(checkStability(scene).ok) << "no explicit bound for VBD";
}

// The integrator key changes the physics: VBD's run differs from Verlet's and from XPBD's.
TEST(VbdSolver, TheIntegratorKeyChangesTheRun) {
  Scene xpbd = vbdScene("pinned2.json");
  xpbd.sim.integrator = Integrator::Xpbd;
  Scene verlet = xpbd;
  verlet.sim.integrator = Integrator::Verlet;
  CpuSolver<float> a(verlet), x(xpbd), v(vbdScene("pinned2.json"));
  for (int f = 0; f < 10; ++f) {
    a.stepFrame();
    x.stepFrame();
    v.stepFrame();
  }
  EXPECT_GT(maxDeviation(v.readPositions(), a.readPositions()), 1e-4);
  EXPECT_GT(maxDeviation(v.readPositions(), x.readPositions()), 1e-4);
}

// Float against double, thread-count independence, more sweeps stretching less, and stability at 30
// substeps on the stiff hanging cloth: tests/xpbd_test.cpp, ImplicitSolver, for XPBD and VBD alike.

// `drape stability` runs every case with VBD too when asked, never guarded; the markdown has its own
// table and the CSV names the integrator.
TEST(VbdStability, TheSweepRunsEveryCaseWithVbd) {
  std::vector<StabilityCase> cases;
  for (const StabilityCase& c : stabilityCases())
    if (c.name == "ks-1e9") cases.push_back(c);
  ASSERT_EQ(cases.size(), 1u);
  cases[0].frames = 20;
  const StabilityReport r = runStability(cases, {30}, {}, 1, {30}, {Integrator::Xpbd, Integrator::Vbd});
  for (Integrator i : {Integrator::Xpbd, Integrator::Vbd}) {
    const StabilityResult* x = findResult(r, "ks-1e9", 30, false, i);
    ASSERT_NE(x, nullptr) << integratorName(i);
    EXPECT_EQ(x->steps_per_frame, 30);
    EXPECT_TRUE(x->stable) << integratorName(i) << ": " << x->what;
  }
  const std::string md = stabilityMarkdown(r, cases);
  EXPECT_NE(md.find("VBD (simulation.integrator vbd"), std::string::npos) << md;
  EXPECT_NE(stabilityCsv(r).find("\nks-1e9,vbd,30,0,30,"), std::string::npos) << stabilityCsv(r);
}

}  // namespace
}  // namespace drape
