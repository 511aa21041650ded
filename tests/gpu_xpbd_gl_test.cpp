// The implicit integrators, XPBD and VBD, on the GPU against CpuSolver<float>: each pass alone from the
// same state, whole runs, and two GPU runs against each other. On llvmpipe all three are bit for bit
// (docs/design.md section 7).
#include "gl_fixture.hpp"
#include "gpu/gpu_solver.hpp"
#include "gpu_test_support.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <ostream>

namespace drape {
namespace {

using gpu_test::floatUlp;
using gpu_test::maxAbs;
using gpu_test::maxComponentDifference;

// Worker threads for llvmpipe, set before the first context exists: CTest runs GL tests with
// LP_NUM_THREADS=0, where work groups run one after another and thread order could never vary; the
// comparisons here must hold with work groups racing too.
const bool kThreaded = [] { return setenv("LP_NUM_THREADS", "2", 1) == 0; }();

// As tests/gpu_passes_gl_test.cpp: 4 float ulps of the largest input coordinate per pass where the
// driver may round division and square root differently, 0 on llvmpipe.
constexpr double kUlps = 4.0;

Scene xpbdScene(const char* file, int iterations, bool self_collision, Integrator integrator = Integrator::Xpbd) {
  Scene scene = gpu_test::standardScene(file);
  scene.sim.integrator = integrator;
  scene.sim.iterations = iterations;
  scene.sim.self_collision = scene.sim.self_collision && self_collision;
  return scene;
}

bool hasColliders(const Scene& s) {
  return !s.spheres.empty() || !s.planes.empty() || !s.meshes.empty();
}

struct XpbdCase {
  const char* name;
  const char* scene;
  int frames;  // CPU float frames before the compared state
  int iterations;
  bool self_collision;
  Integrator integrator = Integrator::Xpbd;
};

void PrintTo(const XpbdCase& c, std::ostream* os) {
  *os << c.name;
}

struct State {
  std::vector<glm::dvec3> x, v;
};

// A few points moved half a spacing towards their right-hand neighbour, inside the self-collision range,
// or lifted by 15 mm, beyond the stretch limit: a pass compared where it does nothing proves nothing.
State nudged(const State& in, const Topology& topo, bool towards_neighbour) {
  State out = in;
  for (int k = 1; k <= 5; ++k) {
    const int x = k * (topo.W - 2) / 6, y = k * (topo.H - 1) / 6;
    const std::size_t i = std::size_t(y * topo.W + x);
    if (topo.pinned[i] || topo.pinned[i + 1]) continue;
    if (towards_neighbour)
      out.x[i + 1] = in.x[i] + 0.5 * (in.x[i + 1] - in.x[i]);
    else
      out.x[i].y += 0.015;
  }
  return out;
}

class GpuXpbdPass : public GlTest, public ::testing::WithParamInterface<XpbdCase> {
 protected:
  void compare(const char* stage, const State& in, const State& cpu, const State& gpu) {
    const double bound = gpu_test::exactDevice(info()) ? 0.0 : kUlps * floatUlp(maxAbs(in.x));
    const double dx = maxComponentDifference(cpu.x, gpu.x), dv = maxComponentDifference(cpu.v, gpu.v);
    std::printf("%-18s %-22s moved %5d points, max |dx| %.3g m, max |dv| %.3g m (bound %.3g m)\n", GetParam().name,
                stage, gpu_test::changedPoints(in.x, cpu.x), dx, dv, bound);
    EXPECT_GT(gpu_test::changedPoints(in.x, cpu.x), 0)
        << stage << " must move points for the comparison to mean anything";
    EXPECT_LE(dx, bound) << stage << ": positions";
    EXPECT_LE(dv, bound) << stage << ": displacements";
  }
};

TEST_P(GpuXpbdPass, EachPassMatchesTheCpuFloatPass) {
  ASSERT_TRUE(kThreaded);
  const XpbdCase c = GetParam();
  const Scene scene = xpbdScene(c.scene, c.iterations, c.self_collision, c.integrator);
  const bool colliders = hasColliders(scene);
  const bool vbd = c.integrator == Integrator::Vbd;
  const auto cpuSolve = vbd ? &CpuSolver<float>::solveVbd : &CpuSolver<float>::solveXpbd;
  CpuSolver<float> cpu(scene);
  for (int f = 0; f < c.frames; ++f)
    cpu.stepFrame();
  gpu_test::stepUntilCollisionsHaveWork(cpu, [&](CpuSolver<float>& probe) {
    probe.accumulateForces();
    probe.integrate();
    (probe.*cpuSolve)();
  });
  GpuSolver gpu(scene, gpu_test::general());
  const Topology& topo = cpu.topology();
  auto cpuState = [&] { return State{cpu.readPositions(), cpu.readDisplacements()}; };
  auto runGpu = [&](const State& in, void (GpuSolver::*stage)()) {
    gpu.uploadState(in.x, in.v, cpu.substeps());
    (gpu.*stage)();
    return State{gpu.readPositions(), gpu.readDisplacements()};
  };
  EXPECT_FALSE(gpu.collideFusedWithIntegrate());

  const State start = cpuState();
  ASSERT_TRUE(allFinite(start.x));
  cpu.accumulateForces();
  cpu.integrate();
  const State predicted = cpuState();
  compare("forces+predict", start, predicted, runGpu(start, &GpuSolver::forcesIntegrate));

  (cpu.*cpuSolve)();
  const State solved = cpuState();
  compare(vbd ? "vbd sweeps" : "xpbd sweeps", predicted, solved,
          runGpu(predicted, vbd ? &GpuSolver::solveVbd : &GpuSolver::solveXpbd));

  State before_stretch = solved;
  if (scene.sim.self_collision) {
    State in = solved;
    cpu.selfCollide();
    if (gpu_test::changedPoints(in.x, cpu.readPositions()) == 0) {
      in = nudged(solved, topo, true);
      cpu.setState(in.x, in.v);
      cpu.selfCollide();
    }
    if (colliders) cpu.collide();
    before_stretch = cpuState();
    compare("self_collide(+collide)", in, before_stretch, runGpu(in, &GpuSolver::selfCollide));
  } else if (colliders) {
    cpu.collide();
    before_stretch = cpuState();
    compare("collide", solved, before_stretch, runGpu(solved, &GpuSolver::collide));
  }

  State in = before_stretch;
  cpu.setState(in.x, in.v);
  cpu.limitStretch();
  if (gpu_test::changedPoints(in.x, cpu.readPositions()) == 0) {
    in = nudged(before_stretch, topo, false);
    cpu.setState(in.x, in.v);
    cpu.limitStretch();
  }
  compare("limit_stretch", in, cpuState(), runGpu(in, &GpuSolver::limitStretch));
}

// The hanging cloths are stretched after 10 frames, the sphere cloth drapes over its sphere after ~48,
// the plane cloth reaches the floor after ~66, the selfCollision cloth folds onto itself within ~20.
INSTANTIATE_TEST_SUITE_P(
    Scenes, GpuXpbdPass,
    ::testing::Values(XpbdCase{"pinned2", "pinned2.json", 10, 1, true},
                      XpbdCase{"pinned4_3sweeps", "pinned4.json", 10, 3, true},
                      XpbdCase{"sphere", "sphere.json", 48, 1, true},
                      XpbdCase{"sphere_no_self", "sphere.json", 48, 2, false},
                      XpbdCase{"plane_no_self", "plane.json", 65, 1, false}, XpbdCase{"wind", "wind.json", 10, 1, true},
                      XpbdCase{"selfCollision", "selfCollision.json", 60, 2, true},
                      XpbdCase{"vbd_pinned2", "pinned2.json", 10, 1, true, Integrator::Vbd},
                      XpbdCase{"vbd_pinned4_3sweeps", "pinned4.json", 10, 3, true, Integrator::Vbd},
                      XpbdCase{"vbd_sphere", "sphere.json", 48, 1, true, Integrator::Vbd},
                      XpbdCase{"vbd_plane_no_self", "plane.json", 65, 2, false, Integrator::Vbd},
                      XpbdCase{"vbd_wind", "wind.json", 10, 1, true, Integrator::Vbd}),
    [](const ::testing::TestParamInfo<XpbdCase>& p) { return std::string(p.param.name); });

class GpuXpbdRun : public GlTest, public ::testing::WithParamInterface<XpbdCase> {};

// Half a simulated second, compared every frame. Bit for bit on llvmpipe; elsewhere each substep may
// add the per-pass bound, as in tests/gpu_runs_gl_test.cpp.
TEST_P(GpuXpbdRun, RunsStayWithTheCpuFloatRun) {
  const XpbdCase c = GetParam();
  const Scene scene = xpbdScene(c.scene, c.iterations, c.self_collision, c.integrator);
  GpuSolver gpu(scene, gpu_test::general());
  CpuSolver<float> cpu(scene);
  const bool exact = gpu_test::exactDevice(gpu.contextInfo());
  std::optional<gpu_test::RoundingTwin> twin;
  if (!exact) twin.emplace(scene);
  const double size = clothSize(scene.cloth);
  double worst = 0;
  for (int f = 1; f <= c.frames; ++f) {
    gpu.stepFrame();
    cpu.stepFrame();
    if (twin) twin->stepFrame();
    const auto xg = gpu.readPositions(), xc = cpu.readPositions();
    ASSERT_TRUE(allFinite(xc)) << "frame " << f;
    const double bound =
        exact ? 0.0
              : twin->bound(xc, size, double(gpu.substeps()) * kUlps * floatUlp(std::max(maxAbs(xc), 1.0)) / size);
    const double relative = maxDeviation(xg, xc) / size;
    worst = std::max(worst, relative);
    ASSERT_LE(relative, bound) << c.name << " frame " << f;
    if (bound == 0.0) {
      ASSERT_EQ(gpu_test::changedPoints(gpu.readDisplacements(), cpu.readDisplacements()), 0) << "frame " << f;
    }
  }
  EXPECT_GT(maxDeviation(cpu.readPositions(), cpu.topology().initial_positions), 0.05) << "the cloth must move";
  EXPECT_TRUE(gpu.health().ok());
  std::printf("%-18s %d frames: largest deviation %.3g of the cloth size\n", c.name, c.frames, worst);
}

INSTANTIATE_TEST_SUITE_P(
    Scenes, GpuXpbdRun,
    ::testing::Values(XpbdCase{"pinned2", "pinned2.json", 45, 1, true},
                      XpbdCase{"pinned4_4sweeps", "pinned4.json", 45, 4, true},
                      XpbdCase{"sphere", "sphere.json", 60, 1, true},
                      XpbdCase{"plane_no_self", "plane.json", 75, 1, false}, XpbdCase{"wind", "wind.json", 45, 2, true},
                      XpbdCase{"vbd_pinned2", "pinned2.json", 45, 1, true, Integrator::Vbd},
                      XpbdCase{"vbd_pinned4_4sweeps", "pinned4.json", 45, 4, true, Integrator::Vbd},
                      XpbdCase{"vbd_sphere", "sphere.json", 60, 1, true, Integrator::Vbd}),
    [](const ::testing::TestParamInfo<XpbdCase>& p) { return std::string(p.param.name); });

void expectRepeatedRunsBitIdentical(const Scene& scene, int frames) {
  GpuSolver first(scene, gpu_test::general()), second(scene, gpu_test::general());
  for (int f = 1; f <= frames; ++f) {
    first.stepFrame();
    second.stepFrame();
    if (f % 20 != 0) continue;
    const auto x1 = first.readPositions();
    ASSERT_TRUE(allFinite(x1)) << "frame " << f;
    ASSERT_EQ(gpu_test::changedPoints(x1, second.readPositions()), 0) << "positions differ after frame " << f;
    ASSERT_EQ(gpu_test::changedPoints(first.readDisplacements(), second.readDisplacements()), 0)
        << "displacements differ after frame " << f;
  }
}

class GpuXpbdDeterminism : public GlTest {};

// Two GPU runs of the self-collision scene with XPBD (2 sweeps, so the multipliers' buffer is used), and
// with VBD (2 sweeps: the prediction's buffer), are bit-identical, with llvmpipe's work groups racing
// (kThreaded).
TEST_F(GpuXpbdDeterminism, RepeatedRunsAreBitIdentical) {
  ASSERT_TRUE(kThreaded);
  for (Integrator integrator : {Integrator::Xpbd, Integrator::Vbd}) {
    SCOPED_TRACE(integratorName(integrator));
    const Scene scene = xpbdScene("selfCollision.json", 2, true, integrator);
    expectRepeatedRunsBitIdentical(scene, integrator == Integrator::Xpbd ? 60 : 40);
  }
}

class GpuXpbdPlan : public GlTest {};

// What a substep dispatches with XPBD: the prediction, one dispatch per colour and sweep, then the
// collisions as a pass of their own (no self-collision) or the lists' travel check before self-collision,
// and the collisions again after the stretch limit.
// A live switch between the integrators replans and recompiles.
TEST_F(GpuXpbdPlan, PassesFollowTheIntegratorAndSweeps) {
  const auto count = [](const std::vector<std::string>& passes, const char* name) {
    return std::count(passes.begin(), passes.end(), std::string(name));
  };
  GpuSolver plane(xpbdScene("plane.json", 3, false), gpu_test::general());
  const std::vector<std::string> p = plane.passes();
  ASSERT_FALSE(p.empty());
  EXPECT_EQ(p.front(), "forces+predict");
  EXPECT_EQ(count(p, "xpbd_colour"), 3 * 12);
  EXPECT_EQ(count(p, "collide"), 2);  // after the sweeps, and again after the stretch limit
  EXPECT_EQ(p.back(), "collide");
  EXPECT_EQ(count(p, "pairs_check"), 0);
  EXPECT_EQ(plane.dispatchesPerFrame(), int(p.size()) * plane.scene().sim.steps_per_frame + 1);

  // General: a live switch to Verlet would move Auto to the one-dispatch path on a GPU
  GpuSolver sphere(xpbdScene("sphere.json", 1, true), {.path = GpuPath::General});
  const std::vector<std::string> s = sphere.passes();
  EXPECT_EQ(count(s, "xpbd_colour"), 12);
  EXPECT_EQ(count(s, "collide"), 1);  // fused into self_collide, then again after the stretch limit
  EXPECT_EQ(count(s, "pairs_check"), 1);
  EXPECT_EQ(count(s, "self_collide+collide"), 1);

  // Live: back to Verlet, then to XPBD again, each with the other's plan gone.
  Scene verlet = sphere.scene();
  verlet.sim.integrator = Integrator::Verlet;
  sphere.setParams(verlet.cloth, verlet.sim);
  const std::vector<std::string> v = sphere.passes();
  EXPECT_EQ(v.front(), "forces+integrate+pairs_check");
  EXPECT_EQ(count(v, "xpbd_colour"), 0);
  EXPECT_EQ(count(v, "pairs_check"), 0);
  verlet.sim.integrator = Integrator::Xpbd;
  verlet.sim.iterations = 2;
  sphere.setParams(verlet.cloth, verlet.sim);
  EXPECT_EQ(count(sphere.passes(), "xpbd_colour"), 24);
  for (int f = 0; f < 5; ++f)
    sphere.stepFrame();
  EXPECT_TRUE(sphere.health().ok());
}

// With VBD: the prediction, one dispatch per point colour and sweep (each over that colour's points),
// then the collisions as for XPBD (twice); switched live from XPBD, which drops the spring-colour dispatches.
TEST_F(GpuXpbdPlan, VbdDispatchesOncePerPointColourAndSweep) {
  const auto count = [](const std::vector<std::string>& passes, const char* name) {
    return std::count(passes.begin(), passes.end(), std::string(name));
  };
  GpuSolver plane(xpbdScene("plane.json", 3, false, Integrator::Vbd), gpu_test::general());
  const int colours = colourPoints(plane.topology()).colourCount();
  const std::vector<std::string> p = plane.passes();
  ASSERT_FALSE(p.empty());
  EXPECT_EQ(p.front(), "forces+predict");
  EXPECT_EQ(count(p, "vbd_colour"), 3 * colours);
  EXPECT_EQ(count(p, "xpbd_colour"), 0);
  EXPECT_EQ(count(p, "collide"), 2);
  EXPECT_EQ(plane.dispatchesPerFrame(), int(p.size()) * plane.scene().sim.steps_per_frame + 1);

  GpuSolver sphere(xpbdScene("sphere.json", 1, true), gpu_test::general());
  Scene vbd = sphere.scene();
  vbd.sim.integrator = Integrator::Vbd;
  vbd.sim.iterations = 2;  // the prediction's buffer, made on the switch
  sphere.setParams(vbd.cloth, vbd.sim);
  const std::vector<std::string> s = sphere.passes();
  EXPECT_EQ(count(s, "xpbd_colour"), 0);
  EXPECT_EQ(count(s, "vbd_colour"), 2 * colours);
  EXPECT_EQ(count(s, "pairs_check"), 1);
  for (int f = 0; f < 5; ++f)
    sphere.stepFrame();
  EXPECT_TRUE(sphere.health().ok());
  EXPECT_GT(maxDeviation(sphere.readPositions(), sphere.topology().initial_positions), 0.01) << "it must move";
}

}  // namespace
}  // namespace drape
