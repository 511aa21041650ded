// The model's constants and rules checked against answers worked out by hand (each in the test's
// comment), not against the other solver: CPU-against-GPU agreement cannot tell that both are wrong.
// Pure functions from cpu/physics.hpp and core/derived.hpp, and tiny CpuSolver<double> scenes where
// the rule lives in a pass (averaging, division by steps per frame, damping as a percentage).
#include "cpu/physics.hpp"
#include "core/derived.hpp"
#include "cpu/cpu_solver.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <utility>
#include <vector>

namespace drape {
namespace {

using glm::dvec3;
constexpr double kTight = 1e-12;  // m: what double round-off leaves of these few operations

void expectNear(dvec3 got, dvec3 want, double tolerance = kTight) {
  EXPECT_NEAR(got.x, want.x, tolerance);
  EXPECT_NEAR(got.y, want.y, tolerance);
  EXPECT_NEAR(got.z, want.z, tolerance);
}

// A W x H cloth with every spring type off, no gravity, no damping, no stretch limit, no
// self-collision, 1 substep per frame: each test turns on only what it checks.
Scene bareScene(int W, int H) {
  Scene s;
  s.cloth.num_width_points = W;
  s.cloth.num_height_points = H;
  s.cloth.enable_structural = s.cloth.enable_shearing = s.cloth.enable_bending = false;
  s.cloth.damping = 0.0;
  s.sim.gravity = dvec3(0.0);
  s.sim.stretch_passes = 0;
  s.sim.self_collision = false;
  s.sim.steps_per_frame = 1;
  return s;
}

// --- derived quantities ------------------------------------------------------------------------

// CS184's standard cloth: 1 m x 1 m at 150 kg/m^2 is 150 kg over 50 x 50 = 2500 points: 0.06 kg each.
TEST(Derived, PointMassSharesTheClothsMassEqually) {
  ClothSpec c;
  c.width = c.height = 1.0;
  c.num_width_points = c.num_height_points = 50;
  c.density = 150.0;
  EXPECT_DOUBLE_EQ(derived::pointMass(c), 0.06);
  // 2 m x 0.5 m at 3 kg/m^2 = 3 kg over 3 x 2 points: 0.5 kg.
  c.width = 2.0;
  c.height = 0.5;
  c.density = 3.0;
  c.num_width_points = 3;
  c.num_height_points = 2;
  EXPECT_DOUBLE_EQ(derived::pointMass(c), 0.5);
}

TEST(Derived, BendingSpringsHaveAFifthOfKs) {
  ClothSpec c;
  c.ks = 5000.0;
  EXPECT_DOUBLE_EQ(derived::bendingStiffness(c), 1000.0);
  EXPECT_DOUBLE_EQ(derived::springStiffness(c, SpringType::Bending), 1000.0);
  EXPECT_DOUBLE_EQ(derived::springStiffness(c, SpringType::Structural), 5000.0);
  EXPECT_DOUBLE_EQ(derived::springStiffness(c, SpringType::Shearing), 5000.0);
}

// One bucket per point, rounded up to a power of two: 2500 points -> 4096, 4096 -> 4096, 4097 -> 8192.
TEST(Derived, HashBucketsAreThePowerOfTwoAtOrAboveThePointCount) {
  EXPECT_EQ(derived::hashBucketCount(2500), 4096u);
  EXPECT_EQ(derived::hashBucketCount(4096), 4096u);
  EXPECT_EQ(derived::hashBucketCount(4097), 8192u);
  EXPECT_EQ(derived::hashBucketCount(1), 1u);
  EXPECT_EQ(derived::hashBucketCount(0), 1u);  // never an empty table
}

// --- bending at 0.2 ks, through the solver -----------------------------------------------------

// A 3 x 2 cloth, 2 m x 1 m: points 1 m apart, bending springs (x, y)-(x+2, y) of rest length 2 m (no
// vertical bending: H = 2). Only bending is on, ks = 100 N/m, so k = 20 N/m. Point (2, 0) is pulled
// 0.1 m along +x: its spring to (0, 0) is 2.1 m long and pulls with 20 * 0.1 = 2 N. Mass 2*1*3/6 =
// 1 kg, dt = 0.1 s: the point's displacement becomes (F/m) dt^2 = -2 * 0.01 = -0.02 m, so it ends at
// x = 2.1 - 0.02 = 2.08, and (0, 0) at +0.02. With k = ks it would move five times as far.
TEST(HandWorked, BendingSpringPullsWithAFifthOfKs) {
  Scene s = bareScene(3, 2);
  s.cloth.width = 2.0;
  s.cloth.height = 1.0;
  s.cloth.density = 3.0;
  s.cloth.ks = 100.0;
  s.cloth.enable_bending = true;
  s.sim.frames_per_sec = 10.0;
  CpuSolver<double> solver(s);
  std::vector<dvec3> x = solver.topology().initial_positions;
  ASSERT_EQ(x[2], dvec3(2.0, 1.0, 0.0));
  x[2].x = 2.1;
  solver.setState(x, std::vector<dvec3>(x.size(), dvec3(0.0)));
  solver.step();
  const std::vector<dvec3> after = solver.readPositions();
  expectNear(after[2], dvec3(2.08, 1.0, 0.0));
  expectNear(after[0], dvec3(0.02, 1.0, 0.0));
  for (int i : {1, 3, 4, 5})
    expectNear(after[i], x[i]);  // their springs are at rest length
}

// --- self-collision: averaged, then divided by steps per frame ----------------------------------

// A 2 x 2 cloth whose points are placed by hand, thickness 0.1 m (range 2 * thickness = 0.2 m), 5
// substeps per frame. On the x axis: p1 at 0.1, p0 at 0, p2 at -0.15; p3 far away.
//   p0: p1 is 0.1 away (overlap 0.1, push -x), p2 0.15 away (overlap 0.05, push +x);
//       average (-0.1 + 0.05) / 2 = -0.025, / 5 = -0.005        -> p0 at -0.005
//   p1: only p0 (p1-p2 is 0.25 apart): +0.1, / 5 = +0.02        -> p1 at 0.12
//   p2: only p0: -0.05, / 5 = -0.01                              -> p2 at -0.16
// Summing instead of averaging would move p0 to -0.01; not dividing would move it to -0.025. Jacobi:
// every correction uses the positions from before the pass.
TEST(HandWorked, SelfCollisionAveragesAndDividesByStepsPerFrame) {
  Scene s = bareScene(2, 2);
  s.cloth.thickness = 0.1;
  s.sim.steps_per_frame = 5;
  s.sim.self_collision = true;
  CpuSolver<double> solver(s);
  const std::vector<dvec3> x = {{0.0, 0.0, 0.0}, {0.1, 0.0, 0.0}, {-0.15, 0.0, 0.0}, {5.0, 5.0, 5.0}};
  const std::vector<dvec3> v(4, dvec3(0.0));
  solver.setState(x, v);
  solver.selfCollide();
  const std::vector<dvec3> after = solver.readPositions();
  expectNear(after[0], dvec3(-0.005, 0.0, 0.0));
  expectNear(after[1], dvec3(0.12, 0.0, 0.0));
  expectNear(after[2], dvec3(-0.16, 0.0, 0.0));
  EXPECT_EQ(after[3], x[3]);
  // A correction moves x_prev with x: the displacement takes the same correction.
  expectNear(solver.readDisplacements()[0], dvec3(-0.005, 0.0, 0.0));
}

// The pure function: overlap along the unit vector from xj to xi, nothing at or beyond the range.
TEST(HandWorked, SelfCollisionCorrectionIsTheOverlap) {
  // 0.12 apart along y, range 0.2: pushed 0.08 along +y.
  expectNear(physics::selfCollisionCorrection<double>({0, 0.12, 0}, {0, 0, 0}, 0.1), dvec3(0, 0.08, 0));
  EXPECT_EQ(physics::selfCollisionCorrection<double>({0, 0.2, 0}, {0, 0, 0}, 0.1), dvec3(0.0));
  EXPECT_EQ(physics::selfCollisionCorrection<double>({0, 0, 0}, {0, 0, 0}, 0.1), dvec3(0.0));  // no direction
}

// Both ends of a pair at once (the CPU's sum finds each pair once) are the two calls bit for bit: points at
// the range, inside it on the grid of float steps around a point, on an axis (zero components), coincident,
// and with a NaN coordinate.
TEST(HandWorked, SelfCollisionCorrectionsAreBothEndsBitForBit) {
  using vec3 = glm::vec3;
  const float thickness = 0.0095f, range = 2.0f * thickness;
  const auto same = [](vec3 a, vec3 b) { return std::memcmp(&a, &b, sizeof(vec3)) == 0; };
  std::vector<std::pair<vec3, vec3>> pairs = {{{0, 0, 0}, {range, 0, 0}},
                                              {{0.5f, 0.25f, 0.125f}, {0.5f, 0.25f, 0.125f}},
                                              {{0.5f, 0.25f, 0.125f}, {0.5f, 0.25f + 0.01f, 0.125f}},
                                              {{-0.0f, 0.3f, 0.0f}, {0.0f, 0.31f, -0.0f}},
                                              {{std::nanf(""), 0, 0}, {0, 0, 0}},
                                              {{0, 0, 0}, {0.01f, std::nanf(""), 0}}};
  for (int k = 0; k < 2000; ++k)  // scattered within and just beyond the range, around a point off the origin
    pairs.push_back({{0.731f, 0.412f, -0.257f},
                     {0.731f + 0.021f * std::sin(float(k)), 0.412f + 0.017f * std::cos(1.7f * float(k)),
                      -0.257f + 0.013f * std::sin(2.3f * float(k))}});
  int in_range = 0;
  for (const auto& [a, b] : pairs) {
    vec3 ci(7.0f), cj(7.0f);
    const bool hit = physics::selfCollisionCorrections(a, b, thickness, ci, cj);
    const vec3 ea = physics::selfCollisionCorrection(a, b, thickness),
               eb = physics::selfCollisionCorrection(b, a, thickness);
    in_range += hit;
    if (!hit) {
      EXPECT_TRUE(ea == vec3(0) && eb == vec3(0));
      continue;
    }
    EXPECT_TRUE(same(ci, ea)) << a.x << " " << b.x;
    EXPECT_TRUE(same(cj, eb)) << a.x << " " << b.x;
  }
  EXPECT_GT(in_range, 500);
  EXPECT_LT(in_range, 1900);
}

// --- Verlet damping ------------------------------------------------------------------------------

// damping is a percentage of the displacement lost per substep: at 20 %, a point moving 1 cm per
// substep with no force moves 0.8 cm in the next. With gravity -10 m/s^2 and dt = 0.1 s a point at
// rest gains (g dt^2) = -0.1 m of displacement in one substep, whatever the damping.
TEST(HandWorked, DampingKeepsEightyPercentOfTheDisplacementAtTwentyPercent) {
  expectNear(physics::integrateVerlet<double>({0.01, 0, 0}, {0, 0, 0}, 0.01, 0.8), dvec3(0.008, 0, 0));
  expectNear(physics::integrateVerlet<double>({0, 0, 0}, {0, -10, 0}, 0.01, 0.8), dvec3(0, -0.1, 0));

  Scene s = bareScene(2, 2);
  s.cloth.damping = 20.0;
  s.sim.frames_per_sec = 10.0;
  CpuSolver<double> solver(s);
  const std::vector<dvec3> x = solver.topology().initial_positions;
  solver.setState(x, std::vector<dvec3>(4, dvec3(0.01, 0.0, 0.0)));
  solver.step();
  for (std::size_t i = 0; i < 4; ++i) {
    expectNear(solver.readDisplacements()[i], dvec3(0.008, 0.0, 0.0));
    expectNear(solver.readPositions()[i], x[i] + dvec3(0.008, 0.0, 0.0));
  }
}

// --- sphere friction -----------------------------------------------------------------------------

// Unit sphere at the origin. The point moved from x_prev = (-0.1, 1.2, 0) by v = (0.4, -0.8, 0) to
// x = (0.3, 0.4, 0), which is inside (|x| = 0.5). Its nearest surface point is x / |x| = (0.6, 0.8, 0).
// The response is x' = x_prev + (1 - f)(target - x_prev); target - x_prev = (0.7, -0.4, 0):
//   f = 0.5: x' = (-0.1 + 0.35, 1.2 - 0.2, 0) = (0.25, 1.0, 0), a correction c = x' - x = (-0.05, 0.6, 0)
//   f = 0:   x' = target, c = (0.3, 0.4, 0)
//   f = 1:   x' = x_prev (a touching point stops), c = -v
TEST(HandWorked, SphereFrictionStopsThePointOnTheChordFromItsLastPosition) {
  const dvec3 x(0.3, 0.4, 0.0), v(0.4, -0.8, 0.0), centre(0.0);
  dvec3 c;
  ASSERT_TRUE(physics::collideSphere(x, v, centre, 1.0, 0.5, c));
  expectNear(c, dvec3(-0.05, 0.6, 0.0));
  ASSERT_TRUE(physics::collideSphere(x, v, centre, 1.0, 0.0, c));
  expectNear(c, dvec3(0.3, 0.4, 0.0));
  ASSERT_TRUE(physics::collideSphere(x, v, centre, 1.0, 1.0, c));
  expectNear(c, -v);
  // Outside the sphere nothing happens.
  EXPECT_FALSE(physics::collideSphere(dvec3(0.0, 1.01, 0.0), v, centre, 1.0, 0.5, c));
}

// --- plane ---------------------------------------------------------------------------------------

// Plane y = 0. From x_prev = (0, 0.1, 0) by v = (0.1, -0.2, 0) to x = (0.1, -0.1, 0): the segment
// meets the plane half way, at (0.05, 0, 0); the target is 1e-4 m above it (kSurfaceOffset, on
// x_prev's side). Frictionless, the point goes there: c = target - x = (-0.05, 0.1001, 0).
TEST(HandWorked, PlaneStopsACrossingPointJustAboveWhereItCrossed) {
  dvec3 c;
  ASSERT_TRUE(physics::collidePlane<double>({0.1, -0.1, 0}, {0.1, -0.2, 0}, {0, 0, 0}, {0, 1, 0}, 0.0, c));
  expectNear(c, dvec3(-0.05, 0.1 + physics::kSurfaceOffset, 0.0));
}

// x_prev within the kPlaneEpsilon band below the plane counts as above it (it is where a point that
// started on the plane lands after rounding). Such a point moving up too slowly to reach the plane,
// x_prev.y = -0.8 um, v = (0.5 mm, 0.1 um, 0), ends at y = -0.7 um, still "crossed". The line through
// x_prev and x meets the plane at s = 8, seven steps ahead of x: the unclamped response moved the point
// 7 * 0.5 mm = 3.5 mm along x. Clamped to the step's segment it stays at x, lifted to the offset.
TEST(HandWorked, PlaneBandBelowThePlaneDoesNotThrowThePointSideways) {
  const double band = 0.8e-6;
  ASSERT_LT(band, physics::kPlaneEpsilon);
  for (double friction : {0.0, 0.5}) {
    const dvec3 v(0.5e-3, 0.1e-6, 0.0);
    const dvec3 x = dvec3(0.2, -band, 0.3) + v;
    dvec3 c;
    ASSERT_TRUE(physics::collidePlane<double>(x, v, {0, 0, 0}, {0, 1, 0}, friction, c));
    const dvec3 after = x + c, x_prev = x - v;
    // Between x_prev and x along x: no farther than the step itself went (friction takes motion away).
    EXPECT_GE(after.x - x_prev.x, -1e-12) << "friction " << friction;
    EXPECT_LE(after.x - x_prev.x, v.x + 1e-12) << "friction " << friction;
    EXPECT_GT(after.y, 0.0) << "friction " << friction;
    EXPECT_LE(after.y, physics::kSurfaceOffset) << "friction " << friction;
    // Float, as the GPU and CpuSolver<float> compute it.
    glm::vec3 cf;
    ASSERT_TRUE(physics::collidePlane<float>(glm::vec3(x), glm::vec3(v), glm::vec3(0), {0, 1, 0}, float(friction), cf));
    EXPECT_LE(std::abs(double(cf.x) + double(friction) * v.x), 1e-9) << "friction " << friction;
  }
}

}  // namespace
}  // namespace drape
