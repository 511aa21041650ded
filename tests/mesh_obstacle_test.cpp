// Mesh obstacles: the baked distance field against exact triangle distances, the meshes refused, the
// collision response, and no cloth point ending inside an obstacle in the bundled scenes or a 20 m/s throw.
#include "core/mesh_obstacle.hpp"
#include "core/mesh_query.hpp"
#include "core/metrics.hpp"
#include "core/penetration.hpp"
#include "cpu/cpu_solver.hpp"
#include "cpu/mesh_physics.hpp"
#include "mesh_test_support.hpp"
#include "test_paths.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace drape {
namespace {

namespace fs = std::filesystem;

const fs::path kScenes = fs::path(drape::test::sourceDir()) / "scenes";

const MeshObstacle& firstMesh(const Scene& s) {
  return *s.meshes.at(0).mesh;
}

// Closed boxes as 6 quads each, wound outward (or inward), in one OBJ.
std::string boxesObj(const std::vector<std::pair<glm::dvec3, glm::dvec3>>& boxes, bool inward = false) {
  std::string vertices, faces;
  int base = 0;
  for (const auto& [lo, hi] : boxes) {
    for (int k = 0; k < 8; ++k)
      vertices += fmt::format("v {} {} {}\n", k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z);
    const int quads[6][4] = {{1, 3, 4, 2}, {5, 6, 8, 7}, {1, 2, 6, 5}, {3, 7, 8, 4}, {1, 5, 7, 3}, {2, 4, 8, 6}};
    for (const auto& q : quads) {
      if (inward)
        faces += fmt::format("f {} {} {} {}\n", base + q[3], base + q[2], base + q[1], base + q[0]);
      else
        faces += fmt::format("f {} {} {} {}\n", base + q[0], base + q[1], base + q[2], base + q[3]);
    }
    base += 8;
  }
  return vertices + faces;
}

std::string boxObj(glm::dvec3 lo, glm::dvec3 hi, bool inward = false) {
  return boxesObj({{lo, hi}}, inward);
}

Scene obstacleScene(const std::string& obj_text, const std::string& extra = "") {
  mesh_test::writeFile("obstacle.obj", obj_text);
  return parseScene(R"({"cloth": {"width": 0.4, "height": 0.4, "num_width_points": 12, "num_height_points": 12,
                       "thickness": 0.005, "orientation": 0},
                       "meshes": [{"obj": "obstacle.obj")" +
                        extra + "}]}",
                    (mesh_test::tempDir() / "scene.json").string());
}

// Within the band the samples are the exact signed distances; beyond it, the closest-point transform's: the
// distance to a real surface point, so never below the exact one, and (measured on the bundled obstacles) at
// most 0.17 cells above it. The sign is the exact one everywhere.
TEST(MeshObstacle, FieldSamplesAreSignedDistancesThroughoutTheLattice) {
  const Scene s = loadScene(kScenes / "torus.json");
  const MeshObstacle& m = firstMesh(s);
  const DistanceField& f = m.field;
  const MeshQuery query(m);
  int exact_checked = 0, beyond = 0, deep_inside = 0;
  double worst = 0;
  // Every 5th sample along each axis: about 8000 exact queries.
  for (int k = 0; k < f.dims.z; k += 5)
    for (int j = 0; j < f.dims.y; j += 5)
      for (int i = 0; i < f.dims.x; i += 5) {
        const glm::dvec3 p = f.origin + f.cell * glm::dvec3(i, j, k);
        const double exact = query.signedDistance(p);
        const float sample = f.samples[f.index(i, j, k)];
        if (std::fabs(exact) <= f.band) {
          EXPECT_EQ(sample, float(exact)) << i << " " << j << " " << k;
          ++exact_checked;
          continue;
        }
        ++beyond;
        deep_inside += exact < -f.band;
        ASSERT_EQ(sample < 0, exact < 0) << i << " " << j << " " << k;
        const double over = std::fabs(double(sample)) - std::fabs(exact);
        EXPECT_GE(over, -1e-6) << "below the exact distance at " << i << " " << j << " " << k;
        worst = std::max(worst, over);
      }
  EXPECT_GT(exact_checked, 100);
  EXPECT_GT(deep_inside, 100) << "the tube is 24 cm thick: most of its inside is beyond the band";
  EXPECT_GT(beyond, 1000);
  EXPECT_LT(worst, 0.2 * f.cell) << "the closest-point transform's error";
  EXPECT_NEAR(f.cell, (2 * (0.32 + 0.12)) / kFieldResolution, 1e-3);
}

// The field's trilinear interpolation, which the solvers collide with, against the exact signed distance at
// random points of the table's lattice: right in sign wherever the point is more than a cell from the
// surface, and within 2 cells everywhere (what docs/design.md promises).
TEST(MeshObstacle, TrilinearFieldIsWithinTwoCellsOfTheExactDistance) {
  const Scene s = loadScene(kScenes / "tablecloth.json");
  const MeshObstacle& m = firstMesh(s);
  const DistanceField& f = m.field;
  const MeshQuery query(m);
  std::uint32_t seed = 12345;
  auto uniform = [&seed] {
    seed = seed * 1664525u + 1013904223u;
    return double(seed >> 8) / 16777216.0;
  };
  double worst = 0;
  for (int n = 0; n < 3000; ++n) {
    const glm::dvec3 p = f.origin + f.cell * glm::dvec3(f.dims - 1) * glm::dvec3(uniform(), uniform(), uniform());
    const double exact = query.signedDistance(p), estimate = *fieldDistance(f, p);
    worst = std::max(worst, std::fabs(estimate - exact));
    if (std::fabs(exact) > f.cell) {
      EXPECT_EQ(estimate < 0, exact < 0) << p.x << " " << p.y << " " << p.z;
    }
  }
  EXPECT_LT(worst, 2 * f.cell);
}

TEST(MeshObstacle, QueryAnswersAsTheLoopOverEveryTriangle) {
  const Scene s = loadScene(kScenes / "mannequin.json");
  const MeshObstacle& m = firstMesh(s);
  const MeshQuery query(m);
  const DistanceField& f = m.field;
  for (int n = 0; n < 300; ++n) {
    // Spread over the lattice and a little beyond it.
    const glm::dvec3 t(std::fmod(n * 0.618034, 1.0), std::fmod(n * 0.414214, 1.0), std::fmod(n * 0.732051, 1.0));
    const glm::dvec3 p = f.origin - f.cell + (f.cell * glm::dvec3(f.dims + 1)) * t;
    EXPECT_EQ(query.inside(p), insideMesh(m, p)) << n;
    EXPECT_EQ(query.distance(p), unsignedDistance(m, p)) << n;
  }
}

TEST(MeshObstacle, InwardWoundMeshIsTurnedAroundAndOverlappingPartsAreTheirUnion) {
  const Scene in = obstacleScene(boxObj({0, 0, 0}, {1, 1, 1}, true));
  EXPECT_TRUE(insideMesh(firstMesh(in), {0.5, 0.5, 0.5}));
  EXPECT_LT(signedDistance(firstMesh(in), {0.5, 0.5, 0.5}), -0.49);
  // Two boxes overlapping in [0.5, 1]: a point there is inside (winding 2), and so is its field sample.
  const std::string two = boxesObj({{{0, 0, 0}, {1, 1, 1}}, {{0.5, 0.2, 0.2}, {1.5, 0.8, 0.8}}});
  const Scene both = obstacleScene(two);
  const MeshObstacle& m = firstMesh(both);
  EXPECT_TRUE(insideMesh(m, {0.75, 0.5, 0.5}));
  EXPECT_TRUE(insideMesh(m, {1.25, 0.5, 0.5}));
  EXPECT_FALSE(insideMesh(m, {1.25, 0.9, 0.5}));
  const DistanceField& f = m.field;
  const glm::ivec3 at(glm::round((glm::dvec3(0.75, 0.5, 0.5) - f.origin) / f.cell));
  EXPECT_LT(f.samples[f.index(at.x, at.y, at.z)], 0.0f);
}

struct BadObstacle {
  const char* name;
  std::string obj;
  std::string expect;
};

class BadObstacleTest : public ::testing::TestWithParam<BadObstacle> {};

TEST_P(BadObstacleTest, IsRefusedWithOneLineNamingTheKeyAndProblem) {
  try {
    obstacleScene(GetParam().obj);
    FAIL() << "accepted";
  } catch (const SceneError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(": meshes[0].obj: "), std::string::npos) << what;
    EXPECT_NE(what.find(GetParam().expect), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos);
  }
}

INSTANTIATE_TEST_SUITE_P(
    Mesh, BadObstacleTest,
    ::testing::Values(
        BadObstacle{"open", "v 0 0 0\nv 1 0 0\nv 0 0 1\nf 1 2 3\n", "not a closed, consistently wound surface"},
        BadObstacle{"one_face_turned",
                    boxObj({0, 0, 0}, {1, 1, 1}).substr(0, boxObj({0, 0, 0}, {1, 1, 1}).rfind("f ")) + "f 6 8 4 2\n",
                    "not a closed, consistently wound surface"},
        BadObstacle{"no_faces", "v 0 0 0\n", "no faces"},
        BadObstacle{"nan", "v nan 0 0\nv 1 0 0\nv 0 0 1\nf 1 2 3\n", "not a finite number"}),
    [](const ::testing::TestParamInfo<BadObstacle>& p) { return std::string(p.param.name); });

TEST(MeshObstacle, MissingFileAndBadKeysAreRefused) {
  const std::string scene = (mesh_test::tempDir() / "scene.json").string();
  const std::string cloth = R"("cloth": {"width": 1, "height": 1, "num_width_points": 4, "num_height_points": 4,
                            "thickness": 0.01, "orientation": 0})";
  EXPECT_THROW(parseScene("{" + cloth + R"(, "meshes": [{"obj": "nothing_here.obj"}]})", scene), SceneError);
  mesh_test::writeFile("box.obj", boxObj({0, 0, 0}, {1, 1, 1}));
  EXPECT_THROW(parseScene("{" + cloth + R"(, "meshes": [{"obj": "box.obj", "scale": 0}]})", scene), SceneError);
  EXPECT_THROW(parseScene("{" + cloth + R"(, "meshes": [{"obj": "box.obj", "friction": 2}]})", scene), SceneError);
  for (const char* bad : {"0", "-0.01", "\"thick\""})
    EXPECT_THROW(parseScene("{" + cloth + R"(, "meshes": [{"obj": "box.obj", "thickness": )" + bad + "}]}", scene),
                 SceneError)
        << bad;
  try {
    parseScene("{" + cloth + R"(, "meshes": [{"obj": "box.obj", "thickness": 0}]})", scene);
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("meshes[0].thickness: must be > 0"), std::string::npos) << e.what();
  }
  EXPECT_THROW(parseScene("{" + cloth + R"(, "meshes": [{"obj": "box.obj", "ofset": [0, 0, 0]}]})", scene), SceneError);
  try {
    mesh_test::writeFile("big.obj", boxObj({0, 0, 0}, {10, 10, 10}));
    parseScene("{" + cloth + R"(, "meshes": [{"obj": "big.obj", "scale": 1e38}]})", scene);
    FAIL() << "a box scaled beyond float range was accepted";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("is beyond float range"), std::string::npos) << e.what();
  }
  const Scene placed = parseScene(
      "{" + cloth + R"(, "meshes": [{"obj": "box.obj", "offset": [1, 2, 3], "scale": 2, "friction": 0.7}]})", scene);
  EXPECT_EQ(placed.meshes[0].friction, 0.7);
  EXPECT_EQ(meshThickness(placed.cloth, placed.meshes[0]), 0.01) << "the cloth's, by default";
  const Scene thin = parseScene("{" + cloth + R"(, "meshes": [{"obj": "box.obj", "thickness": 0.003}]})", scene);
  EXPECT_EQ(meshThickness(thin.cloth, thin.meshes[0]), 0.003);
  EXPECT_TRUE(insideMesh(firstMesh(placed), {2.9, 3.9, 4.9}));
  EXPECT_FALSE(insideMesh(firstMesh(placed), {3.1, 3.9, 4.9}));
}

TEST(MeshObstacle, CollisionMovesAPointInsideOutToTheSurfaceOffsetWithFriction) {
  const Scene s = obstacleScene(boxObj({0, 0, 0}, {1, 1, 1}));
  const DistanceField& f = firstMesh(s).field;
  glm::dvec3 c;
  // 3 mm below the top face, moving down: out to kMeshSurfaceOffset above it, without friction.
  const glm::dvec3 x(0.5, 0.997, 0.5), v(0, -0.004, 0);
  ASSERT_TRUE(physics::collideField(x, v, f, kMeshSurfaceOffset, 0.0, c));
  EXPECT_NEAR((x + c).y, 1.0 + kMeshSurfaceOffset, 1e-9);
  EXPECT_NEAR((x + c).x, 0.5, 1e-12);
  // With friction 1 the point returns to where it was before the substep.
  ASSERT_TRUE(physics::collideField(x, v, f, kMeshSurfaceOffset, 1.0, c));
  EXPECT_NEAR(glm::distance(x + c, x - v), 0.0, 1e-12);
  EXPECT_FALSE(physics::collideField(glm::dvec3(0.5, 1.01, 0.5), v, f, kMeshSurfaceOffset, 0.0, c))
      << "outside the offset";
  EXPECT_FALSE(physics::collideField(glm::dvec3(5, 5, 5), v, f, kMeshSurfaceOffset, 0.0, c)) << "beyond the field";
  const double nan = std::nan("");
  EXPECT_FALSE(physics::collideField(glm::dvec3(nan, 0.5, 0.5), v, f, kMeshSurfaceOffset, 0.0, c));
}

// However deep inside, a point goes out through the nearest face: 3 cm under the top of a 1 m box (4 cells,
// beyond the band of exact samples) and 3 cm inside its side near a corner.
TEST(MeshObstacle, APointDeepInsideIsPushedOutThroughTheNearestFace) {
  const Scene s = obstacleScene(boxObj({0, 0, 0}, {1, 1, 1}));
  const DistanceField& f = firstMesh(s).field;
  ASSERT_GT(0.03, f.band);
  glm::dvec3 c;
  const glm::dvec3 v(0, -0.004, 0);
  const glm::dvec3 under_top(0.5, 0.97, 0.45);
  ASSERT_TRUE(physics::collideField(under_top, v, f, kMeshSurfaceOffset, 0.0, c));
  EXPECT_NEAR((under_top + c).y, 1.0 + kMeshSurfaceOffset, 1e-4);
  EXPECT_NEAR((under_top + c).x, 0.5, 1e-4);
  EXPECT_NEAR((under_top + c).z, 0.45, 1e-4);
  const glm::dvec3 inside_side(0.97, 0.6, 0.2);  // 3 cm from x = 1, 20 cm from z = 0
  ASSERT_TRUE(physics::collideField(inside_side, v, f, kMeshSurfaceOffset, 0.0, c));
  EXPECT_NEAR((inside_side + c).x, 1.0 + kMeshSurfaceOffset, 1e-4);
  EXPECT_NEAR((inside_side + c).y, 0.6, 1e-4);
  // In float, as the solvers run it: the same.
  glm::vec3 cf;
  ASSERT_TRUE(physics::collideField(glm::vec3(under_top), glm::vec3(v), f, float(kMeshSurfaceOffset), 0.0f, cf));
  EXPECT_NEAR(double((glm::vec3(under_top) + cf).y), 1.0 + kMeshSurfaceOffset, 1e-4);
}

// The gauge against depths worked out by hand: a triangle whose corners are all outside a box, cutting its
// edge, is inside by d / sqrt(2) at most; one through a sphere by r - (distance of its plane).
// A box within float range but scaled far past any scene (a hostile file: 1e28 m corners) is an obstacle
// like any other: the solver is made (its sharp edges' lookup grid once asked for more cells than a vector
// holds) and the cloth, far from it, falls freely.
TEST(MeshObstacle, AnObstacleScaledPastAnySceneIsMadeAndStepped) {
  const Scene s = obstacleScene(boxObj({1e27, 1e27, 1e27}, {1e28, 2e28, 1e28}));
  CpuSolver<float> cpu(s);
  const auto start = cpu.positions();
  for (int f = 0; f < 3; ++f)
    cpu.stepFrame();
  for (std::size_t i = 0; i < start.size(); ++i)
    ASSERT_TRUE(std::isfinite(cpu.positions()[i].y) && cpu.positions()[i].y < start[i].y) << "point " << i;
}

TEST(Penetration, DeepestPointOfATriangleAcrossABoxEdge) {
  const Scene s = obstacleScene(boxObj({0, 0, 0}, {1, 1, 1}));
  const double d = 0.02;  // the edge (x = 1, y = 1) is d beyond the triangle's plane x + y = 2 - d sqrt(2)
  const double r2 = std::sqrt(2.0);
  Topology topo;
  topo.triangles = {0, 1, 2};
  const Positions x = {{1.03, 0.97 - d * r2, 0.4}, {0.97 - d * r2, 1.03, 0.4}, {1.03, 0.97 - d * r2, 0.6}};
  const PenetrationGauge gauge(s, topo, 1e-3);
  const Penetration p = gauge.measure(x);
  EXPECT_EQ(p.vertices_inside, 0);
  EXPECT_EQ(p.vertex, 0.0);
  EXPECT_NEAR(p.surface, d / r2, 1e-3) << "sampled at most 1 mm apart";
  EXPECT_LE(p.surface, d / r2 + 1e-12);
  EXPECT_NEAR(p.nearest, 0.03, 2 * firstMesh(s).field.cell)
      << "each corner is 3 cm outside a face (an estimate so far)";
  // The same triangle moved 4 cm out along x, its corners beyond the field's lattice: outside, nothing inside.
  Positions moved = x;
  for (glm::dvec3& q : moved)
    q.x += 0.04;
  EXPECT_EQ(gauge.measure(moved).surface, 0.0);
  EXPECT_EQ(p.surface_triangle, 0);

  Scene ball;
  ball.spheres.push_back({glm::dvec3(0, 0, 0), 0.5, 0.3});
  const Positions y = {{-1, 0.4, -1}, {1, 0.4, -1}, {0, 0.4, 1}, {0, 0.45, 0}};
  Topology two;
  two.triangles = {0, 1, 2};
  const Penetration q = PenetrationGauge(ball, two).measure(y);
  EXPECT_NEAR(q.surface, 0.1, 1e-12) << "the plane y = 0.4 is 0.1 inside a sphere of radius 0.5";
  EXPECT_NEAR(q.vertex, 0.05, 1e-12) << "point 3, not in a triangle, is 5 cm inside";
  EXPECT_EQ(q.vertex_index, 3);
  EXPECT_EQ(q.vertices_inside, 1);
}

// Every point outside every obstacle (the exact triangles, not the field).
void expectOutside(const Scene& s, const Positions& x, const std::string& what) {
  for (const MeshSpec& m : s.meshes)
    for (std::size_t i = 0; i < x.size(); ++i)
      ASSERT_FALSE(insideMesh(*m.mesh, x[i])) << what << ": point " << i << " ends inside " << m.obj;
}

class BundledObstacleScene : public ::testing::TestWithParam<const char*> {};

TEST_P(BundledObstacleScene, NoPointEndsInsideAnObstacle) {
  const Scene s = loadScene(kScenes / GetParam());
  CpuSolver<float> cpu(s);
  for (int f = 1; f <= 120; ++f) {
    cpu.stepFrame();
    if (f % 40 == 0) expectOutside(s, cpu.readPositions(), std::string(GetParam()) + " frame " + std::to_string(f));
  }
  const Positions x = cpu.readPositions();
  ASSERT_TRUE(allFinite(x));
  EXPECT_GT(colliderDistances(s, x).back(), 0.0);
  EXPECT_LT(colliderDistances(s, x).back(), 0.01) << "the cloth lies on the obstacle";
}

INSTANTIATE_TEST_SUITE_P(Scenes, BundledObstacleScene,
                         ::testing::Values("tablecloth.json", "torus.json", "mannequin.json"),
                         [](const ::testing::TestParamInfo<const char*>& p) {
                           std::string name = p.param;
                           return name.substr(0, name.find('.'));
                         });

// A small cloth thrown straight down at 20 m/s onto each bundled obstacle's thinnest part in its path: 7.4 mm
// per substep, against a 5 cm table top, a 24 cm torus tube, a 10 cm arm.
struct Throw {
  const char* scene;
  glm::dvec3 corner;  // where the cloth's (0, 0) corner starts
};

class ThrowTest : public ::testing::TestWithParam<Throw> {};

TEST_P(ThrowTest, At20MetresPerSecondNoPointEndsInside) {
  Scene s = loadScene(kScenes / GetParam().scene);
  s.cloth.width = s.cloth.height = 0.2;
  s.cloth.num_width_points = s.cloth.num_height_points = 12;
  s.cloth.thickness = 0.004;
  CpuSolver<float> cpu(s);
  const double dt = s.sim.dt();
  std::vector<glm::dvec3> x = cpu.topology().initial_positions, v(x.size(), glm::dvec3(0, -20.0 * dt, 0));
  for (glm::dvec3& p : x)
    p += GetParam().corner - glm::dvec3(0, 1, 0);
  cpu.setState(x, v);
  double lowest_speed = 20.0;
  for (int f = 1; f <= 12; ++f) {
    cpu.stepFrame();
    expectOutside(s, cpu.readPositions(), std::string(GetParam().scene) + " frame " + std::to_string(f));
    lowest_speed = std::min(lowest_speed, glm::length(cpu.readDisplacements()[65]) / dt);
  }
  EXPECT_LT(lowest_speed, 5.0) << "the cloth was stopped by the obstacle, not missed it";
}

INSTANTIATE_TEST_SUITE_P(Scenes, ThrowTest,
                         ::testing::Values(Throw{"tablecloth.json", {0.9, 1.1, 0.7}},
                                           Throw{"torus.json", {0.82, 0.6, 0.5}},
                                           Throw{"mannequin.json", {1.1, 0.9, 0.6}}),
                         [](const ::testing::TestParamInfo<Throw>& p) {
                           std::string name = p.param.scene;
                           return name.substr(0, name.find('.'));
                         });

}  // namespace
}  // namespace drape
