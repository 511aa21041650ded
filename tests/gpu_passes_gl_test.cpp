// Each GPU pass alone against the CPU float passes it fuses, on the same input state: a real scene
// after some CPU frames, so springs are stretched and points touch colliders and each other.
#include "gl/shader.hpp"
#include "gl_fixture.hpp"
#include "gpu/gpu_solver.hpp"
#include "gpu_test_support.hpp"

#include <algorithm>
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
  int frames;                       // CPU float frames before the compared state
  bool self_contacts;               // the state has points that the self-collision pass moves, else it is nudged
  bool overstretched;               // the state has springs beyond the stretch limit, else it is nudged
  bool self_collision = true;       // false: turned off, so the collisions fuse into the integrate kernel
  GpuPath path = GpuPath::General;  // forced: Auto picks per device (llvmpipe General, a GPU one-dispatch)
  int size = 0;                     // resampled to size x size points (0: as the scene has it)
  int terms_held = GpuSolverOptions{}.self_terms_held;  // self-collision terms summed in registers (-1: per device)
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
  // `rounding`: how far the CPU's own result moves when its input moves by an ulp, where the compared passes
  // hold a contact decision that can flip (gpu_test::substepSensitivity); 0 for a pass without one.
  void compare(const char* stage, const Stage& in, const Stage& cpu, const Stage& gpu, double rounding = 0.0) {
    const double bound = gpu_test::exactDevice(info())
                             ? 0.0
                             : std::max(kUlps * floatUlp(maxAbs(in.x)), gpu_test::kTwinFactor * rounding);
    const double dx = maxComponentDifference(cpu.x, gpu.x);
    const double dv = maxComponentDifference(cpu.v, gpu.v);
    std::printf("%-14s %-28s max |dx| %.3g m, max |dv| %.3g m (bound %.3g m)\n", GetParam().name, stage, dx, dv, bound);
    EXPECT_LE(dx, bound) << stage << ": positions";
    EXPECT_LE(dv, bound) << stage << ": displacements";
  }
};

// A pass compared where it does nothing proves nothing. Where a case's state gives a pass no work,
// its input is nudged until it has some: a few points moved half a spacing towards their right-hand
// neighbour (0.5 * 20.4 mm, inside the 19 mm self-collision range of the standard cloth), or lifted
// out of the cloth by 15 mm (their structural springs then measure sqrt(20.4^2 + 15^2) = 25.3 mm,
// 1.24 times rest, beyond the 1.1 limit). Same input to both solvers, so the comparison stays exact.
Stage nudged(const Stage& in, const Topology& topo, bool towards_neighbour) {
  Stage out = in;
  for (int k = 1; k <= 5; ++k) {
    const int x = k * (topo.W - 2) / 6, y = k * (topo.H - 1) / 6;
    const std::size_t i = std::size_t(y * topo.W + x);
    if (topo.pinned[i] || topo.pinned[i + 1]) continue;
    if (towards_neighbour) {
      out.x[i + 1] = in.x[i] + 0.5 * (in.x[i + 1] - in.x[i]);
    } else {
      out.x[i].y += 0.015;
    }
  }
  return out;
}

// Per point, the other points closer than `range` (the nonzero terms of its self-collision sum, up to
// rounding at the range itself), by brute force.
std::vector<int> selfCollisionTerms(const std::vector<glm::dvec3>& x, double range) {
  std::vector<int> terms(x.size(), 0);
  for (std::size_t i = 0; i < x.size(); ++i)
    for (std::size_t j = i + 1; j < x.size(); ++j) {
      const glm::dvec3 d = x[i] - x[j];
      if (glm::dot(d, d) < range * range && glm::dot(d, d) > 0) {
        ++terms[i];
        ++terms[j];
      }
    }
  return terms;
}

TEST_P(GpuPassTest, EachPassMatchesTheCpuFloatPassWhereItMovesPoints) {
  const PassCase c = GetParam();
  Scene scene = gpu_test::standardScene(c.scene);
  scene.sim.self_collision = scene.sim.self_collision && c.self_collision;
  if (c.size > 0) scene.cloth.num_width_points = scene.cloth.num_height_points = c.size;
  const bool colliders = !scene.spheres.empty() || !scene.planes.empty();
  CpuSolver<float> cpu(scene);
  for (int f = 0; f < c.frames; ++f)
    cpu.stepFrame();
  gpu_test::stepUntilCollisionsHaveWork(cpu, [](CpuSolver<float>& probe) {
    probe.accumulateForces();
    probe.integrate();
  });
  GpuSolver gpu(scene, {.path = c.path, .self_terms_held = c.terms_held});
  ASSERT_EQ(gpu.oneDispatch(), c.path == GpuPath::OneDispatch) << gpu.oneDispatchMisfit();
  if (c.path == GpuPath::Tiled) {
    ASSERT_TRUE(gpu.tiledStretch()) << gpu.tiledStretchMisfit();
  }
  const Topology& topo = cpu.topology();
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
  EXPECT_GT(gpu_test::changedPoints(start.x, integrated.x), 0) << "integration moves the free points";
  if (colliders) {
    cpu.collide();
    const int collider_moved = gpu_test::changedPoints(integrated.x, cpu.readPositions());
    std::printf("%-14s collisions moved %d points\n", c.name, collider_moved);
    EXPECT_GT(collider_moved, 0) << "the state must touch a collider";
    if (!gpu.collideFusedWithIntegrate()) cpu.setState(integrated.x, integrated.v);
  }
  const Stage after_integrate = cpuState();
  compare(gpu.passes().front().c_str(), start, after_integrate, runGpu(start, &GpuSolver::forcesIntegrate));
  if (gpu.oneDispatch()) {  // and the whole substep in its one dispatch
    CpuSolver<float> whole = cpu;
    whole.setState(start.x, start.v);
    whole.step();
    // Its collisions after the stretch limit decide contact on the stretch limit's last bits
    const double rounding =
        gpu_test::exactDevice(info())
            ? 0.0
            : gpu_test::substepSensitivity(cpu, start.x, start.v, [](CpuSolver<float>& s) { s.step(); });
    compare("one substep", start, Stage{whole.readPositions(), whole.readDisplacements()},
            runGpu(start, &GpuSolver::step), rounding);
  }

  // self-collision (+ collide).
  Stage before_stretch = after_integrate;
  if (scene.sim.self_collision) {
    const Stage in = c.self_contacts ? after_integrate : nudged(after_integrate, topo, true);
    cpu.setState(in.x, in.v);
    cpu.selfCollide();
    const int self_moved = gpu_test::changedPoints(in.x, cpu.readPositions());
    if (colliders) cpu.collide();
    before_stretch = cpuState();
    compare("self_collide(+collide)", in, before_stretch, runGpu(in, &GpuSolver::selfCollide));
    std::printf("%-14s self-collision moved %d points%s\n", c.name, self_moved, c.self_contacts ? "" : " (nudged)");
    EXPECT_GT(self_moved, 0) << "the self-collision pass must have work for the comparison to mean anything";
    // Points with more nonzero terms than the kernel holds take its sum by cell order: the case with one
    // held must have points on both sides, or one of the two sums went unchecked.
    if (c.terms_held >= 0) {
      const std::vector<int> terms = selfCollisionTerms(in.x, 2.0 * scene.cloth.thickness);
      const auto over = std::count_if(terms.begin(), terms.end(), [&](int n) { return n > c.terms_held; });
      const auto held = std::count_if(terms.begin(), terms.end(), [&](int n) { return n > 0 && n <= c.terms_held; });
      std::printf("%-14s self-collision terms: at most %d a point; %td points within %d held, %td beyond\n", c.name,
                  *std::max_element(terms.begin(), terms.end()), held, c.terms_held, over);
      if (c.terms_held == 1) {
        EXPECT_GT(over, 0) << "no point has more terms than held: the sum by cell order is not compared";
        EXPECT_GT(held, 0) << "no point's terms fit: the held sum is not compared";
      }
    }
  }

  // stretch limit.
  const Stage in = c.overstretched ? before_stretch : nudged(before_stretch, topo, false);
  cpu.setState(in.x, in.v);
  cpu.limitStretch();
  const Stage after_stretch = cpuState();
  const int stretch_moved = gpu_test::changedPoints(in.x, after_stretch.x);
  compare("limit_stretch", in, after_stretch, runGpu(in, &GpuSolver::limitStretch));
  std::printf("%-14s stretch limit moved %d points%s\n", c.name, stretch_moved, c.overstretched ? "" : " (nudged)");
  EXPECT_GT(stretch_moved, 0) << "springs must be over the limit for the comparison to mean anything";
}

// Frames chosen so the state is stretched and (where the scene has them) in contact: the hanging
// cloths pass 10% strain after ~10 frames, the horizontal cloths reach the sphere after ~46 frames and
// the floor after ~66 (falling flat, so nothing is overstretched there: that input is nudged), the
// vertical selfCollision cloth lands at once and folds onto itself within ~20 frames. Only that cloth
// touches itself; the others' self-collision input is nudged.
INSTANTIATE_TEST_SUITE_P(
    Scenes, GpuPassTest,
    ::testing::Values(
        PassCase{"pinned2", "pinned2.json", 10, false, true}, PassCase{"pinned4", "pinned4.json", 10, false, true},
        PassCase{"sphere", "sphere.json", 48, false, true}, PassCase{"plane", "plane.json", 65, false, false},
        PassCase{"sphere_no_self", "sphere.json", 48, false, true, false},
        PassCase{"plane_no_self", "plane.json", 65, false, false, false},
        PassCase{"wind", "wind.json", 10, false, true},
        PassCase{"pinned2_one", "pinned2.json", 10, false, true, true, GpuPath::OneDispatch},
        PassCase{"sphere_one", "sphere.json", 48, false, true, false, GpuPath::OneDispatch},
        PassCase{"plane_one", "plane.json", 65, false, false, false, GpuPath::OneDispatch},
        PassCase{"wind_one", "wind.json", 10, false, true, true, GpuPath::OneDispatch},
        // Self-collision in the work group's own grid, at 32x32 (llvmpipe's 32 KiB of shared memory).
        PassCase{"sphere_self_one", "sphere.json", 48, false, false, true, GpuPath::OneDispatch, 32},
        PassCase{"selfCollision_one", "selfCollision.json", 60, false, false, true, GpuPath::OneDispatch, 32},
        PassCase{"selfCollision", "selfCollision.json", 60, true, true},
        // The self-collision sum with its terms held (8: all of them), and with one held: the points with
        // more (folded layers) take the kernel's sum by cell order; with none held, all do.
        PassCase{"selfCollision_held8", "selfCollision.json", 60, true, true, true, GpuPath::General, 0, 8},
        PassCase{"selfCollision_held1", "selfCollision.json", 60, true, true, true, GpuPath::General, 0, 1},
        PassCase{"selfCollision_held0", "selfCollision.json", 60, true, true, true, GpuPath::General, 0, 0},
        // The stretch limit's colours in one dispatch of blocks with their rings: 50x50 is 2x2 blocks of
        // 31 on llvmpipe, 96x96 has blocks with a neighbour on every side.
        PassCase{"pinned2_tiled", "pinned2.json", 10, false, true, true, GpuPath::Tiled},
        PassCase{"pinned4_tiled96", "pinned4.json", 10, false, true, false, GpuPath::Tiled, 96},
        PassCase{"sphere_tiled", "sphere.json", 48, false, true, true, GpuPath::Tiled},
        PassCase{"selfCollision_tiled", "selfCollision.json", 60, true, true, true, GpuPath::Tiled}),
    [](const ::testing::TestParamInfo<PassCase>& param) { return std::string(param.param.name); });

// The plane response's GLSL twin against physics::collidePlane<float>, case by case, including the
// band below the plane where the crossing parameter has to be clamped (tests/physics_test.cpp works
// the cases by hand). x_prev = x - v throughout.
class GpuPlaneTwin : public GlTest {};

TEST_F(GpuPlaneTwin, CollidePlaneMatchesTheCppFunction) {
  struct Case {
    glm::vec3 x, v, p, n;
    float friction;
  };
  const glm::vec3 up(0, 1, 0), origin(0);
  const glm::vec3 tilted = glm::normalize(glm::vec3(0.3f, 1.0f, -0.2f));
  const Case cases[] = {
      {{0.1f, -0.1f, 0}, {0.1f, -0.2f, 0}, origin, up, 0.0f},                // crosses half way
      {{0.1f, -0.1f, 0}, {0.1f, -0.2f, 0}, origin, up, 0.5f},                // the same with friction
      {{0.2005f, -0.7e-6f, 0.3f}, {0.5e-3f, 0.1e-6f, 0}, origin, up, 0.0f},  // band, rising slowly: clamped
      {{0.2005f, -0.7e-6f, 0.3f}, {0.5e-3f, 0.1e-6f, 0}, origin, up, 0.5f},
      {{0.3f, -0.9e-6f, 0}, {1e-3f, -0.2e-6f, 0}, origin, up, 0.0f},                  // band, sinking: crossed behind
      {{0.2f, 0.05f, 0.1f}, {0.0f, 0.1f, 0.0f}, origin, up, 0.2f},                    // from below, crossing up
      {{0.4f, 0.0f, 0.4f}, {0.01f, 0.0f, 0.0f}, origin, up, 0.3f},                    // on the plane, moving along it
      {{0.5f, 1.0f, 0.5f}, {0.0f, -0.01f, 0.0f}, origin, up, 0.3f},                   // far above: no contact
      {{0.1f, 0.0f, 0.3f}, {0.02f, -0.3f, 0.01f}, {0.1f, 0.1f, 0.2f}, tilted, 0.4f},  // tilted plane
  };
  const std::uint32_t count = std::uint32_t(std::size(cases));
  std::vector<glm::vec4> in;
  for (const Case& c : cases)
    in.insert(in.end(), {glm::vec4(c.x, c.friction), glm::vec4(c.v, 0), glm::vec4(c.p, 0), glm::vec4(c.n, 0)});
  const gl::Program program = gl::compileCompute(testShader("collide_plane.comp"));
  gl::Buffer input = gl::Buffer::fromVector(in);
  gl::Buffer output = gl::Buffer::create(count * sizeof(glm::vec4));
  input.bindBase(GL_SHADER_STORAGE_BUFFER, 0);
  output.bindBase(GL_SHADER_STORAGE_BUFFER, 1);
  program.setUniform("count", count);
  program.dispatch(program.groupsFor(count));
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  const std::vector<glm::vec4> gpu = output.download<glm::vec4>(count);

  const bool exact = gpu_test::exactDevice(info());
  int hits = 0;
  for (std::uint32_t i = 0; i < count; ++i) {
    const Case& c = cases[i];
    glm::vec3 cpu(0);
    const bool hit = physics::collidePlane(c.x, c.v, c.p, c.n, c.friction, cpu);
    hits += hit;
    EXPECT_EQ(gpu[i].w == 1.0f, hit) << "case " << i;
    const double bound = exact ? 0.0 : kUlps * floatUlp(double(glm::length(c.x)) + 1.0);
    for (int k = 0; k < 3; ++k)
      EXPECT_LE(std::abs(double(gpu[i][k]) - double(cpu[k])), bound) << "case " << i << " component " << k;
    // Nothing is thrown beyond its own step: a correction never moves the point farther along the
    // plane than |v| plus the offset.
    if (hit) {
      const glm::vec3 along = glm::vec3(gpu[i]) - glm::dot(glm::vec3(gpu[i]), c.n) * c.n;
      EXPECT_LE(glm::length(along), glm::length(c.v) + 1e-6f) << "case " << i;
    }
  }
  EXPECT_EQ(hits, int(count) - 1);  // every case but the one far above touches the plane
}

}  // namespace
}  // namespace drape
