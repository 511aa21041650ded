// Each GPU pass alone against the CPU float passes it fuses, on the same input state: a real scene
// after some CPU frames, so springs are stretched and points touch colliders and each other.
#include "gl_fixture.hpp"
#include "gpu/gpu_solver.hpp"
#include "gpu_test_support.hpp"

#include <cstdio>
#include <ostream>

namespace drape {
namespace {

using gpu_test::floatUlp;
using gpu_test::maxAbs;
using gpu_test::maxComponentDifference;

struct PassCase {
  const char* name;
  const char* scene;
  int frames;                  // CPU float frames before the compared state
  bool collider_contacts;      // the state must have points that the collide pass moves,
  bool self_contacts;          // points that the self-collision pass moves,
  bool overstretched;          // springs beyond the stretch limit
  bool self_collision = true;  // false: turned off, so the collisions fuse into the integrate kernel
};

// Test names and CTest listings show the case's name instead of its bytes.
void PrintTo(const PassCase& c, std::ostream* os) {
  *os << c.name;
}

// Bound on every coordinate of every point, in float ulps of the largest coordinate of the input.
// A pass rounds a handful of float operations per point. `precise` in glsl/sim keeps the GPU from
// contracting a*b + c into an fma or reassociating sums, and both sides use the same operation
// order, so the only freedom left is in division and square root (GLSL allows 2.5 ulp for a/b):
// that changes a force or correction in its last bits, and adding it to a position of ~1 m rounds
// to the same or an adjacent float. 4 ulps leaves margin for that; a wrong term, order or formula
// shows up as thousands. On llvmpipe the bound is 0 (gpu_test::bitIdenticalDevice).
constexpr double kUlps = 4.0;

struct Stage {
  std::vector<glm::dvec3> x, v;
};

class GpuPassTest : public GlTest, public ::testing::WithParamInterface<PassCase> {
 protected:
  // Compares a GPU stage with the CPU passes it fuses, both started from `in`.
  void compare(const char* stage, const Stage& in, const Stage& cpu, const Stage& gpu) {
    const double bound = gpu_test::bitIdenticalDevice(info()) ? 0.0 : kUlps * floatUlp(maxAbs(in.x));
    const double dx = maxComponentDifference(cpu.x, gpu.x);
    const double dv = maxComponentDifference(cpu.v, gpu.v);
    std::printf("%-14s %-28s max |dx| %.3g m, max |dv| %.3g m (bound %.3g m)\n", GetParam().name, stage, dx, dv, bound);
    EXPECT_LE(dx, bound) << stage << ": positions";
    EXPECT_LE(dv, bound) << stage << ": displacements";
  }
};

TEST_P(GpuPassTest, EachPassMatchesTheCpuFloatPass) {
  const PassCase c = GetParam();
  Scene scene = gpu_test::standardScene(c.scene);
  scene.sim.self_collision = scene.sim.self_collision && c.self_collision;
  const bool colliders = !scene.spheres.empty() || !scene.planes.empty();
  CpuSolver<float> cpu(scene);
  for (int f = 0; f < c.frames; ++f)
    cpu.stepFrame();
  // Then substep by substep until the next substep has the contacts the case asks for (a falling cloth
  // crosses the floor within one substep only now and then).
  for (int s = 0; s < 3 * scene.sim.steps_per_frame && c.collider_contacts; ++s) {
    CpuSolver<float> probe = cpu;
    probe.accumulateForces();
    probe.integrate();
    const auto integrated = probe.readPositions();
    probe.collide();
    if (gpu_test::changedPoints(integrated, probe.readPositions()) > 0) break;
    cpu.step();
  }
  GpuSolver gpu(scene);
  auto cpuState = [&] { return Stage{cpu.readPositions(), cpu.readDisplacements()}; };
  auto runGpu = [&](const Stage& in, void (GpuSolver::*stage)()) {
    gpu.uploadState(in.x, in.v, cpu.substeps());
    (gpu.*stage)();
    return Stage{gpu.readPositions(), gpu.readDisplacements()};
  };

  // forces + integrate, and collide when no self-collision pass sits in between.
  const Stage start = cpuState();
  ASSERT_TRUE(allFinite(start.x)) << "the CPU reference blew up within " << c.frames << " frames";
  cpu.accumulateForces();
  cpu.integrate();
  const Stage integrated = cpuState();
  int collider_moved = 0;
  if (colliders) {
    cpu.collide();
    collider_moved = gpu_test::changedPoints(integrated.x, cpu.readPositions());
    if (!gpu.collideFusedWithIntegrate()) {
      cpu.setState(integrated.x, integrated.v);
    }
  }
  const Stage after_integrate = cpuState();
  compare(gpu.passes().front().c_str(), start, after_integrate, runGpu(start, &GpuSolver::forcesIntegrate));

  // self-collision (+ collide).
  Stage before_stretch = after_integrate;
  if (scene.sim.self_collision) {
    cpu.selfCollide();
    const int self_moved = gpu_test::changedPoints(after_integrate.x, cpu.readPositions());
    if (colliders) cpu.collide();
    before_stretch = cpuState();
    compare("self_collide(+collide)", after_integrate, before_stretch,
            runGpu(after_integrate, &GpuSolver::selfCollide));
    std::printf("%-14s self-collision moved %d points\n", c.name, self_moved);
    if (c.self_contacts) {
      EXPECT_GT(self_moved, 0) << "the state must have self-collisions for the test to mean anything";
    }
  }
  if (colliders) {
    std::printf("%-14s collisions moved %d points\n", c.name, collider_moved);
    if (c.collider_contacts) {
      EXPECT_GT(collider_moved, 0) << "the state must touch a collider";
    }
  }

  // stretch limit.
  cpu.limitStretch();
  const Stage after_stretch = cpuState();
  const int stretch_moved = gpu_test::changedPoints(before_stretch.x, after_stretch.x);
  compare("limit_stretch", before_stretch, after_stretch, runGpu(before_stretch, &GpuSolver::limitStretch));
  std::printf("%-14s stretch limit moved %d points\n", c.name, stretch_moved);
  if (c.overstretched) {
    EXPECT_GT(stretch_moved, 0) << "springs must be over the limit for the test to mean anything";
  }
}

// Frames chosen so the state is stretched and (where the scene has them) in contact: the hanging
// cloths pass 10% strain after ~10 frames, the horizontal cloths reach the sphere after ~46 frames and
// the floor after ~66 (falling flat, so nothing is overstretched there), the vertical selfCollision
// cloth lands at once and folds onto itself within ~20 frames.
INSTANTIATE_TEST_SUITE_P(Scenes, GpuPassTest,
                         ::testing::Values(PassCase{"pinned2", "pinned2.json", 10, false, false, true},
                                           PassCase{"pinned4", "pinned4.json", 10, false, false, true},
                                           PassCase{"sphere", "sphere.json", 48, true, false, true},
                                           PassCase{"plane", "plane.json", 65, true, false, false},
                                           PassCase{"sphere_no_self", "sphere.json", 48, true, false, true, false},
                                           PassCase{"plane_no_self", "plane.json", 65, true, false, false, false},
                                           PassCase{"wind", "wind.json", 10, false, false, true},
                                           PassCase{"selfCollision", "selfCollision.json", 60, true, true, true}),
                         [](const ::testing::TestParamInfo<PassCase>& param) { return std::string(param.param.name); });

}  // namespace
}  // namespace drape
