// The explicit-integration bound (core/stability.hpp): the per-vertex stiffness sum, the bound on the
// stiffness matrix's largest eigenvalue, Verlet's limit, autoSubsteps, and the blow-up test.
#include "core/stability.hpp"
#include "core/derived.hpp"
#include "cpu/cpu_solver.hpp"
#include "cpu/physics.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace drape {
namespace {

Scene gridScene(int w, int h, double ks = 5000.0, double density = 150.0) {
  Scene s;
  s.cloth.num_width_points = w;
  s.cloth.num_height_points = h;
  s.cloth.ks = ks;
  s.cloth.density = density;
  s.sim.self_collision = false;
  return s;
}

// Counted by hand from the spring pattern (structural: left, right, up, down; shearing: the four
// diagonals; bending: two away along each axis, at 0.2 ks), at the point with the most springs:
//   50 x 50, all on: an interior point, 4 + 4 + 4 * 0.2 = 8.8 ks
//   2 x 2: every point is a corner, 2 structural + 1 shearing, no bending = 3 ks
//   3 x 3: the centre, 4 + 4 and no bending (nothing two away on both sides) = 8 ks; a corner has
//          2 + 1 + 2 * 0.2 = 3.4 ks, an edge middle 3 + 2 + 0.2 = 5.2 ks
//   2 x 50: an interior point of a long edge, 3 structural + 2 shearing + 2 * 0.2 = 5.4 ks
//   5 x 5, bending only: the centre, 4 * 0.2 = 0.8 ks; 50 x 50, shearing only: 4 ks
//   2 x 7, structural only: 1 across + 2 along = 3 ks
TEST(Stability, MaxStiffnessSumIsTheHandCountedLargestVertexSum) {
  struct Case {
    int w, h;
    bool structural, shearing, bending;
    double ks_multiple;
  };
  const Case cases[] = {{50, 50, true, true, true, 8.8}, {2, 2, true, true, true, 3.0},
                        {3, 3, true, true, true, 8.0},   {2, 50, true, true, true, 5.4},
                        {5, 5, false, false, true, 0.8}, {50, 50, false, true, false, 4.0},
                        {2, 7, true, false, false, 3.0}, {50, 50, false, false, false, 0.0}};
  for (const Case& c : cases) {
    Scene s = gridScene(c.w, c.h, 1000.0);
    s.cloth.enable_structural = c.structural;
    s.cloth.enable_shearing = c.shearing;
    s.cloth.enable_bending = c.bending;
    EXPECT_NEAR(maxStiffnessSum(s.cloth), c.ks_multiple * 1000.0, 1e-9)
        << c.w << "x" << c.h << " structural " << c.structural << " shearing " << c.shearing << " bending "
        << c.bending;
  }
}

// The standard scenes: dt = 1/2700 s, k_sum = 8.8 * 5000 = 44000 N/m, m = 0.06 kg, so
// dt sqrt(k_sum / m) = sqrt(733333) / 2700 = 856.35 / 2700 = 0.3172; the limit at 0.2 % damping is
// sqrt(1 + 0.998) = 1.4135 (scenes/README.md quotes 0.32).
TEST(Stability, TheStandardSceneNumberWorkedByHand) {
  const Scene s = gridScene(50, 50);
  EXPECT_NEAR(stabilityNumber(s), 0.3172, 1e-4);
  EXPECT_NEAR(stabilityLimit(0.2), 1.4135, 1e-4);
  EXPECT_TRUE(checkStability(s).ok);
}

// Damped Verlet on x'' = -w^2 x is stable exactly for w dt < sqrt(2 (1 + keep)): 2 undamped, sqrt(2)
// at 100 % damping. The limit the guard is derived from.
double oscillatorPeak(double w_dt, double keep) {
  double x = 1.0, v = 0.0, peak = 0.0;
  for (int i = 0; i < 20000; ++i) {
    v = physics::integrateVerlet<double>(glm::dvec3(v), glm::dvec3(-w_dt * w_dt * x), 1.0, keep).x;
    x += v;
    peak = std::max(peak, std::abs(x));
  }
  return peak;
}

TEST(Stability, VerletOnAnOscillatorIsStableBelowItsLimitAndNotAbove) {
  // Undamped, below the limit the amplitude stays within 1/sqrt(1 - (w dt/2)^2) of the start.
  EXPECT_LT(oscillatorPeak(1.9, 1.0), 1.0 / std::sqrt(1.0 - 0.95 * 0.95) + 1e-6);
  EXPECT_GT(oscillatorPeak(2.05, 1.0), 1e6);
  for (double keep : {0.0, 0.5, 0.998}) {
    const double limit = std::sqrt(2.0 * (1.0 + keep));
    EXPECT_LT(oscillatorPeak(0.98 * limit, keep), 1e3) << keep;
    EXPECT_GT(oscillatorPeak(1.02 * limit, keep), 1e6) << keep;
    EXPECT_DOUBLE_EQ(std::sqrt(2.0) * stabilityLimit(100.0 * (1.0 - keep)), limit);
  }
}

// Largest eigenvalue of the linearised stiffness matrix of a free grid at `scale` times its rest size,
// by power iteration; `residual` says how well it converged (|K v - lambda v| for unit v).
double largestStiffnessEigenvalue(const ClothSpec& cloth, double scale, double& residual) {
  const Topology topo = buildTopology(cloth);
  const std::size_t n = std::size_t(topo.pointCount()) * 3;
  std::vector<double> K(n * n, 0.0);
  for (const Spring& s : topo.springs) {
    if (!cloth.springEnabled(s.type)) continue;
    const double k = derived::springStiffness(cloth, s.type);
    const glm::dvec3 d = scale * (topo.initial_positions[s.b] - topo.initial_positions[s.a]);
    const double len = glm::length(d);
    const glm::dvec3 u = d / len;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) {
        const double b = k * u[r] * u[c] + k * (1.0 - s.rest / len) * ((r == c ? 1.0 : 0.0) - u[r] * u[c]);
        K[(s.a * 3 + r) * n + s.a * 3 + c] += b;
        K[(s.b * 3 + r) * n + s.b * 3 + c] += b;
        K[(s.a * 3 + r) * n + s.b * 3 + c] -= b;
        K[(s.b * 3 + r) * n + s.a * 3 + c] -= b;
      }
  }
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  std::vector<double> v(n), w(n);
  for (double& x : v)
    x = uni(rng);
  double lambda = 0;
  for (int it = 0; it < 3000; ++it) {
    double norm = 0;
    for (double x : v)
      norm += x * x;
    norm = std::sqrt(norm);
    for (double& x : v)
      x /= norm;
    for (std::size_t i = 0; i < n; ++i) {
      double sum = 0;
      for (std::size_t j = 0; j < n; ++j)
        sum += K[i * n + j] * v[j];
      w[i] = sum;
    }
    lambda = 0;
    for (std::size_t i = 0; i < n; ++i)
      lambda += v[i] * w[i];
    residual = 0;
    for (std::size_t i = 0; i < n; ++i)
      residual += (w[i] - lambda * v[i]) * (w[i] - lambda * v[i]);
    residual = std::sqrt(residual);
    v.swap(w);
  }
  return lambda;
}

// Power iteration finds the eigenvalue of largest magnitude. At rest and stretched it is the largest
// positive one; compressed to 0.6 of rest it is the negative transverse (buckling) one, whose
// magnitude the bound covers too as long as springs keep at least half their rest length.
TEST(Stability, GershgorinBoundsTheStiffnessMatrix) {
  for (double scale : {1.0, 1.1, 0.6}) {
    const Scene s = gridScene(7, 6);
    double residual = 0;
    const double lambda = largestStiffnessEigenvalue(s.cloth, scale, residual);
    const double bound = 2.0 * maxStiffnessSum(s.cloth);
    EXPECT_LT(residual, 1e-6 * std::abs(lambda)) << "power iteration did not converge at scale " << scale;
    EXPECT_LE(std::abs(lambda), bound) << "scale " << scale;
    // Conservative, but not uselessly so: within a factor 4 of the truth.
    if (scale >= 1.0) {
      EXPECT_GT(lambda, bound / 4.0) << "scale " << scale;
    }
  }
}

// A free cloth (no pins, no gravity, no stretch limit) from a jittered start, at one substep per frame
// with frames_per_sec chosen so that dt sqrt(k/m) = number. Returns the first frame the blow-up test
// fails (-1 if none) and the max strain at the end.
struct FreeRun {
  int blow_up_frame = -1;
  double final_strain = 0;
};

FreeRun runFreeCloth(double number, int frames, double damping) {
  Scene s = gridScene(8, 8, 5000.0, 150.0);
  s.cloth.damping = damping;
  s.sim.gravity = glm::dvec3(0.0);
  s.sim.stretch_passes = 0;
  s.sim.steps_per_frame = 1;
  s.sim.frames_per_sec = std::sqrt(maxStiffnessSum(s.cloth) / derived::pointMass(s.cloth)) / number;
  EXPECT_NEAR(stabilityNumber(s), number, 1e-12);
  CpuSolver<double> solver(s);
  std::vector<glm::dvec3> x = solver.topology().initial_positions, v(x.size(), glm::dvec3(0));
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> uni(-0.02, 0.02);
  for (glm::dvec3& p : x)
    p += glm::dvec3(uni(rng), uni(rng), uni(rng));
  solver.setState(x, v);
  FreeRun run;
  for (int f = 1; f <= frames; ++f) {
    solver.stepFrame();
    if (!detectBlowUp(solver.topology(), s.cloth, x, solver.readPositions()).empty()) {
      run.blow_up_frame = f;
      return run;
    }
  }
  run.final_strain = maxStrain(solver.topology(), s.cloth, solver.readPositions());
  return run;
}

TEST(Stability, InsideTheBoundStaysBoundedFarOutsideBlowsUp) {
  EXPECT_EQ(runFreeCloth(0.99 * kStabilityLimit, 5000, 0.0).blow_up_frame, -1);
  EXPECT_GT(runFreeCloth(3.0 * kStabilityLimit, 5000, 0.0).blow_up_frame, 0);
}

// At 100 % damping the step is gradient descent on the spring energy and the limit is 1, not sqrt(2).
// Beyond it the springs' nonlinearity keeps the motion bounded (a point overshooting its neighbour
// flips the spring's direction), so nothing blows up: the cloth just never settles.
TEST(Stability, FullDampingHalvesTheStableRange) {
  EXPECT_EQ(stabilityLimit(100.0), 1.0);
  const FreeRun inside = runFreeCloth(0.99, 2000, 100.0);
  const FreeRun outside = runFreeCloth(1.9, 2000, 100.0);  // inside the undamped limit sqrt(2)
  EXPECT_EQ(inside.blow_up_frame, -1);
  EXPECT_LT(inside.final_strain, 0.01);  // relaxing to rest from the jittered start
  EXPECT_GT(outside.final_strain, 0.1);  // still thrashing
}

TEST(Stability, AutoSubstepsIsTheSmallestCountInsideTheBound) {
  for (double ks : {1e2, 5e3, 1e5, 1e6, 1e7})
    for (double density : {1.0, 150.0, 1e4}) {
      Scene s = gridScene(16, 16, ks, density);
      s.cloth.damping = 5.0;  // so that the damping rescale of withSubsteps matters
      const int steps = autoSubsteps(s);
      ASSERT_GE(steps, 1);
      EXPECT_TRUE(checkStability(withSubsteps(s, steps)).ok) << ks << " " << density;
      if (steps > 1) {
        EXPECT_FALSE(checkStability(withSubsteps(s, steps - 1)).ok) << ks << " " << density;
      }
    }
}

TEST(Stability, CheckSaysWhatToDo) {
  Scene s = gridScene(16, 16, 1e6, 15.0);
  const StabilityCheck c = checkStability(s);
  EXPECT_FALSE(c.ok);
  EXPECT_GE(c.number, c.limit);
  EXPECT_NE(c.message.find(std::to_string(autoSubsteps(s)) + " substeps"), std::string::npos) << c.message;
  EXPECT_EQ(c.steps_needed, autoSubsteps(s));
  EXPECT_GT(c.steps_needed, s.sim.steps_per_frame);
  s.cloth.density = 0.0;
  EXPECT_EQ(autoSubsteps(s), 0);
  EXPECT_FALSE(checkStability(s).ok);
  EXPECT_EQ(checkStability(s).steps_needed, 0);
  s.cloth.enable_structural = s.cloth.enable_shearing = s.cloth.enable_bending = false;
  EXPECT_TRUE(checkStability(s).ok);  // no springs, nothing to be stiff
}

// The ks = 1e6 case of `drape stability`, with the stretch limit off so that only the integration is
// tested: the scene's 30 substeps blow up, the guard's count does not.
TEST(Stability, AutoSubstepsMakesAStiffClothStable) {
  Scene s = gridScene(12, 12, 1e6, 15.0);
  s.cloth.pinned = {{0, 0}, {11, 0}, {0, 11}, {11, 11}};
  s.sim.stretch_passes = 0;
  auto run = [](const Scene& scene) {
    CpuSolver<float> solver(scene);
    const Positions start = solver.readPositions();
    for (int f = 1; f <= 90; ++f) {
      solver.stepFrame();
      if (!detectBlowUp(solver.topology(), scene.cloth, start, solver.readPositions()).empty()) return f;
    }
    return -1;
  };
  ASSERT_FALSE(checkStability(s).ok);
  EXPECT_GT(run(s), 0);
  const Scene guarded = withSubsteps(s, autoSubsteps(s));
  ASSERT_TRUE(checkStability(guarded).ok);
  EXPECT_EQ(run(guarded), -1);
}

TEST(Stability, WithSubstepsKeepsTheDampingAndFrictionPerSecond) {
  Scene s = gridScene(4, 4);
  s.cloth.damping = 0.2;
  s.spheres.push_back({glm::dvec3(0.5), 0.2, 0.3});
  s.planes.push_back({glm::dvec3(0.0), glm::dvec3(0, 1, 0), 0.5});
  const double substeps_per_s = s.sim.frames_per_sec * s.sim.steps_per_frame;
  for (int steps : {1, 7, 30, 480}) {
    const Scene t = withSubsteps(s, steps);
    EXPECT_EQ(t.sim.steps_per_frame, steps);
    const double n = t.sim.frames_per_sec * steps;  // substeps per simulated second
    EXPECT_NEAR(std::pow(1.0 - t.cloth.damping / 100.0, n), std::pow(1.0 - 0.002, substeps_per_s), 1e-12);
    EXPECT_NEAR(std::pow(1.0 - t.spheres[0].friction, n), std::pow(1.0 - 0.3, substeps_per_s), 1e-12);
    EXPECT_NEAR(std::pow(1.0 - t.planes[0].friction, n), std::pow(1.0 - 0.5, substeps_per_s), 1e-12);
  }
  s.cloth.damping = 100.0;
  EXPECT_EQ(withSubsteps(s, 5).cloth.damping, 100.0);
  s.cloth.damping = 0.0;
  EXPECT_EQ(withSubsteps(s, 5).cloth.damping, 0.0);
}

TEST(Stability, DetectBlowUpNamesWhatBroke) {
  const Scene s = gridScene(5, 5);
  const Topology topo = buildTopology(s.cloth);
  const Positions start = topo.initial_positions;
  EXPECT_EQ(detectBlowUp(topo, s.cloth, start, start), "");

  Positions x = start;
  x[7].y = NAN;
  EXPECT_NE(detectBlowUp(topo, s.cloth, start, x).find("non-finite"), std::string::npos);

  // Everything moved together far away: no spring stretched, but it ran away.
  x = start;
  for (glm::dvec3& p : x)
    p.y -= 200.0 * clothSize(s.cloth);
  EXPECT_NE(detectBlowUp(topo, s.cloth, start, x).find("from its start"), std::string::npos);

  // One point pulled out to 12 spacings: strain 11 > 10.
  x = start;
  x[12].y += 12.0 * 0.25;
  EXPECT_NE(detectBlowUp(topo, s.cloth, start, x).find("stretched"), std::string::npos);
  x[12].y = start[12].y + 2.0 * 0.25;  // strain ~1.2: large, but not a blow-up
  EXPECT_EQ(detectBlowUp(topo, s.cloth, start, x), "");
}

}  // namespace
}  // namespace drape
