// The closest distance of a cloth to a mesh obstacle (simulate's summary, accuracy's penetration): the
// field's value near the surface, the exact triangles elsewhere, and the bucket search equal to trying
// every triangle.
#include "core/mesh_distance.hpp"
#include "core/metrics.hpp"
#include "core/scene.hpp"
#include "test_paths.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <limits>
#include <random>

namespace drape {
namespace {

const Scene& tableScene() {
  static const Scene scene = loadScene(std::filesystem::path(drape::test::sourceDir()) / "scenes" / "tablecloth.json");
  return scene;
}

const MeshObstacle& table() {
  return *tableScene().meshes.at(0).mesh;
}

double everyTriangle(const MeshObstacle& mesh, glm::dvec3 p) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t t = 0; t < mesh.triangles.size() / 3; ++t)
    best = std::min(best, triangleDistance(mesh, t, p));
  return best;
}

// Points around the table, inside its top, beside its legs, and far off in every direction.
std::vector<glm::dvec3> scattered(int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> near(-0.5, 2.5), far(-20.0, 20.0);
  std::vector<glm::dvec3> points;
  for (int i = 0; i < count; ++i)
    points.push_back(i % 4 == 3 ? glm::dvec3(far(rng), far(rng), far(rng))
                                : glm::dvec3(near(rng), 0.5 * near(rng), 0.8 * near(rng)));
  return points;
}

TEST(MeshDistance, TheBucketSearchFindsWhatEveryTriangleGives) {
  const MeshObstacle& mesh = table();
  for (const glm::dvec3& p : scattered(40, 7))
    EXPECT_EQ(closestTriangleDistance(mesh, {p}), everyTriangle(mesh, p)) << p.x << " " << p.y << " " << p.z;
  const std::vector<glm::dvec3> cloud = scattered(120, 11);
  double best = std::numeric_limits<double>::infinity();
  for (const glm::dvec3& p : cloud)
    best = std::min(best, everyTriangle(mesh, p));
  EXPECT_EQ(closestTriangleDistance(mesh, cloud), best);
}

// A cloth near the surface is measured by the field the solvers collide with: its trilinear value.
TEST(MeshDistance, NearTheSurfaceTheFieldAnswers) {
  const MeshObstacle& mesh = table();
  // The table's top at y = 0.775 around (1, 0.8); one point 1 cm above it, one 1 cm into it, one far above.
  const glm::dvec3 above(1.0, 0.785, 0.8), inside(1.2, 0.765, 0.7), far(1.0, 3.0, 0.8);
  ASSERT_TRUE(fieldDistance(mesh.field, above).has_value());
  EXPECT_EQ(closestSignedDistance(mesh, {above, far}), *fieldDistance(mesh.field, above));
  EXPECT_NEAR(closestSignedDistance(mesh, {above, far}), signedDistance(mesh, above), 1e-4);
  EXPECT_EQ(closestSignedDistance(mesh, {above, inside, far}), *fieldDistance(mesh.field, inside));
  EXPECT_LT(closestSignedDistance(mesh, {above, inside, far}), 0.0);
}

// Beyond the field's band the distance is the exact one, whether the points are in the field's box or not.
TEST(MeshDistance, FarFromTheSurfaceTheTrianglesAnswerExactly) {
  const MeshObstacle& mesh = table();
  for (double height : {0.06, 0.3, 5.0}) {
    std::vector<glm::dvec3> cloth;
    for (int i = 0; i < 12; ++i)
      for (int k = 0; k < 12; ++k)
        cloth.emplace_back(-0.2 + 0.2 * i, 0.775 + height + 0.002 * i, 0.15 * k);
    double best = std::numeric_limits<double>::infinity();
    for (const glm::dvec3& p : cloth)
      best = std::min(best, signedDistance(mesh, p));
    EXPECT_EQ(closestSignedDistance(mesh, cloth), best) << height;
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(closestSignedDistance(mesh, {{nan, 0, 0}}), std::numeric_limits<double>::infinity());
  EXPECT_EQ(closestSignedDistance(mesh, {{nan, 0, 0}, {1.0, 2.0, 0.8}}), everyTriangle(mesh, {1.0, 2.0, 0.8}));
}

// Found by tools/test --fuzz obj: a flat obstacle (two triangles back to back, "closed") has no extent
// along y; a point off that plane made a bucket index beyond int (UBSan: float-cast-overflow).
TEST(MeshDistance, AFlatObstacleIsSearchedToo) {
  const MeshObstacle flat = buildMeshObstacle({{{-2, 0, 0}, {0, 0, 0}, {1, 0, -1}}, {{0, 1, 2, 1}}, {}}, {}, 1.0);
  for (const glm::dvec3& p : {glm::dvec3(0, 1000, 0), glm::dvec3(5, -3, 2), glm::dvec3(-0.5, 1e-9, -0.1)})
    EXPECT_EQ(closestTriangleDistance(flat, {p}), everyTriangle(flat, p));
}

TEST(MeshDistance, TheSummaryUsesIt) {
  const Scene& s = tableScene();
  const std::vector<glm::dvec3> x = {{1.0, 0.785, 0.8}, {0.0, 1.5, 0.0}};
  const std::vector<double> d = colliderDistances(s, x);
  ASSERT_EQ(d.size(), s.planes.size() + 1);
  EXPECT_EQ(d.back(), closestSignedDistance(table(), x));
}

}  // namespace
}  // namespace drape
