// Whole runs of the standard scenes on the GPU against the CPU float solver, and the physical checks
// of the self-collision scene once the two are allowed to part.
#include "gl_fixture.hpp"
#include "gpu/gpu_solver.hpp"
#include "gpu_test_support.hpp"

#include <cstdio>
#include <optional>
#include <ostream>

namespace drape {
namespace {

// Largest vertex deviation allowed after `substeps`, relative to the cloth size. Each pass agrees with
// the CPU within 4 float ulps of the coordinates (tests/gpu_passes_gl_test.cpp); the cloth is damped
// and, away from contact, does not amplify a perturbation, so the differences at most add up:
// substeps * 4 ulps of the largest coordinate. After 1 s (2700 substeps) at 1 m that is 1.3 mm, 9e-4
// of the 1.41 m diagonal. Self-collision contact can amplify differences, which is why the
// selfCollision scene is compared for 0.2 s only. On llvmpipe every pass is bit-identical, so every
// run is too: the bound there is 0.
double runBound(const gl::ContextInfo& device, long long substeps, double coordinate_scale, double cloth_size) {
  if (gpu_test::exactDevice(device)) return 0.0;
  return double(substeps) * 4.0 * gpu_test::floatUlp(std::max(coordinate_scale, 1.0)) / cloth_size;
}

// Sanity limit: a run whose points leave a box 100x the cloth size has blown up (no use comparing).
bool sane(const std::vector<glm::dvec3>& x, double cloth_size) {
  return allFinite(x) && gpu_test::maxAbs(x) < 100.0 * cloth_size;
}

// Runs both solvers for `frames`, comparing every frame. Returns false when one of them blew up.
bool compareRuns(GpuSolver& gpu, CpuSolver<float>& cpu, int frames, const char* name) {
  const double size = clothSize(cpu.scene().cloth);
  std::optional<gpu_test::RoundingTwin> twin;
  if (!gpu_test::exactDevice(gpu.contextInfo())) twin.emplace(cpu.scene());
  double worst = 0, worst_bound = 0;
  int worst_frame = 0;
  for (int f = 1; f <= frames; ++f) {
    gpu.stepFrame();
    cpu.stepFrame();
    if (twin) twin->stepFrame();
    const auto xg = gpu.readPositions(), xc = cpu.readPositions();
    if (!sane(xc, size)) {
      ADD_FAILURE() << name << ": the CPU float reference blew up by frame " << f << " (nothing to compare)";
      return false;
    }
    if (!sane(xg, size)) {
      ADD_FAILURE() << name << ": the GPU run blew up by frame " << f << " while the CPU did not";
      return false;
    }
    const double relative = maxDeviation(xg, xc) / size;
    double bound = runBound(gpu.contextInfo(), gpu.substeps(), gpu_test::maxAbs(xc), size);
    if (twin) bound = twin->bound(xc, size, bound);
    if (relative >= worst) {
      worst = relative;
      worst_bound = bound;
      worst_frame = f;
    }
    EXPECT_LE(relative, bound) << name << " frame " << f;
  }
  std::printf("%-14s %d frames: largest deviation %.3g of the cloth size (frame %d; bound there %.3g)\n", name, frames,
              worst, worst_frame, worst_bound);
  return true;
}

struct RunCase {
  const char* name;
  const char* scene;
  GpuPath path = GpuPath::General;  // forced: Auto picks per device (llvmpipe General, a GPU one-dispatch)
  bool no_self_collision = false;   // turned off (the one-dispatch path runs none)
  bool jacobi = false;              // the Jacobi stretch scheme instead of the scene's Gauss-Seidel
  int size = 0;                     // resampled to size x size points (0: as the scene has it)
  int frames = 0;                   // frames compared (0: one simulated second)
  // CPU frames run first, the GPU starting from their state: a slow path's case skips the free fall that the
  // general path's case of the scene compares from the start (on llvmpipe the tiled path's frames cost most of
  // CI's GL tests)
  int from_frame = 0;
};

// Test names and CTest listings show the case's name instead of its bytes.
void PrintTo(const RunCase& c, std::ostream* os) {
  *os << c.name;
}

class GpuRunTest : public GlTest, public ::testing::WithParamInterface<RunCase> {};

// One simulated second (90 frames of 30 substeps), or the case's frames.
TEST_P(GpuRunTest, OneSecondStaysWithTheCpuFloatRun) {
  const RunCase c = GetParam();
  Scene scene = gpu_test::standardScene(c.scene);
  if (c.no_self_collision) scene.sim.self_collision = false;
  if (c.jacobi) scene.sim.stretch_scheme = StretchScheme::Jacobi;
  if (c.size > 0) scene.cloth.num_width_points = scene.cloth.num_height_points = c.size;
  GpuSolver gpu(scene, {.path = c.path});
  ASSERT_EQ(gpu.oneDispatch(), c.path == GpuPath::OneDispatch) << gpu.oneDispatchMisfit();
  if (c.path == GpuPath::Tiled) {
    ASSERT_TRUE(gpu.tiledStretch()) << gpu.tiledStretchMisfit();
    // Each substep's stretch limit fused with the next one's forces, wherever nothing runs between them
    // (no self-collision, no collisions again after the stretch limit: no colliders) and the forces are tiled
    // (no wind).
    const bool colliders = !scene.spheres.empty() || !scene.planes.empty() || !scene.meshes.empty();
    EXPECT_EQ(gpu.fusedFrame(), !scene.sim.self_collision && !colliders && !scene.sim.wind.enabled);
  }
  if (gpu.oneDispatch()) {
    EXPECT_EQ(gpu.dispatchesPerFrame(), 1) << "the frame, its health check included";
  }
  CpuSolver<float> cpu(scene);
  for (int f = 0; f < c.from_frame; ++f)
    cpu.stepFrame();
  if (c.from_frame > 0) gpu.uploadState(cpu.readPositions(), cpu.readDisplacements(), cpu.substeps());
  compareRuns(gpu, cpu, c.frames > 0 ? c.frames : int(scene.sim.frames_per_sec), GetParam().name);
}

INSTANTIATE_TEST_SUITE_P(
    Scenes, GpuRunTest,
    ::testing::Values(RunCase{"pinned2", "pinned2.json"}, RunCase{"pinned4", "pinned4.json"},
                      RunCase{"sphere", "sphere.json"}, RunCase{"plane", "plane.json"}, RunCase{"wind", "wind.json"},
                      // The one-dispatch path: a frame in one work group, same bits (half a second where
                      // nothing lands: one work group runs on one of llvmpipe's threads).
                      RunCase{"pinned2_one", "pinned2.json", GpuPath::OneDispatch, false, false, 0, 45},
                      RunCase{"pinned4_one", "pinned4.json", GpuPath::OneDispatch, false, false, 0, 45},
                      RunCase{"sphere_one", "sphere.json", GpuPath::OneDispatch, true},
                      RunCase{"plane_one", "plane.json", GpuPath::OneDispatch, true},
                      RunCase{"wind_one", "wind.json", GpuPath::OneDispatch, false, false, 0, 45},
                      RunCase{"jacobi_one", "pinned2.json", GpuPath::OneDispatch, false, true, 0, 45},
                      RunCase{"jacobi", "pinned2.json", GpuPath::General, false, true},
                      // Self-collision in the work group's own grid: 32x32 fits the 32 KiB
                      // of shared memory llvmpipe has (50x50 needs 44 KiB with the grid).
                      RunCase{"sphere_self_one", "sphere.json", GpuPath::OneDispatch, false, false, 32},
                      RunCase{"selfCollision_one", "selfCollision.json", GpuPath::OneDispatch, false, false, 32},
                      // The stretch limit tiled: blocks and rings in shared memory, same bits. A third of a
                      // second (the hanging cloths pass 10% strain within 10 frames), and the sphere's from
                      // frame 40, before it lands (about frame 46), to 70.
                      RunCase{"pinned2_tiled", "pinned2.json", GpuPath::Tiled, false, false, 0, 30},
                      RunCase{"sphere_tiled", "sphere.json", GpuPath::Tiled, false, false, 0, 30, 40},
                      RunCase{"wind_tiled", "wind.json", GpuPath::Tiled, false, false, 0, 30},
                      // ... without self-collision: the collisions after the stretch limit keep a frame with
                      // colliders unfused (collide_last); fused with the next substep's forces where nothing
                      // runs between them: at 96x96 (blocks of 27 on llvmpipe) some blocks have a neighbour
                      // on every side.
                      RunCase{"sphere_no_self_tiled", "sphere.json", GpuPath::Tiled, true, false, 0, 30, 40},
                      RunCase{"pinned2_fused96", "pinned2.json", GpuPath::Tiled, false, false, 96, 30}),
    [](const ::testing::TestParamInfo<RunCase>& param) { return std::string(param.param.name); });

double closestPair(const std::vector<glm::dvec3>& x) {
  double closest = 1e30;
  for (std::size_t i = 0; i < x.size(); ++i)
    for (std::size_t j = i + 1; j < x.size(); ++j)
      closest = std::min(closest, glm::distance(x[i], x[j]));
  return closest;
}

class GpuSelfCollisionRun : public GlTest {};

// The first 0.2 s against the CPU; then, to 1 s, the physical checks: no point below the floor after
// any frame, and right after the self-collision pass no two points closer than half the collision
// range 2 * thickness. Half: one pass moves a point by at most the average overlap / steps_per_frame
// (CS184), so a fold landing on itself is pushed apart over several substeps, not at once; on this
// scene the closest pair after the pass stays near 0.6 of the range.
TEST_F(GpuSelfCollisionRun, AgreesForTwoTenthsThenStaysPhysical) {
  const Scene scene = gpu_test::standardScene("selfCollision.json");
  ASSERT_EQ(scene.planes.size(), 1u);
  GpuSolver gpu(scene, gpu_test::general());
  CpuSolver<float> cpu(scene);
  const int compared = int(0.2 * scene.sim.frames_per_sec);
  if (!compareRuns(gpu, cpu, compared, "selfCollision")) return;

  const double range = 2 * scene.cloth.thickness;
  double lowest = 1e30, closest = 1e30;
  for (int f = compared + 1; f <= int(scene.sim.frames_per_sec); ++f) {
    // Every tenth frame its last substep runs stage by stage, to look between the passes (without
    // counting the substep: only wind depends on time, and this scene has none).
    const bool inspect = f % 10 == 0;
    for (int s = 0; s < scene.sim.steps_per_frame - (inspect ? 1 : 0); ++s)
      gpu.step();
    if (inspect) {
      gpu.forcesIntegrate();
      gpu.selfCollide();
      const double pair = closestPair(gpu.readPositions());
      closest = std::min(closest, pair);
      EXPECT_GE(pair, 0.5 * range) << "frame " << f << ": closest pair after the self-collision pass";
      gpu.limitStretch();
    }
    const auto x = gpu.readPositions();
    ASSERT_TRUE(allFinite(x)) << "frame " << f;
    const double below = colliderDistances(scene, x)[0];
    lowest = std::min(lowest, below);
    EXPECT_GE(below, 0.0) << "frame " << f << ": a point is below the floor";
  }
  std::printf(
      "selfCollision  0.2-1 s: lowest point %.3g m above the floor, closest pair after the pass %.3g of 2 thickness\n",
      lowest, closest / range);
}

}  // namespace
}  // namespace drape
