// How a mesh obstacle is drawn (render/mesh_data.hpp): hard edges stay hard, soft ones smooth. No GL.
#include "render/mesh_data.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace drape {
namespace {

// A unit cube's six sides, two triangles each, wound outward.
void cube(std::vector<glm::dvec3>& x, std::vector<std::uint32_t>& triangles) {
  x.clear();
  for (int corner = 0; corner < 8; ++corner)
    x.emplace_back(corner & 1, (corner >> 1) & 1, (corner >> 2) & 1);
  const std::uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                     {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  triangles.clear();
  for (const auto& q : quads)
    triangles.insert(triangles.end(), {q[0], q[1], q[2], q[0], q[2], q[3]});
}

TEST(ObstacleMesh, ABoxKeepsItsFlatSidesAndHardEdges) {
  std::vector<glm::dvec3> x;
  std::vector<std::uint32_t> triangles;
  cube(x, triangles);
  const MeshData mesh = buildObstacleMesh(x, triangles);
  EXPECT_EQ(mesh.vertexCount(), 24u) << "each corner drawn once per side it is on";
  ASSERT_EQ(mesh.triangles.size(), triangles.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); t += 3) {
    const glm::vec3 a(mesh.positions[mesh.triangles[t]]), b(mesh.positions[mesh.triangles[t + 1]]),
        c(mesh.positions[mesh.triangles[t + 2]]);
    const glm::vec3 face = glm::normalize(glm::cross(b - a, c - a));
    EXPECT_GT(glm::dot(face, glm::vec3(a) - glm::vec3(0.5f)), 0.0f) << "wound outward";
    for (int k = 0; k < 3; ++k)
      EXPECT_GT(glm::dot(glm::vec3(mesh.normals[mesh.triangles[t + std::size_t(k)]]), face), 0.9999f)
          << "triangle " << t / 3 << " corner " << k << ": the side's own normal";
  }
}

TEST(ObstacleMesh, AGentleBendStaysSmooth) {
  // A strip bent by 20 degrees at its middle: one drawn vertex per point, the middle ones between the sides.
  const double bend = 20.0 * 3.14159265358979 / 180.0;
  const std::vector<glm::dvec3> x = {{0, 0, 0},
                                     {0, 0, 1},
                                     {1, 0, 0},
                                     {1, 0, 1},
                                     {1 + std::cos(bend), std::sin(bend), 0},
                                     {1 + std::cos(bend), std::sin(bend), 1}};
  const std::vector<std::uint32_t> triangles = {0, 1, 2, 2, 1, 3, 2, 3, 4, 4, 3, 5};
  const MeshData mesh = buildObstacleMesh(x, triangles);
  EXPECT_EQ(mesh.vertexCount(), x.size());
  const glm::vec3 middle(mesh.normals[mesh.triangles[2]]);  // point 2, on the bend
  const double angle = std::acos(std::clamp(double(glm::dot(middle, glm::vec3(0, 1, 0))), -1.0, 1.0));
  EXPECT_GT(angle, 0.1 * bend) << "leans towards the bent side";
  EXPECT_LT(angle, 0.9 * bend) << "and towards the flat one";
}

}  // namespace
}  // namespace drape
