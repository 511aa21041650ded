// A cloth from an OBJ mesh: the springs, masses, UVs and pins it gets, the meshes it refuses (one line
// naming file, key and problem), and that it behaves as cloth in the CPU reference.
#include "core/cloth_mesh.hpp"
#include "core/derived.hpp"
#include "core/metrics.hpp"
#include "core/stability.hpp"
#include "core/topology.hpp"
#include "cpu/cpu_solver.hpp"
#include "mesh_test_support.hpp"
#include "test_paths.hpp"

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <numeric>
#include <ostream>
#include <sstream>

namespace drape {
namespace {

using mesh_test::writeFile;

Scene meshScene(const std::string& obj_name, const std::string& obj_text, const std::string& extra_cloth = "",
                const std::string& extra_top = "") {
  writeFile(obj_name, obj_text);
  const std::string json =
      R"({"cloth": {"mesh": ")" + obj_name + R"(", "thickness": 0.01)" + extra_cloth + "}" + extra_top + "}";
  return parseScene(json, (mesh_test::tempDir() / "scene.json").string());
}

std::size_t count(const Topology& t, SpringType type) {
  return t.springCount(type);
}

TEST(MeshCloth, QuadGridGetsStructuralOnEdgesShearingAcrossQuadsBendingAcrossEdges) {
  const int n = 6;
  const Scene s = meshScene("quads.obj", mesh_test::gridObj(n, 1.0, 1.0, true));
  const Topology t = buildTopology(s.cloth);
  ASSERT_EQ(t.pointCount(), n * n);
  EXPECT_EQ(t.W, 0) << "a mesh cloth is not a grid";
  EXPECT_EQ(count(t, SpringType::Structural), std::size_t(2 * n * (n - 1)));
  EXPECT_EQ(count(t, SpringType::Shearing), std::size_t(2 * (n - 1) * (n - 1)));
  // Each quad is split by one diagonal; the triangles' other shared edges are the grid's interior edges,
  // and the vertices across each are not yet joined.
  EXPECT_EQ(count(t, SpringType::Bending), std::size_t(2 * (n - 2) * (n - 1)));
  EXPECT_EQ(t.triangles.size(), std::size_t(6 * (n - 1) * (n - 1)));
  for (const Spring& sp : t.springs) {
    EXPECT_LT(sp.a, sp.b);
    EXPECT_DOUBLE_EQ(sp.rest, glm::distance(t.initial_positions[sp.a], t.initial_positions[sp.b]));
  }
  // Springs come grouped by type, as the grid's do.
  EXPECT_TRUE(std::is_sorted(t.springs.begin(), t.springs.end(),
                             [](const Spring& a, const Spring& b) { return int(a.type) < int(b.type); }));
}

TEST(MeshCloth, TrianglesOnlyHaveNoShearingSprings) {
  const int n = 5;
  const Topology t = buildTopology(meshScene("tris.obj", mesh_test::gridObj(n, 1.0, 1.0, false)).cloth);
  EXPECT_EQ(count(t, SpringType::Shearing), 0u);
  // The quad diagonals are now triangle edges: structural.
  EXPECT_EQ(count(t, SpringType::Structural), std::size_t(2 * n * (n - 1) + (n - 1) * (n - 1)));
  EXPECT_GT(count(t, SpringType::Bending), 0u);
}

TEST(MeshCloth, MassIsDensityTimesAreaLumpedPerVertex) {
  const int n = 5;
  const Scene s = meshScene("mass.obj", mesh_test::gridObj(n, 2.0, 1.0, true), R"(, "density": 0.25)");
  const Topology t = buildTopology(s.cloth);
  double total = 0.0;
  for (std::size_t i = 0; i < std::size_t(t.pointCount()); ++i)
    total += derived::pointMass(s.cloth, t, i);
  EXPECT_NEAR(total, 0.25 * 4.0, 1e-12);
  const double cell = (2.0 / (n - 1)) * (2.0 / (n - 1));
  // An interior vertex has 6 of the 2 (n-1)^2 triangles around it; the corner split by the diagonal
  // has 2, the other corner 1.
  EXPECT_NEAR(t.area[std::size_t(n + 1)], 6 * cell / 2 / 3, 1e-12);
  EXPECT_NEAR(t.area[0], 2 * cell / 2 / 3, 1e-12);
  EXPECT_NEAR(t.area[std::size_t(n - 1)], 1 * cell / 2 / 3, 1e-12);
}

TEST(MeshCloth, UvsComeFromTheFileAndAreProjectedWithout) {
  const Topology t = buildTopology(meshScene("uv.obj", mesh_test::gridObj(4, 1.0, 1.0, true)).cloth);
  EXPECT_EQ(t.uvs[5], glm::vec2(1.0f / 3.0f, 1.0f / 3.0f));
  const Topology disc = buildTopology(meshScene("disc.obj", mesh_test::discObj(3, 0.5, 1.0)).cloth);
  ASSERT_EQ(disc.uvs.size(), std::size_t(disc.pointCount()));
  for (glm::vec2 uv : disc.uvs) {
    EXPECT_GE(std::min(uv.x, uv.y), 0.0f);
    EXPECT_LE(std::max(uv.x, uv.y), 1.0f);
  }
}

TEST(MeshCloth, PinsByIndexAndByBox) {
  const int n = 5;
  const Scene s = meshScene("pins.obj", mesh_test::gridObj(n, 1.0, 1.0, true),
                            R"(, "pinned_vertices": [24, 12], "pin_box": [[-0.01, 0.9, -0.01], [1.01, 1.1, 0.01]])");
  const Topology t = buildTopology(s.cloth);
  std::vector<int> pinned;
  for (int i = 0; i < t.pointCount(); ++i)
    if (t.pinned[std::size_t(i)]) pinned.push_back(i);
  EXPECT_EQ(pinned, (std::vector<int>{0, 1, 2, 3, 4, 12, 24}));
}

TEST(MeshCloth, NormalStencilSpansTheSurfaceAtEveryVertex) {
  const Topology t = buildTopology(meshScene("stencil.obj", mesh_test::discObj(4, 0.5, 1.0)).cloth);
  for (int i = 0; i < t.pointCount(); ++i) {
    const auto& s = t.normal_stencil[std::size_t(i)];
    const auto& x = t.initial_positions;
    const glm::dvec3 n = glm::cross(x[s[1]] - x[s[0]], x[s[3]] - x[s[2]]);
    ASSERT_GT(glm::length(n), 0.0) << "vertex " << i;
    EXPECT_NEAR(std::fabs(glm::normalize(n).y), 1.0, 1e-12) << "vertex " << i;
  }
}

TEST(MeshCloth, GridTopologyKeepsItsStencilAndUniformMass) {
  ClothSpec c;
  c.num_width_points = 4;
  c.num_height_points = 3;
  const Topology t = buildTopology(c);
  EXPECT_EQ(t.normal_stencil[0], (std::array<std::uint32_t, 4>{0, 1, 0, 4}));
  EXPECT_EQ(t.normal_stencil[5], (std::array<std::uint32_t, 4>{4, 6, 1, 9}));
  EXPECT_EQ(t.normal_stencil[11], (std::array<std::uint32_t, 4>{10, 11, 7, 11}));
  for (std::size_t i = 0; i < 12; ++i)
    EXPECT_EQ(derived::pointMass(c, t, i), derived::pointMass(c));
}

TEST(MeshCloth, HangsFromAPinnedEdgeWithBoundedStrain) {
  const int n = 12;
  Scene s = meshScene("hang.obj", mesh_test::gridObj(n, 1.0, 1.0, false),
                      R"(, "density": 0.3, "ks": 30, "pin_box": [[-0.01, 0.9, -0.01], [1.01, 1.1, 0.01]])",
                      R"(, "simulation": {"self_collision": false})");
  ASSERT_TRUE(checkStability(s).ok) << checkStability(s).message;
  CpuSolver<float> cpu(s);
  for (int f = 0; f < 90; ++f)
    cpu.stepFrame();
  const Positions x = cpu.readPositions();
  ASSERT_TRUE(allFinite(x));
  EXPECT_LT(centroid(x).y, 0.8) << "a cloth held along one edge falls until it hangs";
  EXPECT_LT(maxStrain(cpu.topology(), s.cloth, x), 0.2);
  for (int i = 0; i < n; ++i)
    EXPECT_EQ(glm::vec3(x[std::size_t(i)]), glm::vec3(cpu.topology().initial_positions[std::size_t(i)]))
        << "pinned point " << i;
}

TEST(MeshCloth, StabilityBoundUsesTheLightestVertex) {
  const Scene s = meshScene("bound.obj", mesh_test::gridObj(5, 1.0, 1.0, true));
  const Topology t = buildTopology(s.cloth);
  double worst = 0.0;
  std::vector<double> k(std::size_t(t.pointCount()), 0.0);
  for (const Spring& sp : t.springs) {
    k[sp.a] += derived::springStiffness(s.cloth, sp.type);
    k[sp.b] += derived::springStiffness(s.cloth, sp.type);
  }
  for (std::size_t i = 0; i < k.size(); ++i)
    worst = std::max(worst, k[i] / derived::pointMass(s.cloth, t, i));
  EXPECT_DOUBLE_EQ(maxStiffnessOverMass(s.cloth), worst);
  EXPECT_DOUBLE_EQ(stabilityNumber(s), s.sim.dt() * std::sqrt(worst));
}

struct BadMesh {
  const char* name;
  std::string obj;     // "" = no file
  std::string expect;  // in the one-line message, after "cloth.mesh: <file>: "
};

void PrintTo(const BadMesh& b, std::ostream* os) {
  *os << b.name;
}

class BadMeshTest : public ::testing::TestWithParam<BadMesh> {};

TEST_P(BadMeshTest, IsRefusedWithOneLineNamingFileKeyAndProblem) {
  const BadMesh& b = GetParam();
  const std::string obj = std::string(b.name) + ".obj";
  std::filesystem::remove(mesh_test::tempDir() / obj);
  if (!b.obj.empty()) writeFile(obj, b.obj);
  const std::string json = R"({"cloth": {"mesh": ")" + obj + R"(", "thickness": 0.01}})";
  const std::string scene = (mesh_test::tempDir() / "scene.json").string();
  try {
    parseScene(json, scene);
    FAIL() << "accepted";
  } catch (const SceneError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    EXPECT_EQ(what.rfind(scene + ": cloth.mesh: " + (mesh_test::tempDir() / obj).string() + ": ", 0), 0u) << what;
    EXPECT_NE(what.find(b.expect), std::string::npos) << what;
  }
}

const std::string kTriangle = "v 0 0 0\nv 1 0 0\nv 0 0 1\n";

INSTANTIATE_TEST_SUITE_P(
    Mesh, BadMeshTest,
    ::testing::Values(
        BadMesh{"missing", "", "cannot open: no such file"}, BadMesh{"no_faces", kTriangle, "no faces"},
        BadMesh{"nan_vertex", "v 0 0 0\nv 1 nan 0\nv 0 0 1\nf 1 2 3\n", "line 2: vertex coordinate 'nan'"},
        BadMesh{"inf_vertex", "v 0 0 0\nv 1 1e999 0\nv 0 0 1\nf 1 2 3\n", "not a finite number"},
        BadMesh{"beyond_float", "v 0 0 0\nv 1e300 0 0\nv 0 0 1\nf 1 2 3\n", "vertex 1 is beyond float range"},
        BadMesh{"two_coordinates", "v 0 0\nv 1 0 0\nv 0 0 1\nf 1 2 3\n", "needs x, y and z"},
        BadMesh{"index_out_of_range", kTriangle + "f 1 2 4\n", "line 4: face corner '4' names vertex 4, but only 3"},
        BadMesh{"repeated_corner", kTriangle + "f 1 2 2\n", "face 0 is degenerate: vertex 1 appears twice"},
        BadMesh{"zero_area", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n", "has zero area"},
        BadMesh{"non_manifold", kTriangle + "v 0 1 0\nv 0 -1 0\nf 1 2 3\nf 2 1 4\nf 1 2 5\n",
                "the edge between vertices 0 and 1 is shared by more than two triangles"},
        BadMesh{"unused_vertex", kTriangle + "v 5 5 5\nf 1 2 3\n", "vertex 3 is in no face"},
        BadMesh{"syntax", kTriangle + "f 1 2 x\n", "line 4: face corner 'x' is not v, v/vt"}),
    [](const ::testing::TestParamInfo<BadMesh>& p) { return std::string(p.param.name); });

TEST(MeshCloth, GridKeysBesideAMeshAreRefused) {
  writeFile("ok.obj", mesh_test::gridObj(3, 1.0, 1.0, true));
  const std::string scene = (mesh_test::tempDir() / "scene.json").string();
  EXPECT_THROW(parseScene(R"({"cloth": {"mesh": "ok.obj", "thickness": 0.01, "width": 1}})", scene), SceneError);
  try {
    parseScene(R"({"cloth": {"mesh": "ok.obj", "thickness": 0.01, "pinned_vertices": [9]}})", scene);
    FAIL() << "accepted a pin beyond the mesh";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("cloth.pinned_vertices[0]: 9 is not a point of this cloth"), std::string::npos)
        << e.what();
  }
}

// What a user meets: `drape simulate` on a scene with a bad mesh exits 2 with one line on stderr naming the
// scene, the key, the mesh file and the problem, and writes no --out.
TEST(MeshClothCommand, BadMeshIsStatusTwoWithOneLineAndNoOutput) {
  const auto dir = mesh_test::tempDir();
  writeFile("cmd_bad.obj", "v 0 0 0\nv 1 0 0\nv 0 0 1\nv 0 1 0\nv 0 -1 0\nf 1 2 3\nf 2 1 4\nf 1 2 5\n");
  const auto scene = writeFile("cmd_bad.json", R"({"cloth": {"mesh": "cmd_bad.obj", "thickness": 0.01}})");
  std::filesystem::remove(dir / "cmd_out.json");
  std::filesystem::remove(dir / "cmd_err.txt");
  const std::string cmd = std::string(drape::test::drapeBinary()) + " simulate " + scene.string() + " --out " +
                          (dir / "cmd_out.json").string() + " >/dev/null 2>" + (dir / "cmd_err.txt").string();
  const int raw = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(raw));
  EXPECT_EQ(WEXITSTATUS(raw), 2);
  std::stringstream err;
  err << std::ifstream(dir / "cmd_err.txt").rdbuf();
  const std::string text = err.str();
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 1) << text;
  EXPECT_NE(text.find(scene.string() + ": cloth.mesh: "), std::string::npos) << text;
  EXPECT_NE(text.find("non-manifold"), std::string::npos) << text;
  EXPECT_FALSE(std::filesystem::exists(dir / "cmd_out.json"));
  // bench resamples grids: a mesh cloth is refused the same way.
  const std::string flag = std::string(drape::test::sourceDir()) + "/scenes/flag.json";
  const int bench = std::system((std::string(drape::test::drapeBinary()) + " bench --scenes " + flag +
                                 " --solver cpu --sizes 8 --frames 1 >/dev/null 2>&1")
                                    .c_str());
  ASSERT_TRUE(WIFEXITED(bench));
  EXPECT_EQ(WEXITSTATUS(bench), 2);
}

}  // namespace
}  // namespace drape
