// The tether pass on the GPU against CpuSolver<float>: the pass alone from a stretched state, whole runs
// with either integrator (tethers switched on live in one), and what a substep dispatches. Bit for bit
// on llvmpipe, as every other pass (docs/design.md section 7).
#include "core/tethers.hpp"
#include "gl_fixture.hpp"
#include "gpu/gpu_solver.hpp"
#include "gpu_test_support.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <optional>

namespace drape {
namespace {

using gpu_test::changedPoints;
using gpu_test::floatUlp;
using gpu_test::maxAbs;
using gpu_test::maxComponentDifference;

// As the other GL tests that compare: llvmpipe's work groups racing, so that an order dependence shows.
const bool kThreaded = [] { return setenv("LP_NUM_THREADS", "2", 1) == 0; }();

constexpr double kUlps = 4.0;  // per pass, where the driver may round division and square root differently

Scene tethered(const char* file, Integrator integrator) {
  Scene scene = gpu_test::standardScene(file);
  scene.sim.tethers = true;
  scene.sim.integrator = integrator;
  return scene;
}

class GpuTethers : public GlTest {};

class GpuTethersPass : public GlTest, public ::testing::WithParamInterface<GpuPath> {};

// pinned4 stretched away from its first pin by 0 to 40% (half the points beyond some tether's limit), on
// each path: tether.comp, and the one-dispatch kernel's tether phase.
TEST_P(GpuTethersPass, MatchesTheCpuFloatPass) {
  ASSERT_TRUE(kThreaded);
  const Scene scene = tethered("pinned4.json", Integrator::Verlet);
  CpuSolver<float> cpu(scene);
  GpuSolver gpu(scene, {.path = GetParam()});
  ASSERT_TRUE(gpu.usesTethers());
  ASSERT_EQ(gpu.oneDispatch(), GetParam() == GpuPath::OneDispatch) << gpu.oneDispatchMisfit();
  const Topology& t = cpu.topology();
  const glm::dvec3 pin = t.initial_positions[0];
  std::vector<glm::dvec3> x(t.initial_positions.size()), v(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    x[i] = t.pinned[i] ? t.initial_positions[i]
                       : gpu_test::asFloat(pin + (1.0 + 0.4 * double(i % 7) / 6.0) * (t.initial_positions[i] - pin));
    v[i] = gpu_test::asFloat(glm::dvec3(0.001 * double(i % 3), -0.002, 0));
  }
  cpu.setState(x, v);
  cpu.tether();
  gpu.uploadState(x, v, 0);
  gpu.tether();
  const auto xc = cpu.readPositions(), xg = gpu.readPositions();
  const double bound = gpu_test::exactDevice(info()) ? 0.0 : kUlps * floatUlp(maxAbs(x));
  const double dx = maxComponentDifference(xc, xg);
  const double dv = maxComponentDifference(cpu.readDisplacements(), gpu.readDisplacements());
  std::printf("tether pass: moved %d of %zu points, max |dx| %.3g m, max |dv| %.3g m (bound %.3g m)\n",
              changedPoints(x, xc), x.size(), dx, dv, bound);
  EXPECT_GT(changedPoints(x, xc), int(x.size()) / 4);
  EXPECT_LE(dx, bound);
  EXPECT_LE(dv, bound);
}

INSTANTIATE_TEST_SUITE_P(Paths, GpuTethersPass, ::testing::Values(GpuPath::General, GpuPath::OneDispatch),
                         [](const ::testing::TestParamInfo<GpuPath>& p) {
                           return std::string(p.param == GpuPath::General ? "general" : "onedispatch");
                         });

struct RunCase {
  const char* name;
  const char* scene;
  Integrator integrator;
  int tethers_from;    // the frame after which both solvers switch tethers on (0: from the start)
  double ks;           // N/m
  int stretch_passes;  // with the scene's 1, the stretch limit keeps a 50 x 50 cloth off its tethers
  GpuPath path;
};

class GpuTethersRun : public GlTest, public ::testing::WithParamInterface<RunCase> {};

// Compared every frame, bit for bit on llvmpipe; elsewhere each substep may add the per-pass bound.
TEST_P(GpuTethersRun, StaysWithTheCpuFloatRun) {
  ASSERT_TRUE(kThreaded);
  const RunCase c = GetParam();
  Scene scene = tethered(c.scene, c.integrator);
  scene.sim.tethers = c.tethers_from == 0;
  scene.cloth.ks = c.ks;
  scene.sim.stretch_passes = c.stretch_passes;
  GpuSolver gpu(scene, {.path = c.path});
  ASSERT_EQ(gpu.oneDispatch(), c.path == GpuPath::OneDispatch) << gpu.oneDispatchMisfit();
  CpuSolver<float> cpu(scene);
  Scene without = scene;
  without.sim.tethers = false;
  CpuSolver<float> untethered(without);
  std::optional<gpu_test::RoundingTwin> twin;
  if (!gpu_test::exactDevice(gpu.contextInfo())) twin.emplace(scene);
  const double size = clothSize(scene.cloth);
  for (int f = 1; f <= 45; ++f) {
    untethered.stepFrame();
    if (f == c.tethers_from + 1 && !scene.sim.tethers) {
      scene.sim.tethers = true;
      gpu.setParams(scene.cloth, scene.sim);
      cpu.setParams(scene.cloth, scene.sim);
      if (twin) twin->setParams(scene.cloth, scene.sim);
      ASSERT_TRUE(gpu.usesTethers());
    }
    gpu.stepFrame();
    cpu.stepFrame();
    if (twin) twin->stepFrame();
    const auto xg = gpu.readPositions(), xc = cpu.readPositions();
    const double bound =
        !twin ? 0.0
              : twin->bound(xc, size, double(gpu.substeps()) * kUlps * floatUlp(std::max(maxAbs(xc), 1.0)) / size);
    if (bound > 0.0 && maxDeviation(xg, xc) / size > bound) {
      // Where it parted, for a device that is not bit-identical: the point, whether pinned, its anchors
      std::size_t worst = 0;
      for (std::size_t i = 0; i < xg.size(); ++i)
        if (glm::length(xg[i] - xc[i]) > glm::length(xg[worst] - xc[worst])) worst = i;
      const Topology& topo = gpu.topology();
      std::printf("%s frame %d: worst point %zu (u %zu, v %zu)%s, gpu (%.6f %.6f %.6f) cpu (%.6f %.6f %.6f)\n", c.name,
                  f, worst, worst % std::size_t(topo.W), worst / std::size_t(topo.W),
                  topo.pinned[worst] ? " pinned" : "", xg[worst].x, xg[worst].y, xg[worst].z, xc[worst].x, xc[worst].y,
                  xc[worst].z);
    }
    ASSERT_LE(maxDeviation(xg, xc) / size, bound) << c.name << " frame " << f;
    if (bound == 0.0) {
      ASSERT_EQ(changedPoints(gpu.readDisplacements(), cpu.readDisplacements()), 0) << "frame " << f;
    }
  }
  EXPECT_TRUE(gpu.health().ok());
  EXPECT_GT(changedPoints(cpu.readPositions(), untethered.readPositions()), 0) << "the tethers must have acted";
}

INSTANTIATE_TEST_SUITE_P(Scenes, GpuTethersRun,
                         ::testing::Values(RunCase{"pinned2_xpbd", "pinned2.json", Integrator::Xpbd, 0, 500, 0,
                                                   GpuPath::Auto},
                                           RunCase{"pinned2_onedispatch_live", "pinned2.json", Integrator::Verlet, 15,
                                                   500, 0, GpuPath::OneDispatch},
                                           RunCase{"pinned4_verlet_live", "pinned4.json", Integrator::Verlet, 15, 5000,
                                                   0, GpuPath::General}),
                         [](const ::testing::TestParamInfo<RunCase>& p) { return std::string(p.param.name); });

// The pass runs after the collisions and before the stretch limit; a cloth without pins has no tethers
// to run.
TEST_F(GpuTethers, TheyRunAfterTheCollisionsBeforeTheStretchLimit) {
  GpuSolver gpu(tethered("pinned2.json", Integrator::Verlet), {.path = GpuPath::General});
  const std::vector<std::string> passes = gpu.passes();
  const auto at = std::find(passes.begin(), passes.end(), kTetherPassName);
  ASSERT_NE(at, passes.end());
  EXPECT_EQ(at - passes.begin(), 1) << "after forces+integrate (+collide)";
  EXPECT_EQ(*(at + 1), "limit_stretch_colour");
  GpuSolver sphere(tethered("sphere.json", Integrator::Verlet), gpu_test::general());
  EXPECT_FALSE(sphere.usesTethers());
  // On the one-dispatch path, a phase of its kernel at the same place.
  GpuSolver one(tethered("pinned2.json", Integrator::Verlet), {.path = GpuPath::OneDispatch});
  const std::vector<std::string> phases = one.passes();
  ASSERT_GE(phases.size(), 3u);
  EXPECT_EQ(phases[1], "in-group tether");
  EXPECT_EQ(phases[2], "in-group limit_stretch_colour");
  const std::vector<std::string> sphere_passes = sphere.passes();
  EXPECT_EQ(std::count(sphere_passes.begin(), sphere_passes.end(), kTetherPassName), 0);
}

}  // namespace
}  // namespace drape
