// Mesh cloths and mesh obstacles on the GPU: whole runs against the CPU float reference (bit for bit on
// llvmpipe, as tests/gpu_runs_gl_test.cpp for the grid scenes), two GPU runs with racing work groups
// bit-identical, no point inside an obstacle, and `render --export`.
#include "core/mesh_obstacle.hpp"
#include "core/penetration.hpp"
#include "gl_fixture.hpp"
#include "gpu/gpu_solver.hpp"
#include "gpu_test_support.hpp"
#include "shell_quote.hpp"
#include "test_paths.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>

namespace drape {
namespace {

// Work groups race for the hash grid's counters only with worker threads (see gpu_determinism_gl_test.cpp).
const bool kThreaded = [] { return setenv("LP_NUM_THREADS", "2", 1) == 0; }();

struct MeshCase {
  const char* scene;
  int frames;
};

void PrintTo(const MeshCase& c, std::ostream* os) {
  *os << c.scene;
}

class GpuMeshRun : public GlTest, public ::testing::WithParamInterface<MeshCase> {};

// flag: a mesh cloth (quads, lumped masses, pin box) in wind, with a thin mesh pole, collisions fused into
// integrate; torus: a grid cloth on a mesh obstacle and a plane, with self-collision (collisions in the
// self-collision kernel); mannequin: six overlapping capsules.
TEST_P(GpuMeshRun, StaysWithTheCpuFloatRunAndOutsideEveryObstacle) {
  const Scene scene = gpu_test::standardScene(GetParam().scene);
  GpuSolver gpu(scene, gpu_test::general());
  CpuSolver<float> cpu(scene);
  const bool exact = gpu_test::exactDevice(gpu.contextInfo());
  std::optional<gpu_test::RoundingTwin> twin;
  if (!exact) twin.emplace(scene);
  const double size = clothSize(scene.cloth);
  for (int f = 1; f <= GetParam().frames; ++f) {
    gpu.stepFrame();
    cpu.stepFrame();
    if (twin) twin->stepFrame();
    if (f % 10 != 0 && f != GetParam().frames) continue;
    const auto xg = gpu.readPositions(), xc = cpu.readPositions();
    ASSERT_TRUE(allFinite(xc)) << "frame " << f;
    const double bound = exact ? 0.0
                               : twin->bound(xc, size,
                                             double(gpu.substeps()) * 4.0 *
                                                 gpu_test::floatUlp(std::max(gpu_test::maxAbs(xc), 1.0)) / size);
    ASSERT_LE(maxDeviation(xg, xc) / size, bound) << GetParam().scene << " frame " << f;
  }
  const auto x = gpu.readPositions();
  for (const MeshSpec& m : scene.meshes)
    for (std::size_t i = 0; i < x.size(); ++i)
      ASSERT_FALSE(insideMesh(*m.mesh, x[i])) << "point " << i << " inside " << m.obj;
}

INSTANTIATE_TEST_SUITE_P(Scenes, GpuMeshRun,
                         ::testing::Values(MeshCase{"flag.json", 45}, MeshCase{"torus.json", 60},
                                           MeshCase{"mannequin.json", 50}),
                         [](const ::testing::TestParamInfo<MeshCase>& p) {
                           std::string name = p.param.scene;
                           return name.substr(0, name.find('.'));
                         });

// The box drop (issue 26; tests/contact_test.cpp runs all 18 settings on the CPU): the GPU run equals the CPU
// float run bit for bit on llvmpipe, frame by frame, with the collisions again after the stretch limit and the
// face contacts with the box's edges and corners; from contact on, no cloth point more than 0.5 mm inside the
// exact box and no point of a cloth triangle more than the collision thickness. Three settings, to keep it
// lean: the hardest (5 substeps, the stiff solvers, 2 m) and the default substeps.
struct Drop {
  const char* name;
  double height;  // m above the box's top, as tests/contact_test.cpp places the cloth
  int steps;
  Integrator integrator;
};

void PrintTo(const Drop& d, std::ostream* os) {
  *os << d.name;
}

class GpuBoxDrop : public GlTest, public ::testing::WithParamInterface<Drop> {};

TEST_P(GpuBoxDrop, NothingEndsInsideTheBoxAndTheGpuIsTheCpu) {
  const Drop d = GetParam();
  Scene s = gpu_test::standardScene("box_drop.json");
  s.sim.steps_per_frame = d.steps;
  s.sim.integrator = d.integrator;
  GpuSolver gpu(s, gpu_test::general());
  CpuSolver<float> cpu(s, CpuSolverOptions{.threads = 1});
  const std::vector<std::string> passes = gpu.passes();
  EXPECT_NE(std::find(passes.begin(), passes.end(), "collide_faces+collide"), passes.end());
  std::vector<glm::dvec3> x = cpu.topology().initial_positions, v(x.size(), glm::dvec3(0));
  for (glm::dvec3& p : x)
    p.y += d.height - 1.0;
  cpu.setState(x, v);
  gpu.uploadState(x, v, 0);
  const PenetrationGauge gauge(s, cpu.topology(), 2e-3);
  const double thickness = meshThickness(s.cloth, s.meshes[0]);
  int contact = -1, measured = 0;
  double worst_vertex = 0, worst_surface = 0;
  for (int f = 1; f <= 200 && (contact < 0 || f <= contact + 30); ++f) {
    gpu.stepFrame();
    cpu.stepFrame();
    const Positions now = gpu.readPositions();
    ASSERT_TRUE(allFinite(now)) << "frame " << f;
    if (contact < 0) {
      if (minY(now) > 0.2) continue;  // the box's top is at 0.15 m: not there yet
      if (gauge.measure(now).nearest > s.cloth.thickness) continue;
      contact = f;
    }
    if ((f - contact) % 3) continue;
    if (gpu_test::exactDevice(gpu.contextInfo())) {
      ASSERT_EQ(gpu_test::changedPoints(now, cpu.readPositions()), 0) << "frame " << f;
      ASSERT_EQ(gpu_test::changedPoints(gpu.readDisplacements(), cpu.readDisplacements()), 0) << "frame " << f;
    }
    const Penetration p = gauge.measure(now);
    worst_vertex = std::max(worst_vertex, p.vertex);
    worst_surface = std::max(worst_surface, p.surface);
    ++measured;
    EXPECT_LE(p.vertex, 0.5e-3) << "frame " << f << ": point " << p.vertex_index;
    EXPECT_LE(p.surface, thickness) << "frame " << f << ": triangle " << p.surface_triangle;
  }
  ASSERT_GT(contact, 0) << "the cloth must reach the box";
  EXPECT_EQ(measured, 11);
  std::printf("[ %s ] contact at frame %d; deepest point %.3f mm, deepest triangle point %.3f mm (GPU = CPU: %s)\n",
              d.name, contact, worst_vertex * 1e3, worst_surface * 1e3,
              gpu_test::exactDevice(gpu.contextInfo()) ? "checked" : "not this device");
}

INSTANTIATE_TEST_SUITE_P(Settings, GpuBoxDrop,
                         ::testing::Values(Drop{"2m_5_xpbd", 2.0, 5, Integrator::Xpbd},
                                           Drop{"2m_5_vbd", 2.0, 5, Integrator::Vbd},
                                           Drop{"1m_30_verlet", 1.0, 30, Integrator::Verlet}),
                         [](const ::testing::TestParamInfo<Drop>& p) { return std::string(p.param.name); });

class GpuMeshDeterminism : public GlTest {};

TEST_F(GpuMeshDeterminism, MeshObstacleAndMeshClothRunsAreBitIdentical) {
  ASSERT_TRUE(kThreaded);
  for (const char* file : {"torus.json", "flag.json"}) {
    const Scene scene = gpu_test::standardScene(file);
    GpuSolver first(scene, gpu_test::general()), second(scene, gpu_test::general());
    for (int f = 1; f <= 50; ++f) {
      first.stepFrame();
      second.stepFrame();
    }
    EXPECT_EQ(gpu_test::changedPoints(first.readPositions(), second.readPositions()), 0) << file;
    EXPECT_EQ(gpu_test::changedPoints(first.readDisplacements(), second.readDisplacements()), 0) << file;
  }
}

class GpuMeshLimits : public GlTest {};

TEST_F(GpuMeshLimits, AMeshBeyondTheBufferLimitIsRefusedBeforeAnyBuffer) {
  const Scene scene = gpu_test::standardScene("flag.json");
  try {
    GpuSolver gpu(scene, {.max_buffer_bytes = 4096});
    FAIL() << "a 651-point mesh fitted 4 KiB buffers";
  } catch (const GpuLimitError& e) {
    EXPECT_NE(std::string(e.what()).find("a 651-point mesh cloth needs"), std::string::npos) << e.what();
  }
}

class RenderExport : public GlTest {};

TEST_F(RenderExport, RenderWritesTheUsdaOfTheFramesItDraws) {
  namespace fs = std::filesystem;
  const test::TempDir temp("drape_render_export_");
  const fs::path& dir = temp.path();
  const std::string cmd = std::string(drape::test::drapeBinary()) + " render " +
                          testing::quote(std::string(drape::test::sourceDir()) + "/scenes/flag.json") +
                          " --frames 4 --every 2 --size 48x32 --out " + testing::quote((dir / "png").string()) +
                          " --export " + testing::quote((dir / "flag.usda").string()) + " >/dev/null 2>&1";
  const int raw = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(raw) && WEXITSTATUS(raw) == 0) << cmd;
  std::ifstream in(dir / "flag.usda");
  std::stringstream text;
  text << in.rdbuf();
  const std::string usda = text.str();
  EXPECT_EQ(usda.rfind("#usda 1.0\n", 0), 0u);
  for (const char* sample : {"\n        0: [", "\n        2: [", "\n        4: ["})
    EXPECT_NE(usda.find(sample), std::string::npos) << sample;
  EXPECT_EQ(usda.find("\n        1: ["), std::string::npos);
  EXPECT_TRUE(fs::exists(dir / "png" / "frame_0004.png"));
}

}  // namespace
}  // namespace drape
