// The cloth's surface as drawn (render/cloth_surface.hpp), on the CPU reference the GPU pass is checked
// against (render_images_gl_test.cpp): flat at rest, a crease followed whichever diagonal it runs along, and
// normals that do not depend on how a quad is split.
#include "render/cloth_surface.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>

namespace drape {
namespace {

Topology grid(int w, int h) {
  ClothSpec cloth;
  cloth.num_width_points = w;
  cloth.num_height_points = h;
  return buildTopology(cloth);
}

std::vector<glm::vec4> positionsOf(const std::vector<glm::dvec3>& x) {
  std::vector<glm::vec4> out;
  for (const glm::dvec3& p : x)
    out.emplace_back(glm::vec3(p), 1.0f);
  return out;
}

TEST(ClothSurface, EachCellIsFourTrianglesAroundItsCentre) {
  const Topology topo = grid(4, 3);
  const SurfaceLayout layout = buildSurfaceLayout(topo);
  EXPECT_EQ(layout.points, 12u);
  EXPECT_EQ(layout.quads, 6u);
  EXPECT_EQ(layout.triangles.size(), 6u * 12u);
  EXPECT_EQ(layout.uvs.size(), 18u);
  for (std::uint32_t q = 0; q < layout.quads; ++q)
    for (int k = 0; k < 4; ++k)
      EXPECT_EQ(layout.triangles[12 * q + 3 * std::size_t(k) + 2], layout.points + q) << "the centre closes each";
  // Every cell corner lists the cell among its faces.
  for (std::uint32_t q = 0; q < layout.quads; ++q)
    for (int k = 0; k < 4; ++k) {
      const std::uint32_t p = layout.faces[q][k];
      const auto begin = layout.point_faces.begin() + layout.face_offsets[p];
      const auto end = layout.point_faces.begin() + layout.face_offsets[p + 1];
      EXPECT_NE(std::find(begin, end, q), end);
    }
}

TEST(ClothSurface, AFlatGridFacesUpWithTheTangentAlongU) {
  const Topology topo = grid(4, 3);
  const SurfaceLayout layout = buildSurfaceLayout(topo);
  std::vector<glm::vec4> normals, tangents, centres;
  computeSurface(layout, positionsOf(topo.initial_positions), normals, tangents, centres);
  ASSERT_EQ(normals.size(), layout.vertices());
  for (std::size_t i = 0; i < normals.size(); ++i) {
    EXPECT_NEAR(glm::distance(glm::vec3(normals[i]), glm::vec3(0, 1, 0)), 0.0f, 1e-6f) << i;
    EXPECT_NEAR(glm::distance(glm::vec3(tangents[i]), glm::vec3(1, 0, 0)), 0.0f, 1e-6f) << i;  // u grows along x
    // v grows along +z: bitangent = w * cross(N, T) = w * (0, 0, -1) must be +z.
    EXPECT_EQ(tangents[i].w, -1.0f) << i;
  }
  for (std::uint32_t q = 0; q < layout.quads; ++q) {
    const glm::uvec4 c = layout.faces[q];
    glm::vec3 mean(0.0f);
    for (int k = 0; k < 4; ++k)
      mean += 0.25f * glm::vec3(topo.initial_positions[c[k]]);
    EXPECT_LT(glm::distance(glm::vec3(centres[q]), mean), 1e-6f) << "a flat cell's centre is its middle";
  }
}

// A 2 x 2 cell folded along one of its diagonals by `degrees`: the corners off the crease drop, and come
// closer together, as a folded sheet's do.
std::vector<glm::vec4> foldedCell(const Topology& topo, bool along_split, float degrees) {
  std::vector<glm::vec4> x = positionsOf(topo.initial_positions);
  const glm::vec3 a(x[along_split ? 1 : 0]), b(x[along_split ? 2 : 3]);  // the crease's ends
  const glm::vec3 axis = glm::normalize(b - a);
  for (int i : along_split ? std::array<int, 2>{0, 3} : std::array<int, 2>{1, 2}) {
    const glm::vec3 p = glm::vec3(x[std::size_t(i)]) - a;
    const glm::vec3 along = glm::dot(p, axis) * axis, across = p - along;
    // Rotate the half across the crease down about it.
    const float angle = glm::radians(degrees) * (glm::dot(glm::cross(axis, across), glm::vec3(0, 1, 0)) > 0 ? -1 : 1);
    const glm::vec3 rotated = across * std::cos(angle) + glm::cross(axis, across) * std::sin(angle);
    x[std::size_t(i)] = glm::vec4(a + along + rotated, 1.0f);
  }
  return x;
}

// The zig-zags along folds came from drawing every cell split along the same diagonal: a crease along the
// other one became teeth. The centre now lies on the crease, whichever diagonal it is.
TEST(ClothSurface, TheCentreLiesOnTheCreaseAlongEitherDiagonal) {
  const Topology topo = grid(2, 2);  // points 0 (0,0), 1 (1,0), 2 (0,1), 3 (1,1); the cell's corners 0, 2, 3, 1
  const SurfaceLayout layout = buildSurfaceLayout(topo);
  ASSERT_EQ(layout.quads, 1u);
  for (bool along_split : {true, false}) {
    const std::vector<glm::vec4> x = foldedCell(topo, along_split, 60.0f);
    std::vector<glm::vec4> normals, tangents, centres;
    computeSurface(layout, x, normals, tangents, centres);
    const glm::vec3 crease_middle = 0.5f * (glm::vec3(x[along_split ? 1 : 0]) + glm::vec3(x[along_split ? 2 : 3]));
    EXPECT_LT(glm::distance(glm::vec3(centres[0]), crease_middle), 1e-5f)
        << (along_split ? "along" : "across") << " the triangles' split";
  }
}

// Nothing pops between frames: as a fold starts, the centre leaves the corners' average gradually.
TEST(ClothSurface, TheCentreMovesSmoothlyAsAFoldDeepens) {
  const Topology topo = grid(2, 2);
  const SurfaceLayout layout = buildSurfaceLayout(topo);
  glm::vec3 previous(0.5f, 1.0f, 0.5f);
  for (float degrees = 1.0f; degrees <= 60.0f; degrees += 1.0f) {
    std::vector<glm::vec4> normals, tangents, centres;
    computeSurface(layout, foldedCell(topo, false, degrees), normals, tangents, centres);
    EXPECT_LT(glm::distance(glm::vec3(centres[0]), previous), 0.02f) << degrees << " degrees";
    previous = glm::vec3(centres[0]);
  }
}

// A point's normal sums whole faces: a cell's normal is the cross product of its diagonals, the same
// whichever way the triangles split it, so both diagonal folds give mirror-image normals.
TEST(ClothSurface, NormalsDoNotDependOnTheSplit) {
  const Topology topo = grid(2, 2);
  const SurfaceLayout layout = buildSurfaceLayout(topo);
  std::vector<glm::vec4> n_along, n_across, t, c;
  computeSurface(layout, foldedCell(topo, true, 40.0f), n_along, t, c);
  computeSurface(layout, foldedCell(topo, false, 40.0f), n_across, t, c);
  // Mirror x -> 1 - x maps one fold onto the other and point i onto point i ^ 1.
  for (std::size_t i = 0; i < 4; ++i) {
    const glm::vec3 a(n_along[i]), b(n_across[i ^ 1u]);
    EXPECT_NEAR(a.x, -b.x, 1e-5f) << i;
    EXPECT_NEAR(a.y, b.y, 1e-5f) << i;
    EXPECT_NEAR(a.z, b.z, 1e-5f) << i;
  }
}

}  // namespace
}  // namespace drape
