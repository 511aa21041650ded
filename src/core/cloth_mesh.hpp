// A cloth made from a polygon mesh (scene key cloth.mesh): the mesh checked once on load, and what the
// solvers need from it beyond the vertices (springs, each vertex's area, the wind's normal stencil),
// derived once so that the scene loader, the stability bound and the GPU's size check see the same
// springs the topology will have. buildTopology turns it into the Topology both solvers run on, as it
// does a grid. The rules: docs/design.md section 2 ("Mesh cloth").
#pragma once

#include "core/obj_reader.hpp"
#include "core/scene.hpp"

#include <array>

namespace drape {

// Corner 3 of a triangle in ClothMesh::faces and Topology::faces.
inline constexpr std::uint32_t kNoCorner = 0xffffffffu;

struct MeshSpring {
  std::uint32_t a = 0, b = 0;  // a < b
  SpringType type = SpringType::Structural;
};

struct ClothMesh {
  std::vector<glm::dvec3> positions;  // m, as in the file
  std::vector<glm::vec2> uvs;         // the file's, else a projection on the two longest bounding-box axes
  bool uvs_from_file = false;
  std::vector<std::uint32_t> triangles;             // quads and larger faces split into a fan from their first corner
  std::vector<std::array<std::uint32_t, 4>> faces;  // Topology::faces: quads whole, the rest as `triangles`
  std::vector<MeshSpring> springs;                  // structural, then shearing, then bending
  std::vector<double> area;                         // m^2 per vertex: a third of each triangle it is a corner of
  // Wind needs a normal per point: cross(x[1] - x[0], x[3] - x[2]) over these four points, chosen at rest
  // among the vertex and its neighbours (the grid's stencil is its four neighbours).
  std::vector<std::array<std::uint32_t, 4>> normal_stencil;
  std::size_t quads = 0;
};

// Checks the mesh for what a cloth cannot be (a face of fewer than 3 corners or with a repeated corner, a
// zero-area triangle, an edge shared by more than two triangles, a vertex in no face) and derives the rest.
// Throws MeshError with the problem.
ClothMesh buildClothMesh(const PolygonMesh& mesh);

}  // namespace drape
