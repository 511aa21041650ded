// The GPU solver's own contract: which passes a scene dispatches, timing, limits and errors, the
// buffers the renderer borrows (positions, health), picking and dragging, live parameter changes, blow-up flags.
#include "cpu/cpu_solver.hpp"
#include "gl/shader_source.hpp"
#include "gl_fixture.hpp"
#include "gpu/gpu_solver.hpp"
#include "gpu/kernels.hpp"
#include "gpu/layout.hpp"
#include "gpu_test_support.hpp"
#include "test_paths.hpp"

#include <sys/wait.h>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <random>
#include <regex>
#include <sstream>

namespace drape {
namespace {

using gpu_test::standardScene;
using Strings = std::vector<std::string>;

Scene smallScene(int n, bool self_collision = false) {
  Scene s;
  s.path = "small";
  s.cloth.num_width_points = n;
  s.cloth.num_height_points = n;
  s.sim.self_collision = self_collision;
  return s;
}

class GpuSolverTest : public GlTest {};

// The Gauss-Seidel stretch limit: one dispatch per colour of a grid's 12-colour spring colouring.
Strings colourDispatches(int passes = 1) {
  return Strings(std::size_t(12 * passes), "limit_stretch_colour");
}

Strings operator+(Strings a, const Strings& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

// Integrate and the self-collision lists' build up to 4096 points: the grid and the scan in one work group.
const Strings kListBuild = {"forces+integrate+pairs_check",
                            "pairs_prepare",
                            "pairs_grid_count",
                            "grid_build",
                            "pairs_count",
                            "pairs_scan",
                            "pairs_fill"};

TEST_F(GpuSolverTest, PassListsFollowTheScene) {
  // pinned2: no collider, no self-collision: nothing but the two kernels every cloth needs.
  GpuSolver pinned2(standardScene("pinned2.json"), gpu_test::general());
  EXPECT_EQ(pinned2.passes(), Strings{"forces+integrate"} + colourDispatches());
  EXPECT_EQ(pinned2.framePasses(), Strings{"health"});
  EXPECT_EQ(pinned2.dispatchesPerFrame(), (1 + 12) * 30 + 1);
  for (const std::string& pass : pinned2.passes()) {
    EXPECT_EQ(pass.find("collide"), std::string::npos) << pass;
    EXPECT_EQ(pass.find("grid"), std::string::npos) << pass;
  }
  // selfCollision: the candidate lists' build (one work group for the grid and the scan of 2500 points,
  // dispatched with zero groups while the lists are fresh), the correction with the floor fused.
  GpuSolver self(standardScene("selfCollision.json"), gpu_test::general());
  // Then the collisions again, after the stretch limit (collide_last).
  EXPECT_EQ(self.passes(), (kListBuild + Strings{"self_collide+collide"} + colourDispatches() + Strings{"collide"}));
  EXPECT_EQ(self.dispatchesPerFrame(), (8 + 12 + 1) * 30 + 1);
  // The averaged Jacobi stretch pass is one dispatch.
  Scene jacobi = standardScene("selfCollision.json");
  jacobi.sim.stretch_scheme = StretchScheme::Jacobi;
  EXPECT_EQ(GpuSolver(jacobi, gpu_test::general()).passes(),
            (kListBuild + Strings{"self_collide+collide", "limit_stretch", "collide"}));
  // A collider without self-collision rides on the integrate kernel (and runs again after the stretch limit).
  Scene sphere = standardScene("sphere.json");
  sphere.sim.self_collision = false;
  EXPECT_EQ(GpuSolver(sphere, gpu_test::general()).passes(),
            Strings{"forces+integrate+collide"} + colourDispatches() + Strings{"collide"});
  // No stretch limit, or three passes of it.
  Scene loose = standardScene("pinned2.json");
  loose.sim.stretch_passes = 0;
  EXPECT_EQ(GpuSolver(loose, gpu_test::general()).passes(), (Strings{"forces+integrate"}));
  loose.sim.stretch_passes = 3;
  loose.sim.steps_per_frame = 10;
  GpuSolver three(loose, gpu_test::general());
  EXPECT_EQ(three.passes(), Strings{"forces+integrate"} + colourDispatches(3));
  EXPECT_EQ(three.dispatchesPerFrame(), (1 + 3 * 12) * 10 + 1);
  loose.sim.stretch_scheme = StretchScheme::Jacobi;
  EXPECT_EQ(GpuSolver(loose, gpu_test::general()).passes(),
            (Strings{"forces+integrate", "limit_stretch", "limit_stretch", "limit_stretch"}));
  // Past 4096 buckets the grid build takes five dispatches, past 4096 points the lists' scan three.
  EXPECT_EQ(GpuSolver(smallScene(80, true), gpu_test::general()).passes(),
            (Strings{"forces+integrate+pairs_check", "pairs_prepare", "pairs_grid_count", "grid_scan",
                     "grid_scan_blocks", "grid_scan_offsets", "grid_scatter", "grid_rank", "pairs_count", "pairs_scan",
                     "pairs_scan_blocks", "pairs_scan_offsets", "pairs_fill", "self_collide"} +
             colourDispatches()));
}

TEST_F(GpuSolverTest, TimingsNameEveryDispatchedPass) {
  GpuSolver gpu(standardScene("selfCollision.json"), gpu_test::general({.timing = true}));
  gpu.stepFrame();
  const std::vector<PassTiming> timings = gpu.timings();
  // A pass dispatched several times per substep (one per stretch colour) is one timing entry.
  Strings distinct;
  std::map<std::string, int> per_substep;
  for (const std::string& pass : gpu.passes())
    if (per_substep[pass]++ == 0) distinct.push_back(pass);
  distinct.push_back("health");  // once per frame, after the last substep
  Strings names;
  for (const PassTiming& t : timings) {
    names.push_back(t.name);
    EXPECT_EQ(t.calls, t.name == "health" ? 1 : 30 * per_substep[t.name]) << t.name;
    EXPECT_GE(t.ms, 0.0) << t.name;
  }
  EXPECT_EQ(names, distinct);
  gpu.resetTimings();
  EXPECT_TRUE(gpu.timings().empty());
  // Without timing the dispatches are still counted, never timed.
  Scene jacobi = standardScene("pinned2.json");
  jacobi.sim.stretch_scheme = StretchScheme::Jacobi;
  GpuSolver plain(jacobi, gpu_test::general());
  plain.step();
  for (const PassTiming& t : plain.timings()) {
    EXPECT_EQ(t.calls, 1) << t.name;
    EXPECT_EQ(t.ms, 0.0) << t.name;
  }
}

TEST_F(GpuSolverTest, PinnedPointsNeverMoveAndResetRestores) {
  GpuSolver gpu(standardScene("pinned4.json"), gpu_test::general());
  for (int f = 0; f < 20; ++f)
    gpu.stepFrame();
  const auto x = gpu.readPositions();
  const Topology& t = gpu.topology();
  int pinned = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (!t.pinned[i]) continue;
    EXPECT_EQ(x[i], gpu_test::asFloat(t.initial_positions[i])) << "point " << i;
    ++pinned;
  }
  EXPECT_EQ(pinned, 4);
  EXPECT_LT(centroid(x).y, 0.95) << "the free part of the cloth must have fallen";
  EXPECT_EQ(gpu.substeps(), 600);
  gpu.reset();
  EXPECT_EQ(gpu.substeps(), 0);
  const auto x0 = gpu.readPositions(), v0 = gpu.readDisplacements();
  for (std::size_t i = 0; i < x0.size(); ++i) {
    ASSERT_EQ(x0[i], gpu_test::asFloat(t.initial_positions[i])) << "point " << i;
    ASSERT_EQ(v0[i], glm::dvec3(0)) << "point " << i;
  }
}

TEST_F(GpuSolverTest, ClothAtRestWithoutGravityStaysAtRest) {
  Scene scene = smallScene(20, true);  // spacing 1/19 m > 2 thickness: no pair interacts
  scene.sim.gravity = glm::dvec3(0);
  GpuSolver gpu(scene, gpu_test::general());
  for (int f = 0; f < 30; ++f)
    gpu.stepFrame();
  EXPECT_LT(maxDeviation(gpu.readPositions(), gpu.topology().initial_positions), 1e-6);
  EXPECT_TRUE(gpu.health().ok());
}

TEST_F(GpuSolverTest, StateRoundTripsExactly) {
  GpuSolver gpu(smallScene(8), gpu_test::general());
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-2, 2);
  std::vector<glm::dvec3> x(64), v(64);
  for (std::size_t i = 0; i < x.size(); ++i) {
    x[i] = gpu_test::asFloat({u(rng), u(rng), u(rng)});
    v[i] = gpu_test::asFloat(glm::dvec3(u(rng), u(rng), u(rng)) * 1e-3);
  }
  gpu.uploadState(x, v, 5);
  EXPECT_EQ(gpu.readPositions(), x);
  EXPECT_EQ(gpu.readDisplacements(), v);
  EXPECT_EQ(gpu.substeps(), 5);
  EXPECT_THROW(gpu.uploadState(std::vector<glm::dvec3>(3), std::vector<glm::dvec3>(3), 0), std::invalid_argument);
}

TEST_F(GpuSolverTest, HeldPointStaysAtTheTargetUntilReleased) {
  GpuSolver gpu(standardScene("pinned2.json"), gpu_test::general());
  const int W = gpu.topology().W;
  const int held = 25 * W + 25;
  const glm::vec3 target(0.5f, 1.2f, 0.5f);
  gpu.holdPoint(held, target);
  for (int f = 0; f < 10; ++f)
    gpu.stepFrame();
  auto x = gpu.readPositions();
  EXPECT_EQ(x[std::size_t(held)], glm::dvec3(target));
  EXPECT_GT(x[std::size_t(held + 1)].y, 1.0) << "a neighbour is pulled up with the held point";
  gpu.releasePoint();
  for (int f = 0; f < 10; ++f)
    gpu.stepFrame();
  x = gpu.readPositions();
  EXPECT_LT(x[std::size_t(held)].y, double(target.y)) << "released, it falls";
  // setPosition moves a point and keeps its displacement.
  const auto v = gpu.readDisplacements();
  gpu.setPosition(7, glm::vec3(3, 4, 5));
  EXPECT_EQ(gpu.readPositions()[7], glm::dvec3(3, 4, 5));
  EXPECT_EQ(gpu.readDisplacements()[7], v[7]);
  EXPECT_THROW(gpu.holdPoint(W * W, target), std::out_of_range);
}

// The sphere scene without self-collision: the same draping, at a fraction of the llvmpipe time.
Scene drapedScene() {
  Scene scene = standardScene("sphere.json");
  scene.sim.self_collision = false;
  return scene;
}

TEST_F(GpuSolverTest, PickFindsTheNearestPointAlongTheRay) {
  GpuSolver gpu(drapedScene(), gpu_test::general());
  for (int f = 0; f < 50; ++f)
    gpu.stepFrame();  // draped over the sphere: a curved surface
  const auto x = gpu.readPositions();
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  int hits = 0;
  for (int k = 0; k < 20; ++k) {
    const glm::vec3 origin(u(rng), 2.0f, u(rng));
    const glm::vec3 direction = glm::normalize(glm::vec3(u(rng) - 0.5f, -2.0f, u(rng) - 0.5f));
    const float radius = 0.02f;
    // The same choice on the CPU: smallest t >= 0 within the radius, ties to the smaller index.
    int expected = -1;
    float best = 0;
    for (std::size_t i = 0; i < x.size(); ++i) {
      const glm::vec3 p = glm::vec3(x[i]) - origin;
      const float t = glm::dot(p, direction);
      const glm::vec3 off = p - t * direction;
      if (t < 0 || glm::dot(off, off) > radius * radius) continue;
      if (expected < 0 || t < best) {
        expected = int(i);
        best = t;
      }
    }
    const int picked = gpu.pickPoint(origin, direction, radius);
    if (expected >= 0 && picked != expected) {
      // Only a tie within float rounding may differ: the GPU's t for its choice is as small.
      const glm::vec3 p = glm::vec3(x[std::size_t(picked)]) - origin;
      EXPECT_NEAR(glm::dot(p, direction), best, 1e-6f) << "ray " << k;
    } else {
      EXPECT_EQ(picked, expected) << "ray " << k;
    }
    hits += picked >= 0;
  }
  EXPECT_GT(hits, 5) << "most rays must hit the cloth for the test to mean anything";
  EXPECT_EQ(gpu.pickPoint({0, 2, 0}, {0, 1, 0}, 0.05f), -1) << "a ray pointing away hits nothing";
  EXPECT_EQ(gpu.pickPoint({0, 2, 0}, {0, 0, 0}, 0.05f), -1);
}

TEST_F(GpuSolverTest, LiveParameterChangesMatchTheCpu) {
  Scene scene = standardScene("pinned2.json");
  GpuSolver gpu(scene, gpu_test::general());
  CpuSolver<float> cpu(scene);
  for (int f = 0; f < 5; ++f) {
    gpu.stepFrame();
    cpu.stepFrame();
  }
  ClothSpec cloth = scene.cloth;
  cloth.ks *= 2;
  cloth.damping = 1.0;
  cloth.enable_bending = false;
  SimParams sim = scene.sim;
  sim.gravity = {0.5, -9.8, 0};
  sim.wind.enabled = true;  // a new #define: the kernels are recompiled
  sim.wind.velocity = {0, 0, 2};
  sim.wind.turbulence = 0.3;
  gpu.setParams(cloth, sim);
  cpu.setParams(cloth, sim);
  for (int f = 0; f < 5; ++f) {
    gpu.stepFrame();
    cpu.stepFrame();
  }
  const double size = clothSize(scene.cloth);
  // tests/gpu_runs_gl_test.cpp: 0 on llvmpipe, 4 ulps per substep elsewhere.
  const double bound = gpu_test::exactDevice(gpu.contextInfo()) ? 0.0 : 300 * 4.0 * gpu_test::floatUlp(1.0) / size;
  EXPECT_LE(maxDeviation(gpu.readPositions(), cpu.readPositions()) / size, bound);
  EXPECT_EQ(gpu.scene().cloth.ks, cloth.ks);
  // Turning self-collision on adds its passes (and allocates the grid).
  sim.self_collision = true;
  gpu.setParams(cloth, sim);
  const Strings passes = gpu.passes();
  ASSERT_GT(passes.size(), 8u);
  EXPECT_EQ(Strings(passes.begin(), passes.begin() + 8), (kListBuild + Strings{"self_collide"}));
  EXPECT_TRUE(
      std::all_of(passes.begin() + 8, passes.end(), [](const std::string& p) { return p == "limit_stretch_colour"; }));
  gpu.stepFrame();
  EXPECT_TRUE(allFinite(gpu.readPositions()));
}

TEST_F(GpuSolverTest, ABlowUpIsFlagged) {
  Scene scene = smallScene(10);
  scene.cloth.ks = 1e7;  // far beyond the explicit bound at 1 substep per frame
  scene.sim.steps_per_frame = 1;
  scene.sim.stretch_passes = 0;
  scene.cloth.pinned = {{0, 0}};
  GpuSolver gpu(scene, {.health = {.sane_bound = 1e3}});
  gpu.stepFrame();
  EXPECT_TRUE(gpu.health().ok());
  for (int f = 0; f < 200 && gpu.health().ok(); ++f)
    gpu.stepFrame();
  const Health health = gpu.health();
  EXPECT_FALSE(health.ok());
  EXPECT_GE(health.first_point, 0);
  // Cleared flags are raised again by the next check: the state itself is still blown up.
  gpu.clearHealth();
  EXPECT_FALSE(gpu.health().ok());
  gpu.reset();
  EXPECT_TRUE(gpu.health().ok());
}

// A 3 x 2 cloth whose row 0 is a chain A - B - C along x: A and C pinned 12.5 rest lengths apart, B free
// and 10.5 rest lengths from A (strain 9.5, below the blow-up strain 10), so no spring is a blow-up
// before the stretch pass. The rows are 100 m apart and row 1 is pinned, so the vertical and diagonal
// springs hold B with a strain below 0.002 and never reach the 10% limit. The stretch pass then corrects
// A-B and B-C one after the other (they share B, so they have different colours): whichever it
// corrects first, the second moves B to 1.1 rest lengths of its other end, and the first spring ends at
// 12.5 - 1.1 = 11.4 rest lengths, strain 10.4: the frame's last pass made the blow-up.
struct ChainCase {
  Scene scene;
  std::vector<glm::dvec3> x, v;
};

ChainCase lastPassOverstretches() {
  ChainCase c;
  c.scene.path = "chain";
  c.scene.cloth.width = 1.0;  // rest length along x: 0.5 m
  c.scene.cloth.height = 100.0;
  c.scene.cloth.num_width_points = 3;
  c.scene.cloth.num_height_points = 2;
  c.scene.cloth.ks = 1.0;  // B moves ~1e-5 m in the integration: nothing next to the stretch pass
  c.scene.cloth.pinned = {{0, 0}, {2, 0}, {0, 1}, {1, 1}, {2, 1}};
  c.scene.sim.gravity = glm::dvec3(0);
  c.scene.sim.self_collision = false;
  c.scene.sim.steps_per_frame = 1;
  c.scene.sim.stretch_passes = 1;
  const double r = 0.5;
  c.x = {{0, 0, 0}, {10.5 * r, 0, 0}, {12.5 * r, 0, 0}, {0, 0, 100}, {3, 0, 100}, {12.5 * r, 0, 100}};
  c.v.assign(c.x.size(), glm::dvec3(0));
  return c;
}

TEST_F(GpuSolverTest, ABlowUpMadeByTheFramesLastPassIsReportedInThatFrame) {
  const ChainCase c = lastPassOverstretches();
  ASSERT_TRUE(scanHealth(buildTopology(c.scene.cloth), c.scene.cloth, c.x, c.v).ok()) << "bad before the frame";
  // The state before the stretch pass, checked on the GPU: still sane.
  GpuSolver before(c.scene, gpu_test::general());
  before.uploadState(c.x, c.v, 0);
  before.forcesIntegrate();
  EXPECT_TRUE(before.health().ok()) << before.health().describe();

  GpuSolver gpu(c.scene, gpu_test::general());
  gpu.uploadState(c.x, c.v, 0);
  gpu.stepFrame();
  CpuSolver<float> cpu(c.scene);
  cpu.setState(c.x, c.v);
  cpu.stepFrame();
  const Health g = gpu.health(), h = cpu.health();
  EXPECT_EQ(g.flags, Health::kOverstretched) << g.describe();
  EXPECT_EQ(g.flags, h.flags) << "GPU: " << g.describe() << "; CPU: " << h.describe();
  EXPECT_EQ(g.first_point, h.first_point);
  EXPECT_LE(g.first_point, 1) << "an end of A-B or B-C";
  // What the GPU flagged is what the state it holds shows.
  const Health scanned = scanHealth(gpu.topology(), c.scene.cloth, gpu.readPositions(), gpu.readDisplacements());
  EXPECT_EQ(scanned.flags, g.flags);
  EXPECT_EQ(scanned.first_point, g.first_point);
}

// The frame-late check (what the viewer and `drape simulate` call every frame) reports a blow-up in the
// frame that made it or the one after, and says which state it checked: the first frame whose immediate
// check (health(), which waits) fails.
TEST_F(GpuSolverTest, RecentHealthReportsABlowUpAtMostAFrameLate) {
  Scene scene = smallScene(10);
  scene.cloth.ks = 1e7;  // far beyond the explicit bound
  scene.sim.steps_per_frame = 2;
  scene.sim.stretch_passes = 0;
  scene.cloth.pinned = {{0, 0}};
  // On both paths: the one-dispatch path checks health inside its frame's dispatch.
  for (const GpuPath path : {GpuPath::General, GpuPath::OneDispatch}) {
    SCOPED_TRACE(path == GpuPath::General ? "general path" : "one-dispatch path");
    const GpuSolverOptions options{.path = path, .health = {.sane_bound = 1e3}};
    GpuSolver waiting(scene, options);
    int first_bad = 0;
    for (int f = 1; f <= 200 && first_bad == 0; ++f) {
      waiting.stepFrame();
      if (!waiting.health().ok()) first_bad = f;
    }
    ASSERT_EQ(waiting.oneDispatch(), path == GpuPath::OneDispatch);
    ASSERT_GT(first_bad, 1) << "the case must start sane and blow up";

    GpuSolver late(scene, options);
    int reported = 0;
    Health h;
    for (int f = 1; f <= first_bad + 1 && reported == 0; ++f) {
      late.stepFrame();
      h = late.recentHealth();
      if (!h.ok()) reported = f;
    }
    ASSERT_NE(reported, 0) << "not reported within a frame of frame " << first_bad;
    EXPECT_GE(reported, first_bad);
    const long long steps = scene.sim.steps_per_frame;
    EXPECT_TRUE(h.substeps == first_bad * steps || h.substeps == (first_bad + 1) * steps) << h.substeps;
    EXPECT_EQ(h.flags, waiting.health().flags);
    // A reset forgets the frames in flight: no stale blow-up afterwards.
    late.reset();
    late.stepFrame();
    EXPECT_TRUE(late.recentHealth().ok());
  }
}

// A steady-state frame as `drape view` runs it (every substep, the frame-late health check; the renderer
// computes its normals from the borrowed positions itself), on each path (pinned2 tiled, wind in one dispatch, the
// others general), makes the CPU wait for nothing: no buffer read-back, no glFinish, no query result the GPU has not
// written. On selfCollision the list buffer starts too small, so the frames include list rebuilds, the overflow and the
// buffer's growth, all decided without a read-back.
TEST_F(GpuSolverTest, SteadyStateFramesReadNothingBack) {
  for (const char* name : {"pinned2.json", "sphere.json", "selfCollision.json", "wind.json"}) {
    SCOPED_TRACE(name);
    const Scene scene = standardScene(name);
    GpuSolverOptions options = gpu_test::general();
    if (std::string(name) == "wind.json") options.path = GpuPath::OneDispatch;
    if (std::string(name) == "pinned2.json") options.path = GpuPath::Tiled;
    if (scene.sim.self_collision) options.pair_capacity = 256;
    GpuSolver gpu(scene, options);
    const auto frame = [&] {
      gpu.stepFrame();
      ASSERT_TRUE(gpu.recentHealth().ok());
    };
    frame();  // the first frame has no older frame to answer for it, and waits
    gl::DispatchRecorder recorder;
    for (int f = 0; f < 6; ++f)
      frame();
    std::string waits;
    for (const gl::DispatchRecorder::Wait& w : recorder.waits())
      if (w.what != "fence") waits += w.what + " ";
    EXPECT_EQ(waits, "");
    EXPECT_EQ(int(recorder.dispatches().size()), 6 * gpu.dispatchesPerFrame()) << "the frames ran";
    if (scene.sim.self_collision) {
      const GpuPairs pairs = gpu.readPairs();
      EXPECT_GT(pairs.capacity, 256u) << "the overflow grew the list buffer";
    }
  }
}

// The traffic model behind the bench's bytes and GB/s columns follows the plan (tests/gpu_plan_test.cpp
// checks it without GL); here the candidates it counts for the list pass are those of the real solver's last
// list build, as the health read saw them.
TEST_F(GpuSolverTest, TheTrafficModelCountsTheCandidatesOfTheLastListBuild) {
  Scene scene = smallScene(12, true);
  scene.cloth.thickness = 0.1;  // reach 0.3 m over a 9 cm grid: every point has candidates
  GpuSolver gpu(scene, gpu_test::general());
  const double before = gpu.bytesPerPointPerSubstep();
  gpu.stepFrame();
  ASSERT_TRUE(gpu.health().ok());
  const GpuPairs pairs = gpu.readPairs();
  const double candidates = double(pairs.start.back()) / gpu.topology().pointCount();
  ASSERT_GT(candidates, 0.0);
  // A difference of two sums of about 10^3: equal to its rounding.
  EXPECT_NEAR(gpu.bytesPerPointPerSubstep() - before, candidates * (4 + 16), 1e-9) << "4-byte index, vec4 gather";
}

// Every spring at `factor` times its rest length, every point pinned so that no pass moves any.
std::pair<Health, Health> stretchedBy(double factor) {
  Scene scene = smallScene(6);
  for (int y = 0; y < 6; ++y)
    for (int x = 0; x < 6; ++x)
      scene.cloth.pinned.push_back({x, y});
  scene.sim.steps_per_frame = 2;
  GpuSolver gpu(scene, gpu_test::general());
  CpuSolver<float> cpu(scene);
  std::vector<glm::dvec3> x = gpu.topology().initial_positions;
  for (glm::dvec3& p : x)
    p *= factor;  // the grid starts at the origin's corner: every distance scales
  const std::vector<glm::dvec3> v(x.size(), glm::dvec3(0));
  gpu.uploadState(x, v, 0);
  cpu.setState(x, v);
  gpu.stepFrame();
  cpu.stepFrame();
  return {gpu.health(), cpu.health()};
}

TEST_F(GpuSolverTest, AClothStretchedElevenFoldIsReportedByBothSolvers) {
  const auto [gpu12, cpu12] = stretchedBy(12.0);  // strain 11
  EXPECT_EQ(gpu12.flags, Health::kOverstretched) << gpu12.describe();
  EXPECT_EQ(cpu12.flags, Health::kOverstretched) << cpu12.describe();
  EXPECT_EQ(gpu12.first_point, 0);
  EXPECT_EQ(cpu12.first_point, 0);
  const auto [gpu10, cpu10] = stretchedBy(10.5);  // strain 9.5: stretched, not a blow-up
  EXPECT_TRUE(gpu10.ok()) << gpu10.describe();
  EXPECT_TRUE(cpu10.ok()) << cpu10.describe();
}

TEST_F(GpuSolverTest, TheHealthPassWritesNoPointAndRaisesEachFlag) {
  GpuSolver gpu(standardScene("selfCollision.json"), gpu_test::general());
  for (int f = 0; f < 3; ++f)
    gpu.stepFrame();
  const std::vector<glm::dvec3> x = gpu.readPositions(), v = gpu.readDisplacements();
  gpu.checkHealth();
  gpu.checkHealth();
  EXPECT_EQ(gpu.readPositions(), x);
  EXPECT_EQ(gpu.readDisplacements(), v);
  EXPECT_TRUE(gpu.health().ok());
  // One bad point of each kind flags what the CPU scan flags, with the same first point (a runaway
  // point also overstretches its springs, and so flags neighbours with smaller indices).
  const std::size_t i = 1234;
  for (const auto& [position, displacement] :
       {std::pair{glm::dvec3(std::nan(""), 0, 0), glm::dvec3(0)},
        std::pair{x[i], glm::dvec3(0, std::numeric_limits<double>::infinity(), 0)},
        std::pair{glm::dvec3(0, 0, -2e5), glm::dvec3(0)}}) {
    std::vector<glm::dvec3> bad_x = x, bad_v = v;
    bad_x[i] = position;
    bad_v[i] = displacement;
    gpu.uploadState(bad_x, bad_v, gpu.substeps());
    gpu.clearHealth();
    const Health g = gpu.health();
    const Health c = scanHealth(gpu.topology(), gpu.scene().cloth, bad_x, bad_v);
    EXPECT_EQ(g.flags, c.flags) << g.describe() << " / " << c.describe();
    EXPECT_NE(g.flags & (Health::kNonFinite | Health::kOutOfBounds), 0u) << g.describe();
    EXPECT_EQ(g.first_point, c.first_point);
  }
}

TEST_F(GpuSolverTest, ClothBeyondTheBufferLimitFailsBeforeAnything) {
  // An explicit limit: 300 x 300 points need 1.4 MiB of positions alone.
  Scene scene = smallScene(300);
  try {
    GpuSolver gpu(scene, {.max_buffer_bytes = 1 << 20});
    FAIL() << "a 300x300 cloth fits in 1 MiB buffers";
  } catch (const GpuLimitError& e) {
    EXPECT_NE(std::string(e.what()).find("300x300"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("max_buffer_bytes"), std::string::npos) << e.what();
  }
  // The driver's own limit, with the largest cloth a scene may ask for. Its largest buffer is the
  // adjacency: every spring listed from both ends. On an N x N grid there are 2N(N-1) structural,
  // 2(N-1)^2 shearing and 2N(N-2) bending springs, about 6 per point, so about 12 entries per point:
  // 2 * 100,622,338 = 201,244,676 entries for N = 4096, at sizeof(gpu::Neighbor) = 8 bytes each,
  // 1.5 GiB. Checked from the grid size before the topology is built, so this takes no time and no
  // memory. A driver that allows that much would build the cloth for real: skip there.
  GLint64 block = 0;
  glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &block);
  const std::uint64_t N = 4096;
  const std::uint64_t springs = 2 * N * (N - 1) + 2 * (N - 1) * (N - 1) + 2 * N * (N - 2);
  ASSERT_EQ(springs, 100622338u);
  const std::uint64_t adjacency = 2 * springs * sizeof(gpu::Neighbor);
  ASSERT_EQ(sizeof(gpu::Neighbor), 8u);
  if (std::uint64_t(block) >= adjacency) GTEST_SKIP() << "this GPU allows " << block << " byte buffers";
  const auto start = std::chrono::steady_clock::now();
  try {
    GpuSolver gpu(smallScene(4096), gpu_test::general());
    FAIL() << "a 4096x4096 cloth fits in " << block << " byte buffers";
  } catch (const GpuLimitError& e) {
    EXPECT_NE(std::string(e.what()).find("GL_MAX_SHADER_STORAGE_BLOCK_SIZE"), std::string::npos) << e.what();
  }
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 5.0)
      << "the limit must be found before any topology or buffer is made";
}

// $DRAPE_GLSL_DIR pointed elsewhere for one test, and put back as it was: tools/gpu-check runs this binary
// whole with it naming the repository's glsl/, which the tests after this one need.
class GlslDirFor {
 public:
  explicit GlslDirFor(const std::string& dir) {
    if (const char* now = std::getenv("DRAPE_GLSL_DIR")) before_ = now;
    setenv("DRAPE_GLSL_DIR", dir.c_str(), 1);
  }
  ~GlslDirFor() {
    if (before_)
      setenv("DRAPE_GLSL_DIR", before_->c_str(), 1);
    else
      unsetenv("DRAPE_GLSL_DIR");
  }
  GlslDirFor(const GlslDirFor&) = delete;
  GlslDirFor& operator=(const GlslDirFor&) = delete;

 private:
  std::optional<std::string> before_;
};

TEST_F(GpuSolverTest, AKernelThatFailsToCompileNamesItsFileAndLine) {
  // A copy of glsl/ with one broken line in a simulation kernel, found through $DRAPE_GLSL_DIR.
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("drape_broken_glsl_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::copy(fs::path(drape::test::sourceDir()) / "glsl", dir, fs::copy_options::recursive);
  const fs::path kernel = dir / "sim" / "limit_stretch_coloured.comp";
  int lines = 0;
  {
    std::ifstream in(kernel);
    std::string line;
    while (std::getline(in, line))
      ++lines;
  }
  std::ofstream(kernel, std::ios::app) << "this is not glsl;\n";
  {
    const GlslDirFor broken(dir.string());
    try {
      GpuSolver gpu(standardScene("pinned2.json"), gpu_test::general());
      ADD_FAILURE() << "the broken kernel compiled";
    } catch (const gl::ShaderError& e) {
      EXPECT_NE(e.file().find("sim/limit_stretch_coloured.comp"), std::string::npos) << e.what();
      EXPECT_EQ(e.line(), lines + 1) << e.what();
    }
  }
  fs::remove_all(dir);
}

// `drape simulate --solver gpu` as a user runs it (a subprocess; no context is needed in this one).
struct CommandResult {
  int status = -1;
  std::string output;  // stdout and stderr
};

CommandResult runDrape(const std::string& environment, const std::string& args) {
  CommandResult result;
  const std::string command = environment + " " + drape::test::drapeBinary() + " " + args + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return result;
  char buffer[4096];
  while (std::fgets(buffer, sizeof buffer, pipe))
    result.output += buffer;
  const int status = pclose(pipe);
  result.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

class GpuSolverCommand : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!std::filesystem::exists(drape::test::drapeBinary()))
      GTEST_SKIP() << drape::test::drapeBinary() << " is not built";
  }
  const std::string scene_ = std::string(drape::test::sourceDir()) + "/scenes/";
};

TEST_F(GpuSolverCommand, VerboseListsThePassesOfTheScene) {
  const CommandResult pinned2 =
      runDrape("", "simulate " + scene_ + "pinned2.json --solver gpu-general --frames 1 --verbose");
  if (pinned2.status == 3) GTEST_SKIP() << "no OpenGL 4.5 context: " << pinned2.output;
  ASSERT_EQ(pinned2.status, 0) << pinned2.output;
  EXPECT_NE(pinned2.output.find("GL_RENDERER"), std::string::npos) << pinned2.output;
  // forces+integrate, then the Gauss-Seidel stretch limit's 12 colours.
  EXPECT_NE(pinned2.output.find("13 dispatches per substep, 391 per frame"), std::string::npos) << pinned2.output;
  EXPECT_NE(pinned2.output.find("limit_stretch_colour x12"), std::string::npos) << pinned2.output;
  EXPECT_EQ(pinned2.output.find("collide"), std::string::npos) << "pinned2 has no colliders and no self-collision";
  EXPECT_EQ(pinned2.output.find("grid"), std::string::npos) << pinned2.output;
  const CommandResult self =
      runDrape("", "simulate " + scene_ + "selfCollision.json --solver gpu-general --frames 1 --verbose");
  ASSERT_EQ(self.status, 0) << self.output;
  EXPECT_NE(self.output.find("self_collide+collide"), std::string::npos) << self.output;
  EXPECT_NE(self.output.find("21 dispatches per substep, 631 per frame"), std::string::npos) << self.output;
}

TEST_F(GpuSolverCommand, WithoutAContextTheGpuSolverExitsWith3AndTheCpuStillRuns) {
  // libglvnd finds no EGL vendor library: no context of any kind can be made.
  const std::string no_egl = "__EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent";
  const CommandResult gpu = runDrape(no_egl, "simulate " + scene_ + "pinned2.json --solver gpu --frames 1");
  EXPECT_EQ(gpu.status, 3) << gpu.output;
  EXPECT_NE(gpu.output.find("gpu solver: "), std::string::npos) << gpu.output;
  EXPECT_NE(gpu.output.find("tried"), std::string::npos) << "the line says what was tried: " << gpu.output;
  EXPECT_NE(gpu.output.find("no OpenGL 4.5"), std::string::npos) << "and what is missing: " << gpu.output;
  const CommandResult cpu = runDrape(no_egl, "simulate " + scene_ + "pinned2.json --solver cpu --frames 1");
  EXPECT_EQ(cpu.status, 0) << cpu.output;
}

// ---------------------------------------------------------------------------------------------------
// The dispatches really issued (counted where they reach GL), the solver's pass list and the --verbose
// listing, for every bundled scene.

// Worked out from the scene files: every bundled scene is CS184's 50 x 50 cloth with all three spring
// types (a 12-colour stretch limit; 2500 points, 4096 hash buckets: the grid is built in one work
// group) at 30 substeps per frame. Without self-collision a substep is forces+integrate and 12 colours
// (13 dispatches); with it, grid_build and self_collide as well (15). Then one health check per frame.
const std::map<std::string, int> kBundledDispatchesPerFrame = {
    {"pinned2.json", 13 * 30 + 1},
    {"pinned4.json", 13 * 30 + 1},  // "self_collision": false
    {"wind.json", 13 * 30 + 1},     // "self_collision": false
    // With colliders the collisions run again after the stretch limit (collide_last): a dispatch more a substep.
    {"plane.json", 21 * 30 + 1},
    {"selfCollision.json", 21 * 30 + 1},
    {"sphere.json", 21 * 30 + 1},
    {"two_spheres.json", 21 * 30 + 1},
    // Mesh obstacles: collided with in the kernel that moves the point last, as spheres and planes. The
    // three grid cloths (48², 56², 60² points) self-collide; the flag is an OBJ cloth without self-collision
    // whose springs colour in 12 colours too. Where a mesh has sharp edges or corners (the table's rim, the
    // flag's pole, the mannequin's capsules where they meet) the face contacts run after the stretch limit and
    // the collisions again in their kernel (collide_faces+collide); the torus has none, so a collide pass.
    {"tablecloth.json", 21 * 30 + 1},
    {"torus.json", 21 * 30 + 1},
    {"mannequin.json", 21 * 30 + 1},
    {"flag.json", 14 * 30 + 1},
    // The box drop: an OBJ cloth (21 x 21 quads) that self-collides, over a mesh obstacle and a floor; the
    // greedy colouring of a mesh cloth's springs takes 13 colours here, one dispatch each; the face contacts
    // with the box's edges and corners.
    {"box_drop.json", 22 * 30 + 1},
};

// The bundled scenes' file names (pinned2.json, ...).
Strings bundledScenes() {
  Strings names;
  for (const std::string& name : drape::test::bundledSceneNames())
    names.push_back(name + ".json");
  return names;
}

// The kernel file each pass name runs; the test's own table, so that a pass listed under the wrong
// kernel, or a kernel dispatched without being listed, shows.
std::string kernelOf(const std::string& pass) {
  const std::pair<const char*, const char*> table[] = {
      {"forces+integrate", "forces_integrate.comp"},
      {"forces+predict", "forces_integrate.comp"},  // compiled with PREDICT=1
      {"xpbd_colour", "xpbd_coloured.comp"},
      {"vbd_colour", "vbd_coloured.comp"},
      {"collide_faces", "collide_faces.comp"},  // before "collide", a prefix of it
      {"collide", "collide.comp"},
      {"tether", "tether.comp"},
      {"pairs_check", "pairs_check.comp"},
      {"pairs_prepare", "pairs_prepare.comp"},
      {"pairs_grid_count", "pairs_grid_count.comp"},
      {"pairs_count", "pairs_count.comp"},
      {"pairs_scan", "grid_scan.comp"},  // pairs_scan, pairs_scan_blocks, pairs_scan_offsets: the same file
      {"pairs_fill", "pairs_fill.comp"},
      {"grid_build", "grid_build.comp"},
      {"grid_scan", "grid_scan.comp"},  // grid_scan, grid_scan_blocks, grid_scan_offsets: one file, 3 stages
      {"grid_scatter", "grid_scatter.comp"},
      {"grid_rank", "grid_rank.comp"},
      {"self_collide", "self_collide.comp"},
      {"limit_stretch_tiled", "limit_stretch_tiled.comp"},
      {"limit_stretch_forces_tiled", "limit_stretch_forces_tiled.comp"},
      {"forces_tiled", "forces_integrate_tiled.comp"},
      {"limit_stretch_colour", "limit_stretch_coloured.comp"},
      {"limit_stretch", "limit_stretch.comp"},
      {"health", "health.comp"},
  };
  for (const auto& [prefix, file] : table)
    if (pass.rfind(prefix, 0) == 0) return file;
  return "unknown pass " + pass;
}

std::string fileOf(const std::string& label) {
  const std::size_t slash = label.find_last_of('/');
  return slash == std::string::npos ? label : label.substr(slash + 1);
}

// What a frame should dispatch according to passes() and framePasses(), as kernel files.
Strings plannedKernels(const GpuSolver& gpu) {
  Strings out;
  for (int s = 0; s < gpu.scene().sim.steps_per_frame; ++s)
    for (const std::string& pass : gpu.passes())
      out.push_back(kernelOf(pass));
  for (const std::string& pass : gpu.framePasses())
    out.push_back(kernelOf(pass));
  return out;
}

// What a frame dispatches according to the plan (src/gpu/plan.hpp), as kernel files: the one-dispatch path's
// one dispatch included.
Strings frameKernels(const gpu::Plan& plan) {
  Strings out;
  for (int repeat = 0; repeat < plan.frame.repeats; ++repeat)
    for (const gpu::Dispatch& d : plan.frame.substep)
      out.push_back(fileOf(gpu::kernelRow(d.pass).file));
  for (const gpu::Dispatch& d : plan.frame.tail)
    out.push_back(fileOf(gpu::kernelRow(d.pass).file));
  return out;
}

Strings recordFrame(GpuSolver& gpu) {
  gl::DispatchRecorder recorder;
  gpu.stepFrame();
  Strings out;
  for (const gl::DispatchRecorder::Dispatch& d : recorder.dispatches())
    out.push_back(fileOf(d.program));
  return out;
}

TEST_F(GpuSolverTest, EveryBundledSceneDispatchesExactlyItsPassList) {
  const Strings scenes = bundledScenes();
  ASSERT_EQ(scenes.size(), kBundledDispatchesPerFrame.size()) << "a scene was added or removed: update the table";
  for (const std::string& name : scenes) {
    SCOPED_TRACE(name);
    ASSERT_EQ(kBundledDispatchesPerFrame.count(name), 1u) << "no count worked out for " << name;
    const int expected = kBundledDispatchesPerFrame.at(name);
    GpuSolver gpu(standardScene(name), gpu_test::general());
    EXPECT_EQ(gpu.dispatchesPerFrame(), expected);
    const Strings planned = plannedKernels(gpu);
    EXPECT_EQ(int(planned.size()), expected);
    for (int frame = 0; frame < 2; ++frame) {  // the first frame is no exception
      const Strings real = recordFrame(gpu);
      EXPECT_EQ(int(real.size()), expected) << "frame " << frame;
      EXPECT_EQ(real, planned) << "frame " << frame;
      EXPECT_EQ(real, frameKernels(gpu.plan())) << "frame " << frame;
    }
    // The tiled path on every grid scene (the one-dispatch path on those that fit: below), one frame: the fused
    // frame where nothing runs between the stretch limit and the next forces, else its substep's kernels.
    if (!gpu.scene().cloth.isGrid()) continue;
    GpuSolver tiled(standardScene(name), {.path = GpuPath::Tiled});
    const Strings real = recordFrame(tiled);
    EXPECT_EQ(int(real.size()), tiled.dispatchesPerFrame());
    EXPECT_EQ(real, plannedKernels(tiled));
    EXPECT_EQ(real, frameKernels(tiled.plan()));
  }
  // Variants no bundled scene has: the five-dispatch grid build, the Jacobi stretch scheme, three passes;
  // XPBD with self-collision and two sweeps, and without it (its own collide pass); VBD with two sweeps;
  // tethers.
  Scene jacobi = standardScene("selfCollision.json");
  jacobi.sim.stretch_scheme = StretchScheme::Jacobi;
  jacobi.sim.stretch_passes = 3;
  Scene xpbd = standardScene("sphere.json");
  xpbd.sim.integrator = Integrator::Xpbd;
  xpbd.sim.iterations = 2;
  Scene xpbd_no_self = standardScene("plane.json");
  xpbd_no_self.sim.integrator = Integrator::Xpbd;
  xpbd_no_self.sim.self_collision = false;
  Scene vbd = standardScene("plane.json");  // with self-collision: the lists' travel check of its own
  vbd.sim.integrator = Integrator::Vbd;
  vbd.sim.iterations = 2;
  Scene tethered = standardScene("pinned4.json");
  tethered.sim.tethers = true;
  for (const Scene& scene : {smallScene(80, true), jacobi, xpbd, xpbd_no_self, vbd, tethered}) {
    GpuSolver gpu(scene, gpu_test::general());
    const Strings real = recordFrame(gpu);
    EXPECT_EQ(int(real.size()), gpu.dispatchesPerFrame());
    EXPECT_EQ(real, plannedKernels(gpu));
    EXPECT_EQ(real, frameKernels(gpu.plan()));
  }
}

// The one-dispatch path: where it applies, a frame is one dispatch of one_group.comp, the health check
// included; step() alone is one dispatch too. The bundled grid scenes without self-collision or colliders fit (the
// flag's pole has sharp edges, whose face contacts run on the general path).
TEST_F(GpuSolverTest, TheOneDispatchPathRunsAFrameInOneDispatch) {
  // (The flag's pole has sharp edges: its face contacts run on the general path.)
  for (const char* name : {"pinned2.json", "pinned4.json", "wind.json"}) {
    SCOPED_TRACE(name);
    GpuSolver gpu(standardScene(name), {.path = GpuPath::OneDispatch});
    ASSERT_TRUE(gpu.oneDispatch()) << gpu.oneDispatchMisfit();
    EXPECT_EQ(gpu.name(), "gpu-onedispatch");
    EXPECT_EQ(gpu.dispatchesPerFrame(), 1);
    EXPECT_TRUE(gpu.framePasses().empty());
    EXPECT_DOUBLE_EQ(gpu.dispatchesPerSubstep(), 1.0 / gpu.scene().sim.steps_per_frame);
    // A flat grid (pinned2, pinned4) finds its springs from the grid: device memory sees only the state
    // read, the weight and the state written, once a frame. The vertical wind cloth's rests differ and
    // the flag is a mesh: they read the adjacency and the stretch table every substep.
    const double state = sizeof(glm::vec4) + sizeof(glm::vec3);  // a position and a packed displacement
    const double state_per_frame = (2 * state + 16) / gpu.scene().sim.steps_per_frame;
    if (std::string(name) == "pinned2.json" || std::string(name) == "pinned4.json") {
      EXPECT_DOUBLE_EQ(gpu.bytesPerPointPerSubstep(), state_per_frame);
    } else {
      EXPECT_GT(gpu.bytesPerPointPerSubstep(), state_per_frame + 100) << "12 adjacency entries and 12 table entries";
    }
    for (int frame = 0; frame < 2; ++frame) {
      const Strings real = recordFrame(gpu);
      EXPECT_EQ(real, (Strings{"one_group.comp"})) << "frame " << frame;
      EXPECT_EQ(real, frameKernels(gpu.plan())) << "frame " << frame;
    }
    gl::DispatchRecorder recorder;
    gpu.step();
    EXPECT_EQ(recorder.dispatches().size(), 1u);
    // The substep's phases, as the -v listing shows them: forces, then the 12 stretch colours.
    EXPECT_EQ(gpu.passes().size(), 13u);
  }
}

// The tiled path: the stretch limit's 12 colours in one dispatch, fused with the next substep's forces, so
// a 256x256 cloth without self-collision takes one dispatch a substep and one more a frame (issue #10's
// bound is 2), the same kernels as recorded, and fewer bytes in the traffic model than one dispatch per
// colour.
TEST_F(GpuSolverTest, TheTiledPathRunsTheStretchLimitInOneDispatch) {
  Scene scene = smallScene(256);
  scene.cloth.pinned = {{0, 0}, {255, 0}};
  GpuSolver tiled(scene, {.path = GpuPath::Tiled});
  ASSERT_TRUE(tiled.tiledStretch()) << tiled.tiledStretchMisfit();
  EXPECT_FALSE(tiled.oneDispatch());
  EXPECT_EQ(tiled.name(), "gpu-tiled");
  EXPECT_TRUE(tiled.tiledFromGrid()) << "a flat grid: every direction's springs have one rest length";
  EXPECT_EQ(tiled.stretchTiling().halo, 10u) << "one pass over the grid colouring reaches 10 points";
  EXPECT_GE(tiled.stretchTiling().tile, 8u);
  EXPECT_TRUE(tiled.fusedFrame()) << "no self-collision, tethers or wind between a stretch limit and the forces";
  EXPECT_EQ(tiled.passes(), (Strings{"limit_stretch_forces_tiled+integrate"}));
  EXPECT_EQ(tiled.framePasses(), (Strings{"limit_stretch_tiled", "health"})) << "the last substep's stretch limit";
  const int substeps = scene.sim.steps_per_frame;
  EXPECT_DOUBLE_EQ(tiled.dispatchesPerSubstep(), double(substeps + 1) / substeps);
  EXPECT_EQ(tiled.dispatchesPerFrame(), substeps + 2);
  const Strings real = recordFrame(tiled);
  EXPECT_EQ(real, plannedKernels(tiled));
  EXPECT_EQ(real, frameKernels(tiled.plan()));
  GpuSolver general(scene, {.path = GpuPath::General});
  EXPECT_FALSE(general.tiledStretch());
  EXPECT_DOUBLE_EQ(general.dispatchesPerSubstep(), 13.0);
  // Per point: 16-byte positions copied with their ring (10 for the stretch limit, 2 more for the forces),
  // the 12-byte displacement read and the new state written; no adjacency, no table, no gathers.
  const double ring_free = sizeof(glm::vec4) + sizeof(glm::vec3) + sizeof(glm::vec4) + sizeof(glm::vec3);
  EXPECT_GT(tiled.bytesPerPointPerSubstep(), ring_free);
  EXPECT_LT(tiled.bytesPerPointPerSubstep(), ring_free + 4 * sizeof(glm::vec4)) << "rings under 4 positions a point";
  EXPECT_LT(tiled.bytesPerPointPerSubstep(), 0.2 * general.bytesPerPointPerSubstep());
  if (gpu_test::exactDevice(tiled.contextInfo())) {
    general.stepFrame();
    EXPECT_EQ(gpu_test::changedPoints(general.readPositions(), tiled.readPositions()), 0);
  }
  {  // step() alone must end on a whole substep: the two kernels, not the fused one
    gl::DispatchRecorder recorder;
    tiled.step();
    Strings files;
    for (const gl::DispatchRecorder::Dispatch& d : recorder.dispatches())
      files.push_back(fileOf(d.program));
    EXPECT_EQ(files, (Strings{"forces_integrate_tiled.comp", "limit_stretch_tiled.comp"}));
  }

  // Where it does not apply, forcing it says why; a live change that takes it out of reach (more stretch
  // passes than a block's ring can hold) moves the solver to the per-colour dispatches and back.
  for (const bool jacobi : {true, false}) {
    Scene other = jacobi ? standardScene("pinned2.json") : standardScene("flag.json");
    if (jacobi) other.sim.stretch_scheme = StretchScheme::Jacobi;
    try {
      GpuSolver forced(other, {.path = GpuPath::Tiled});
      ADD_FAILURE() << (jacobi ? "the Jacobi scheme" : "a mesh cloth") << " was accepted on the tiled path";
    } catch (const GpuLimitError& e) {
      EXPECT_NE(std::string(e.what()).find(jacobi ? "Jacobi" : "grid cloth"), std::string::npos) << e.what();
    }
  }
  // A vertical cloth's points are offset by up to 1 mm (CS184), so its rests differ: the table is read.
  EXPECT_FALSE(GpuSolver(standardScene("wind.json"), {.path = GpuPath::Tiled}).tiledFromGrid());
  Scene live = standardScene("pinned2.json");
  live.sim.self_collision = false;
  GpuSolver gpu(live, {.path = GpuPath::Tiled});
  EXPECT_TRUE(gpu.tiledFromGrid());
  CpuSolver<float> cpu(live);
  GLint shared = 0;
  glGetIntegerv(GL_MAX_COMPUTE_SHARED_MEMORY_SIZE, &shared);
  const int too_many = shared <= 49152 ? 4 : 40;  // 4 passes reach 37 points: 82 a side, over 48 KiB
  for (const int passes : {1, too_many, 2}) {
    live.sim.stretch_passes = passes;
    gpu.setParams(live.cloth, live.sim);
    cpu.setParams(live.cloth, live.sim);
    EXPECT_EQ(gpu.tiledStretch(), passes != too_many) << passes << " passes: " << gpu.tiledStretchMisfit();
    gpu.stepFrame();
    cpu.stepFrame();
  }
  // Bending springs off: the reach shrinks (the ring with it) and the forces skip that direction; wind on:
  // the forces go back to the adjacency kernel (forces_integrate_tiled.comp has none), the stretch limit
  // stays tiled.
  live.cloth.enable_bending = false;
  gpu.setParams(live.cloth, live.sim);
  cpu.setParams(live.cloth, live.sim);
  EXPECT_TRUE(gpu.tiledStretch());
  EXPECT_LT(gpu.stretchTiling().halo, 19u) << "2 passes without bending springs";
  gpu.stepFrame();
  cpu.stepFrame();
  live.sim.wind.enabled = true;
  live.sim.wind.velocity = glm::dvec3(3.0, 0.0, 1.0);
  gpu.setParams(live.cloth, live.sim);
  cpu.setParams(live.cloth, live.sim);
  EXPECT_EQ(gpu.passes(), (Strings{"forces+integrate", "limit_stretch_tiled"}));
  gpu.stepFrame();
  cpu.stepFrame();
  if (gpu_test::exactDevice(gpu.contextInfo())) {
    EXPECT_EQ(gpu_test::changedPoints(gpu.readPositions(), cpu.readPositions()), 0);
  }
}

TEST_F(GpuSolverTest, TheOneDispatchPathIsChosenWhereItFitsAndSaysWhyNot) {
  // On llvmpipe the automatic choice is the general path (one work group runs on one thread).
  GpuSolver automatic(standardScene("pinned2.json"));
  EXPECT_EQ(automatic.oneDispatch(), !automatic.contextInfo().software);
  EXPECT_FALSE(GpuSolver(standardScene("pinned2.json"), {.path = GpuPath::General}).oneDispatch());
  // The largest square cloth whose positions fit this device's shared memory (51x51 in llvmpipe's 32 KiB)
  // fits without self-collision and not with it (the grid takes 4 more bytes a point, and a bucket table):
  // forcing the path then is an error that says why.
  GLint shared = 0;
  glGetIntegerv(GL_MAX_COMPUTE_SHARED_MEMORY_SIZE, &shared);
  int n = 2;
  while (12 * (n + 1) * (n + 1) + 4 * (((n + 1) * (n + 1) + 31) / 32) <= shared)
    ++n;
  EXPECT_TRUE(GpuSolver(smallScene(n), {.path = GpuPath::OneDispatch}).oneDispatch()) << n << "x" << n;
  try {
    GpuSolver forced(smallScene(n, true), {.path = GpuPath::OneDispatch});
    ADD_FAILURE() << "a self-colliding " << n << "x" << n << " cloth was accepted on the one-dispatch path";
  } catch (const GpuLimitError& e) {
    // Where shared memory holds the grid (NVIDIA's 48 KiB), the held pairs' rest positions are the reason
    EXPECT_NE(std::string(e.what()).find("self-collision"), std::string::npos) << e.what();
  }
  // Too many points for one work group's shared memory (12 bytes each: 256x256 needs 768 KiB).
  try {
    GpuSolver forced(smallScene(256), {.path = GpuPath::OneDispatch});
    ADD_FAILURE() << "a 256x256 cloth was accepted on the one-dispatch path";
  } catch (const GpuLimitError& e) {
    EXPECT_NE(std::string(e.what()).find("GL_MAX_COMPUTE_SHARED_MEMORY_SIZE"), std::string::npos) << e.what();
  }
  // A live change to self-collision moves a forced solver of that size to the general path and back, the
  // state kept.
  Scene scene = standardScene("pinned2.json");
  scene.cloth.num_width_points = scene.cloth.num_height_points = n;
  GpuSolver gpu(scene, {.path = GpuPath::OneDispatch});
  CpuSolver<float> cpu(scene);
  const auto frameWithSelfCollision = [&](bool on) {
    scene.sim.self_collision = on;
    gpu.setParams(scene.cloth, scene.sim);
    cpu.setParams(scene.cloth, scene.sim);
    gpu.stepFrame();
    cpu.stepFrame();
    return gpu.oneDispatch();
  };
  EXPECT_TRUE(frameWithSelfCollision(false));
  EXPECT_FALSE(frameWithSelfCollision(true));
  EXPECT_TRUE(frameWithSelfCollision(false));
  if (gpu_test::exactDevice(gpu.contextInfo())) {
    EXPECT_EQ(gpu_test::changedPoints(gpu.readPositions(), cpu.readPositions()), 0);
  }
}

// The pin flag rides in the positions' w as well as the displacements' (the Jacobi stretch limit gathers
// only positions): every pass, reset, upload and the mouse's hold and release keep the two equal.
TEST_F(GpuSolverTest, ThePinFlagRidesInThePositionsW) {
  for (const GpuPath path : {GpuPath::General, GpuPath::OneDispatch}) {
    SCOPED_TRACE(path == GpuPath::General ? "general path" : "one-dispatch path");
    Scene scene = standardScene("pinned2.json");
    scene.sim.stretch_scheme = StretchScheme::Jacobi;
    GpuSolver gpu(scene, {.path = path});
    const std::size_t n = std::size_t(gpu.topology().pointCount());
    const auto expectFlags = [&](int held, const char* when) {
      glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
      const auto x = gpu.positionBuffer().download<glm::vec4>(n);
      int wrong = 0;
      for (std::size_t i = 0; i < n; ++i)
        wrong += x[i].w != ((gpu.topology().pinned[i] != 0 || int(i) == held) ? 1.0f : 0.0f);
      EXPECT_EQ(wrong, 0) << when;
    };
    expectFlags(-1, "after reset");
    gpu.stepFrame();
    expectFlags(-1, "after a frame");
    gpu.holdPoint(1234, glm::vec3(0.5f, 0.2f, 0.3f));
    gpu.stepFrame();
    expectFlags(1234, "holding a point");
    gpu.setPosition(1234, glm::vec3(0.5f, 0.1f, 0.3f));
    expectFlags(1234, "moving the held point");
    gpu.releasePoint();
    gpu.stepFrame();
    expectFlags(-1, "after the release");
    gpu.uploadState(gpu.readPositions(), gpu.readDisplacements(), gpu.substeps());
    expectFlags(-1, "after an upload");
  }
}

// The --verbose listing's lines "  N. PASS" or "  N. PASS xK", split at the per-frame heading.
struct VerboseListing {
  int per_substep = -1, per_frame = -1;
  Strings substep, frame;
};

VerboseListing parseVerbose(const std::string& output) {
  VerboseListing out;
  std::smatch m;
  if (std::regex_search(output, m, std::regex("gpu[a-z-]*: (\\d+) dispatches per substep, (\\d+) per frame"))) {
    out.per_substep = std::stoi(m[1]);
    out.per_frame = std::stoi(m[2]);
  }
  Strings* into = &out.substep;
  std::istringstream lines(output);
  std::string line;
  const std::regex entry("  \\d+\\. (\\S+)(?: x(\\d+))?");
  while (std::getline(lines, line)) {
    if (line.rfind("  then once per frame", 0) == 0) into = &out.frame;
    if (!std::regex_match(line, m, entry)) continue;
    const int count = m[2].matched ? std::stoi(m[2]) : 1;
    into->insert(into->end(), std::size_t(count), m[1].str());
  }
  return out;
}

TEST_F(GpuSolverTest, TheVerboseListingOfEveryBundledSceneIsWhatItDispatches) {
  if (!std::filesystem::exists(drape::test::drapeBinary()))
    GTEST_SKIP() << drape::test::drapeBinary() << " is not built";
  for (const std::string& name : bundledScenes()) {
    SCOPED_TRACE(name);
    const CommandResult r = runDrape("", "simulate " + std::string(drape::test::sourceDir()) + "/scenes/" + name +
                                             " --solver gpu-general --frames 1 --verbose");
    ASSERT_EQ(r.status, 0) << r.output;
    const VerboseListing listed = parseVerbose(r.output);
    GpuSolver gpu(standardScene(name), gpu_test::general());
    EXPECT_EQ(listed.substep, gpu.passes()) << r.output;
    EXPECT_EQ(listed.frame, gpu.framePasses()) << r.output;
    EXPECT_EQ(listed.per_substep, int(gpu.passes().size())) << r.output;
    EXPECT_EQ(listed.per_frame, int(recordFrame(gpu).size())) << r.output;
  }
}

}  // namespace
}  // namespace drape
