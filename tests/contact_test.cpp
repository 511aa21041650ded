// Contact that holds (issue 26), on the CPU: the face contacts' pure functions against hand-worked cases,
// the features and grids they read, collisions as the last pass, the box drop at the settings,
// and self-collision skipping the pairs the springs hold.
#include "app/command_error.hpp"
#include "app/solver_factory.hpp"
#include "core/mesh_features.hpp"
#include "core/metrics.hpp"
#include "core/penetration.hpp"
#include "cpu/collision_pairs.hpp"
#include "cpu/cpu_solver.hpp"
#include "cpu/mesh_physics.hpp"
#include "test_paths.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>
#include <string>

namespace drape {
namespace {

namespace fs = std::filesystem;
using dvec3 = glm::dvec3;

const fs::path kScenes = fs::path(drape::test::sourceDir()) / "scenes";

// ---- the pure functions -------------------------------------------------------------------------------

// The edge (x = 1, y = 1) of the box [0, 1]^3 along z, its faces' normals +x and +y.
const dvec3 kEdgeA(1, 1, 0), kEdgeB(1, 1, 1), kSide(1, 0, 0), kTop(0, 1, 0);

TEST(EdgeContact, ACrossingCloseAboveTheEdgeMovesOutAlongTheCommonNormal) {
  // A cloth edge across the box's edge at 45 degrees, in the plane x + y = 2 + 0.002 sqrt(2): 2 mm above it.
  const double up = 0.002, thickness = 0.005;
  const dvec3 out = glm::normalize(dvec3(1, 1, 0));
  const dvec3 p = dvec3(0.9, 1.1, 0.4) + up * out, q = dvec3(1.1, 0.9, 0.6) + up * out;
  double s;
  dvec3 move;
  ASSERT_TRUE(physics::edgeContact(p, q, kEdgeA, kEdgeB, kSide, kTop, thickness, s, move));
  EXPECT_NEAR(s, 0.5, 1e-12);
  // The common normal of (0.2, -0.2, 0.2) and z is along (1, 1, 0): out by thickness - 2 mm.
  EXPECT_NEAR(glm::distance(move, (thickness - up) * out), 0.0, 1e-12);
  // Below the edge (the cloth cut into the box by 3 mm): out by 3 mm + thickness.
  ASSERT_TRUE(physics::edgeContact(p - 0.005 * out, q - 0.005 * out, kEdgeA, kEdgeB, kSide, kTop, thickness, s, move));
  EXPECT_NEAR(glm::length(move), thickness + 0.003, 1e-12);
  EXPECT_GT(glm::dot(move, out), 0.0);
  // The same edge the other way round: the same move, the same point (s measured from the other end).
  ASSERT_TRUE(physics::edgeContact(p, q, kEdgeA, kEdgeB, kSide, kTop, thickness, s, move));
  double s2;
  dvec3 move2;
  ASSERT_TRUE(physics::edgeContact(q, p, kEdgeA, kEdgeB, kSide, kTop, thickness, s2, move2));
  EXPECT_NEAR(s2, 1.0 - s, 1e-12);
  EXPECT_NEAR(glm::distance(move, move2), 0.0, 1e-12);
}

TEST(EdgeContact, NothingWhereTheEdgesAreClearEndToEndOrParallel) {
  const dvec3 out = glm::normalize(dvec3(1, 1, 0));
  double s;
  dvec3 move;
  const dvec3 p(0.9, 1.1, 0.4), q(1.1, 0.9, 0.6);
  EXPECT_FALSE(physics::edgeContact(p + 0.006 * out, q + 0.006 * out, kEdgeA, kEdgeB, kSide, kTop, 0.005, s, move))
      << "6 mm above: clear";
  EXPECT_FALSE(
      physics::edgeContact(dvec3(1.003, 1.0, 0.5), dvec3(1.2, 0.8, 0.5), kEdgeA, kEdgeB, kSide, kTop, 0.005, s, move))
      << "closest at the cloth edge's end: the point's business";
  EXPECT_FALSE(physics::edgeContact(dvec3(1.001, 1.001, 0.2), dvec3(1.001, 1.001, 0.8), kEdgeA, kEdgeB, kSide, kTop,
                                    0.005, s, move))
      << "parallel";
  // Beside the box's side face, 1 cm out, crossing under the edge's height: clear of the side face.
  EXPECT_FALSE(physics::edgeContact(dvec3(1.01, 0.99, 0.4), dvec3(1.01, 0.98, 0.6) + dvec3(0, 0.0, 0), kEdgeA, kEdgeB,
                                    kSide, kTop, 0.005, s, move));
}

TEST(EdgeContact, SharesMoveTheContactPointByTheMove) {
  const dvec3 move(0.001, 0.002, -0.0005);
  for (double s : {0.1, 0.5, 0.83}) {
    const dvec3 dp = physics::edgeShare(s, false, move), dq = physics::edgeShare(s, true, move);
    EXPECT_NEAR(glm::distance((1 - s) * dp + s * dq, move), 0.0, 1e-15) << s;
  }
  const dvec3 bary(0.2, 0.5, 0.3);
  dvec3 moved(0.0);
  for (int k = 0; k < 3; ++k)
    moved += bary[k] * physics::cornerShare(bary, k, move);
  EXPECT_NEAR(glm::distance(moved, move), 0.0, 1e-15);
}

TEST(CornerContact, ATriangleOverACornerGoesThicknessAboveIt) {
  // The box's corner (1, 1, 1), outward along (1, 1, 1); a triangle across it, 1 mm below it along that axis.
  const dvec3 v(1, 1, 1), nv = glm::normalize(dvec3(1, 1, 1));
  const dvec3 c = v - 0.001 * nv;
  const dvec3 u = glm::normalize(dvec3(1, -1, 0)), w = glm::cross(nv, u);
  const dvec3 p0 = c + 0.05 * u, p1 = c - 0.03 * u + 0.04 * w, p2 = c - 0.03 * u - 0.05 * w;
  dvec3 bary, move;
  ASSERT_TRUE(physics::cornerContact(p0, p1, p2, v, nv, 0.004, bary, move));
  EXPECT_NEAR(glm::distance(move, 0.005 * nv), 0.0, 1e-12);
  EXPECT_NEAR(bary.x + bary.y + bary.z, 1.0, 1e-12);
  EXPECT_NEAR(glm::distance(bary.x * p0 + bary.y * p1 + bary.z * p2, c), 0.0, 1e-12) << "the point over the corner";
  // Wound the other way: the same move.
  dvec3 bary2, move2;
  ASSERT_TRUE(physics::cornerContact(p0, p2, p1, v, nv, 0.004, bary2, move2));
  EXPECT_NEAR(glm::distance(move, move2), 0.0, 1e-12);
  // 5 mm above the corner, or the corner beside the triangle: nothing.
  EXPECT_FALSE(physics::cornerContact(p0 + 0.006 * nv, p1 + 0.006 * nv, p2 + 0.006 * nv, v, nv, 0.004, bary, move));
  EXPECT_FALSE(physics::cornerContact(p0 + 0.2 * u, p1 + 0.2 * u, p2 + 0.2 * u, v, nv, 0.004, bary, move));
}

// ---- features, grids, face adjacency ------------------------------------------------------------------

const MeshObstacle& boxDropBox(const Scene& s) {
  return *s.meshes.at(0).mesh;
}

TEST(MeshFeatures, ABoxHasTwelveEdgesAndEightCornersAndATableItsRim) {
  const Scene drop = loadScene(kScenes / "box_drop.json");
  const MeshFeatures box = findFeatures(boxDropBox(drop));
  EXPECT_EQ(box.edges.size(), 12u) << "the quads' diagonals are flat";
  EXPECT_EQ(box.corners.size(), 8u);
  for (const FeatureEdge& e : box.edges)
    EXPECT_NEAR(glm::dot(e.normal_a, e.normal_b), 0.0, 1e-9);
  for (const FeatureCorner& c : box.corners)  // outward: away from the box's centre
    EXPECT_GT(glm::dot(c.normal, c.p - dvec3(0.01, 0.075, -0.005)), 0.0);
  const Scene table = loadScene(kScenes / "tablecloth.json");
  const MeshFeatures rim = findFeatures(*table.meshes.at(0).mesh);
  EXPECT_GT(rim.edges.size(), 500u) << "the rounded rims' 22.5-degree steps";
  const Scene torus = loadScene(kScenes / "torus.json");
  EXPECT_EQ(findFeatures(*torus.meshes.at(0).mesh).edges.size(), 0u) << "13 degrees a step at most";
}

// The edges the grid's cell of p lists (none beyond the grid).
std::set<std::uint32_t> listedEdges(const FeatureGrid& g, dvec3 p) {
  const glm::ivec3 cell(glm::floor((p - g.origin) / g.cell));
  std::set<std::uint32_t> listed;
  if (glm::all(glm::greaterThanEqual(cell, glm::ivec3(0))) && glm::all(glm::lessThan(cell, g.dims)))
    for (std::uint32_t k = g.edge_start[g.index(cell)]; k < g.edge_start[g.index(cell) + 1]; ++k)
      listed.insert(g.edges[k]);
  return listed;
}

// How many (point, edge) pairs within reach were checked; fails where the point's cell misses such an edge.
int expectCellsListEdgesWithinReach(const MeshFeatures& f, const FeatureGrid& g, double reach,
                                    const std::vector<dvec3>& points) {
  int checked = 0;
  for (std::size_t n = 0; n < points.size(); ++n) {
    const dvec3 p = points[n];
    const std::set<std::uint32_t> listed = listedEdges(g, p);
    for (std::uint32_t e = 0; e < f.edges.size(); ++e) {
      const dvec3 a = f.edges[e].a, b = f.edges[e].b;
      const double along = std::clamp(glm::dot(p - a, b - a) / glm::dot(b - a, b - a), 0.0, 1.0);
      if (glm::distance(p, a + along * (b - a)) < reach) {
        EXPECT_TRUE(listed.count(e)) << "point " << n << ", edge " << e;
        ++checked;
      }
    }
  }
  return checked;
}

TEST(MeshFeatures, AGridCellListsEveryFeatureWithinReachOfAPointInIt) {
  const Scene table = loadScene(kScenes / "tablecloth.json");
  const MeshFeatures f = findFeatures(*table.meshes.at(0).mesh);
  const double reach = 0.05;
  const FeatureGrid g = buildFeatureGrid(f, reach);
  EXPECT_EQ(g.cell, reach);
  std::vector<dvec3> points;
  for (int n = 0; n < 400; ++n) {
    const dvec3 t(std::fmod(n * 0.618034, 1.0), std::fmod(n * 0.414214, 1.0), std::fmod(n * 0.732051, 1.0));
    points.push_back(dvec3(-0.1, 0.6, -0.1) + t * dvec3(2.2, 0.3, 1.8));  // around the table's top
  }
  EXPECT_GT(expectCellsListEdgesWithinReach(f, g, reach, points), 50);
}

// An obstacle kilometres across (or scaled past any scene's size by a hostile file: 1e28, whose cell count
// overflowed) gets cells wider than the reach, at most kMaxFeatureCells of them, and still lists every edge
// within reach of a point in a cell.
TEST(MeshFeatures, AGridOverAHugeObstacleKeepsItsCellCountAndItsLists) {
  const Scene table = loadScene(kScenes / "tablecloth.json");
  const MeshFeatures original = findFeatures(*table.meshes.at(0).mesh);
  for (double scale : {1e4, 1e28}) {
    SCOPED_TRACE(scale);
    MeshFeatures f = original;
    for (FeatureEdge& e : f.edges) {
      e.a *= scale;
      e.b *= scale;
    }
    for (FeatureCorner& c : f.corners)
      c.p *= scale;
    const double reach = 0.05;
    const FeatureGrid g = buildFeatureGrid(f, reach);
    EXPECT_GT(g.cell, reach);
    EXPECT_LE(double(g.dims.x) * g.dims.y * g.dims.z, kMaxFeatureCells);
    EXPECT_EQ(g.edge_start.size(), std::size_t(g.dims.x) * g.dims.y * g.dims.z + 1);
    std::vector<dvec3> points;  // beside every fifth edge, a third of the reach off it
    for (std::size_t e = 0; e < f.edges.size(); e += 5)
      points.push_back(glm::mix(f.edges[e].a, f.edges[e].b, 0.3) + dvec3(0.0, reach / 3, 0.0));
    EXPECT_GT(expectCellsListEdgesWithinReach(f, g, reach, points), 50);
  }
}

TEST(FaceAdjacency, AGridHasItsTrianglesEdgesOncePerPointAscending) {
  ClothSpec c;
  c.num_width_points = 5;
  c.num_height_points = 4;
  c.thickness = 0.01;
  const Topology topo = buildTopology(c);
  const FaceAdjacency f = buildFaceAdjacency(topo);
  // (W-1) H + W (H-1) sides and one diagonal per quad.
  EXPECT_EQ(f.edges.size() / 2, std::size_t(4 * 4 + 5 * 3 + 4 * 3));
  EXPECT_EQ(f.point_triangles.size(), topo.triangles.size());
  for (std::size_t i = 0; i + 1 < f.edge_start.size(); ++i) {
    EXPECT_TRUE(std::is_sorted(f.point_edges.begin() + f.edge_start[i], f.point_edges.begin() + f.edge_start[i + 1]));
    for (std::uint32_t k = f.edge_start[i]; k < f.edge_start[i + 1]; ++k) {
      const std::uint32_t e = f.point_edges[k];
      EXPECT_TRUE(f.edges[2 * e] == i || f.edges[2 * e + 1] == i);
    }
  }
  EXPECT_NEAR(f.longest_rest_edge, std::hypot(1.0 / 4, 1.0 / 3), 1e-12) << "a quad's diagonal";
}

// ---- the box drop -------------------------------------------------------------------------------------

struct Drop {
  std::string name;
  double height;  // m above the box's top
  int steps;
  Integrator integrator;
};

class BoxDrop : public ::testing::TestWithParam<Drop> {};

// The settings (tools/box-drop): from contact on, no cloth point more than 0.5 mm inside the exact box
// and no point of a cloth triangle more than the collision thickness (5 mm), every frame for 40 frames (every
// other one measured, triangles sampled 2 mm apart to keep it lean). The cloth starts `height` above the box
// as its OBJ places it 1 m above.
TEST_P(BoxDrop, NothingEndsInsideTheBox) {
  const Drop d = GetParam();
  Scene s = loadScene(kScenes / "box_drop.json");
  s.sim.steps_per_frame = d.steps;
  s.sim.integrator = d.integrator;
  CpuSolver<float> cpu(s, CpuSolverOptions{.threads = 1});
  std::vector<dvec3> x = cpu.topology().initial_positions, v(x.size(), dvec3(0));
  for (dvec3& p : x)
    p.y += d.height - 1.0;
  cpu.setState(x, v);
  const PenetrationGauge gauge(s, cpu.topology(), 2e-3);
  const double thickness = meshThickness(s.cloth, s.meshes[0]);
  int contact = -1, measured = 0;
  double worst_vertex = 0, worst_surface = 0;
  for (int f = 1; f <= 400 && (contact < 0 || f <= contact + 40); ++f) {
    cpu.stepFrame();
    const Positions now = cpu.readPositions();
    ASSERT_TRUE(allFinite(now)) << "frame " << f;
    if (contact < 0) {
      if (minY(now) > 0.2) continue;  // the box's top is at 0.15 m: not there yet
      if (gauge.measure(now).nearest > s.cloth.thickness) continue;
      contact = f;
    }
    if ((f - contact) % 2) continue;
    const Penetration p = gauge.measure(now);
    worst_vertex = std::max(worst_vertex, p.vertex);
    worst_surface = std::max(worst_surface, p.surface);
    ++measured;
    EXPECT_LE(p.vertex, 0.5e-3) << "frame " << f << ": point " << p.vertex_index;
    EXPECT_LE(p.surface, thickness) << "frame " << f << ": triangle " << p.surface_triangle;
  }
  ASSERT_GT(contact, 0) << "the cloth must reach the box";
  EXPECT_EQ(measured, 21);
  std::printf("[ %s ] contact at frame %d; deepest point %.3f mm, deepest triangle point %.3f mm\n", d.name.c_str(),
              contact, worst_vertex * 1e3, worst_surface * 1e3);
}

std::vector<Drop> drops() {
  std::vector<Drop> out;
  for (double h : {1.0, 2.0})
    for (int steps : {5, 10, 30})
      for (Integrator i : {Integrator::Verlet, Integrator::Xpbd, Integrator::Vbd}) {
        out.push_back({std::to_string(int(h)) + "m_" + std::to_string(steps) + "_" + integratorName(i), h, steps, i});
      }
  return out;
}

INSTANTIATE_TEST_SUITE_P(Settings, BoxDrop, ::testing::ValuesIn(drops()), [](const auto& p) { return p.param.name; });

// ---- collisions have the last word ----------------------------------------------------------------------

// CS184's sphere at 5 substeps, without friction (so that a point in contact sits on the surface, not on the
// chord from where it was): the stretch limit, after the collisions, drags points into the sphere; the last
// collision pass puts every one back on or outside it.
// The flag is pinned along its pole, a thickness from it: contacts at the pinned column could never resolve
// and, pushing the free points every substep, wrapped the whole flag around the pole within 14 frames (the
// centroid on the pole's axis, 40% strain). Skipped, the flag streams out in the wind as without the faces.
TEST(CollideFaces, APinnedClothStreamsFromItsPole) {
  const Scene s = loadScene(kScenes / "flag.json");
  CpuSolver<float> cpu(s, CpuSolverOptions{.threads = 1});
  ASSERT_FALSE(cpu.faceAdjacency().edges.empty());
  ASSERT_EQ(cpu.passes()[cpu.passes().size() - 2], "collide_faces");
  for (int k = 0; k < 30 * s.sim.steps_per_frame; ++k)
    cpu.step();
  const Positions x = cpu.readPositions();
  EXPECT_GT(centroid(x).x, 0.3) << "the flag wrapped around its pole (the pole's axis is at x = -0.03)";
  EXPECT_LT(maxStrain(cpu.topology(), s.cloth, x), 0.15);
}

TEST(CollideLast, NoPointEndsASubstepInsideTheSphere) {
  Scene s = loadScene(kScenes / "sphere.json");
  s.sim.steps_per_frame = 5;
  s.spheres[0].friction = 0.0;
  CpuSolver<float> cpu(s, CpuSolverOptions{.threads = 1});
  const glm::vec3 centre(s.spheres[0].origin);
  const float radius = float(s.spheres[0].radius);
  auto deepest = [&] {
    float worst = 0;
    for (const glm::vec3& p : cpu.positions())
      worst = std::max(worst, radius - glm::distance(p, centre));
    return worst;
  };
  int dragged_in = 0;
  for (int k = 0; k < 5 * 60; ++k) {
    cpu.accumulateForces();
    cpu.integrate();
    cpu.selfCollide();
    cpu.collide();
    cpu.limitStretch();
    dragged_in += deepest() > 1e-5f;
    cpu.collide();  // collide_last
    ASSERT_LE(deepest(), 1e-6f) << "substep " << k;
  }
  EXPECT_GT(dragged_in, 10) << "the stretch limit must drag points in for this to show anything";
  EXPECT_EQ(cpu.passes().back(), "collide_last");
}

// ---- self-collision skips what the springs hold ------------------------------------------------------------

Scene cs184File(const char* name) {
  Scene s = loadScene(kScenes / name);
  s.sim = SimParams{};  // the CS184 file: no "simulation" object, so self-collision on
  return s;
}

// CS184's 50 x 50 files are 20 mm between points, more than 2 x 9.5 mm: nothing is held, the bytes are
// those of colliding every pair.
TEST(HeldPairs, ChangeNothingOnTheCs184Files) {
  for (const char* name : {"pinned2.json", "pinned4.json", "sphere.json", "plane.json", "selfCollision.json"}) {
    const Scene s = cs184File(name);
    EXPECT_EQ(heldPairsAtRest(buildTopology(s.cloth).initial_positions, 2 * s.cloth.thickness).count, 0u) << name;
    CpuSolver<float> skip(s, CpuSolverOptions{.threads = 1}),
        all(s, CpuSolverOptions{.threads = 1, .skip_held_pairs = false});
    for (int f = 0; f < 20; ++f) {
      skip.stepFrame();
      all.stepFrame();
    }
    EXPECT_EQ(skip.readPositions(), all.readPositions()) << name;
    EXPECT_EQ(skip.readDisplacements(), all.readDisplacements()) << name;
  }
}

// pinned2 refined to 100 x 100 with CS184's thickness (10 mm apart against 19 mm of contact distance): every
// point starts "in contact" with its neighbours. No pair held at rest is listed, which shortens the list
// by the pairs within 19 mm at rest (what is left: the pairs 19 to 24 mm apart at rest, drawn closer by the
// folds between the pins).
TEST(HeldPairs, AFineClothListsNoPairTheSpringsHold) {
  auto run = [](int n, bool skip, double& entries) {
    Scene s = cs184File("pinned2.json");
    s.cloth.num_width_points = s.cloth.num_height_points = n;
    s.cloth.pinned = {{0, 0}, {n - 1, 0}};
    CpuSolver<float> cpu(s, CpuSolverOptions{.threads = 1, .skip_held_pairs = skip});
    entries = 0;
    for (int f = 0; f < 6; ++f) {
      cpu.stepFrame();
      entries = std::max(entries, double(cpu.collisionPairs().pairCount()) / double(cpu.positions().size()));
    }
    if (!skip) return;
    const float range = 2.0f * float(s.cloth.thickness);
    const std::vector<glm::dvec3>& rest = cpu.topology().initial_positions;
    for (std::size_t i = 0; i < rest.size(); ++i)
      for (const std::uint32_t* j = cpu.collisionPairs().begin(i); j != cpu.collisionPairs().end(i); ++j)
        ASSERT_FALSE(physics::heldAtRest(glm::vec3(rest[i]), glm::vec3(rest[*j]), range)) << i << " " << *j;
  };
  double coarse, fine, fine_all;
  run(50, true, coarse);
  run(100, true, fine);
  run(100, false, fine_all);
  std::printf("list entries a point: 50 x 50 %.2f; 100 x 100 %.2f, %.2f colliding every pair\n", coarse, fine,
              fine_all);
  EXPECT_LT(fine, 0.75 * fine_all) << "the held pairs are a large share of a fine cloth's candidates";
  const Scene fine_scene = [] {
    Scene s = cs184File("pinned2.json");
    s.cloth.num_width_points = s.cloth.num_height_points = 100;
    return s;
  }();
  const HeldPairs held =
      heldPairsAtRest(buildTopology(fine_scene.cloth).initial_positions, 2 * fine_scene.cloth.thickness);
  EXPECT_GT(held.count, 100u * 100u);
  EXPECT_NEAR(held.closest, 1.0 / 99, 1e-9);
}

// heldPairsAtRest against every pair tested: a fine cloth (the grid's dense cells, a hundred points a cell), a
// cloud spread wide (hashed buckets, whose cells share buckets) and a few points (runs of one), with exact counts.
TEST(HeldPairs, CountEveryPairCloserThanTheRange) {
  const auto brute = [](const std::vector<dvec3>& p, double range) {
    HeldPairs h;
    double closest2 = range * range;
    for (std::size_t i = 0; i < p.size(); ++i)
      for (std::size_t j = i + 1; j < p.size(); ++j) {
        const dvec3 d = p[i] - p[j];
        const double d2 = d.x * d.x + d.y * d.y + d.z * d.z;
        if (d2 < range * range) {
          ++h.count;
          closest2 = std::min(closest2, d2);
        }
      }
    h.closest = h.count ? std::sqrt(closest2) : 0.0;
    return h;
  };
  Scene fine = cs184File("pinned2.json");
  fine.cloth.num_width_points = 61;
  fine.cloth.num_height_points = 47;
  fine.cloth.orientation = Orientation::Vertical;  // the points' small offsets off the plane
  std::vector<dvec3> cloud;
  std::uint32_t seed = 12345;
  const auto next = [&seed] {
    seed = seed * 1664525u + 1013904223u;
    return double(seed >> 8) / double(1u << 24);
  };
  for (int i = 0; i < 3001; ++i)
    cloud.push_back(i % 3 == 0 ? dvec3(next(), next(), next()) * 40.0 : dvec3(next(), next(), next()) * 0.3);
  const std::vector<std::pair<std::vector<dvec3>, double>> cases = {
      {buildTopology(fine.cloth).initial_positions, 2 * fine.cloth.thickness * 3},
      {cloud, 0.02},
      {{dvec3(0), dvec3(0.01, 0, 0), dvec3(0, 0.03, 0)}, 0.02},
  };
  for (const auto& [points, range] : cases) {
    const HeldPairs want = brute(points, range), got = heldPairsAtRest(points, range);
    EXPECT_GT(want.count, 0u) << points.size();
    EXPECT_EQ(got.count, want.count) << points.size();
    EXPECT_EQ(got.closest, want.closest) << points.size();
  }
}

// `drape simulate --collide-held-pairs` (the command that shows the CS184 files' bytes unchanged): the factory
// hands it to the CPU solvers, whose result it changes where pairs are held, and refuses it for the GPU.
TEST(HeldPairs, TheFactoryCollidesThemWhenAsked) {
  Scene s = cs184File("pinned2.json");
  s.cloth.num_width_points = s.cloth.num_height_points = 12;
  s.cloth.pinned = {{0, 0}, {11, 0}};
  s.cloth.thickness = 0.06;  // 120 mm of contact distance, 91 mm between points
  SolverFactory factory;
  const std::unique_ptr<Solver> skip = factory.make(s, "cpu", {.threads = 1});
  const std::unique_ptr<Solver> all = factory.make(s, "cpu", {.threads = 1, .collide_held_pairs = true});
  for (int f = 0; f < 3; ++f) {
    skip->stepFrame();
    all->stepFrame();
  }
  EXPECT_NE(skip->readPositions(), all->readPositions());
  EXPECT_THROW(factory.make(s, "gpu", {.collide_held_pairs = true}), CommandError);
}

// `drape simulate --team always` (the figures of a forced team in docs/results/cpu_speed.md): every substep of a
// cloth far below the team's size on a team, the bytes of one thread; refused for the GPU.
TEST(TeamAlways, TheFactoryPutsEverySubstepOnTheTeam) {
  const Scene s = cs184File("pinned2.json");
  SolverFactory factory;
  const std::unique_ptr<Solver> one = factory.make(s, "cpu", {.threads = 1});
  const std::unique_ptr<Solver> team = factory.make(s, "cpu", {.threads = 2, .team_always = true});
  const std::unique_ptr<Solver> trial = factory.make(s, "cpu", {.threads = 2});
  for (int f = 0; f < 2; ++f) {
    one->stepFrame();
    team->stepFrame();
    trial->stepFrame();
  }
  const auto& cpu = dynamic_cast<const CpuSolver<float>&>(*team);
  EXPECT_EQ(cpu.teamSubsteps(), cpu.substeps());
  EXPECT_EQ(cpu.teamTrial(), nullptr) << "no trial decides";
  EXPECT_NE(dynamic_cast<const CpuSolver<float>&>(*trial).teamTrial(), nullptr) << "without it, a trial decides";
  EXPECT_EQ(one->readPositions(), team->readPositions());
  EXPECT_THROW(factory.make(s, "gpu", {.team_always = true}), CommandError);
}

}  // namespace
}  // namespace drape
