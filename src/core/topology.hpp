// Cloth topology built once from a ClothSpec: initial positions, springs, the per-vertex CSR adjacency
// both solvers gather over, pin flags, and triangles/UVs for rendering. No GL here.
#pragma once

#include "core/cloth_mesh.hpp"
#include "core/scene.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace drape {

struct Spring {
  std::uint32_t a = 0, b = 0;  // point indices, a < b
  SpringType type = SpringType::Structural;
  double rest = 0.0;  // m, initial distance
};

// One entry of a point's adjacency: the spring to `other`, seen from this point.
struct Neighbor {
  std::uint32_t other = 0;
  std::uint32_t spring = 0;  // index into Topology::springs
  SpringType type = SpringType::Structural;
  double rest = 0.0;
};

// The one representation of a cloth both solvers run on, made by one of two generators: the grid
// (CS184's, from the grid keys) or a mesh (core/cloth_mesh.hpp).
struct Topology {
  int W = 0, H = 0;                           // the grid's size; 0 for a mesh cloth
  std::vector<glm::dvec3> initial_positions;  // a grid's point (x, y) is index y*W + x
  std::vector<std::uint8_t> pinned;           // 1 if the point never moves
  std::vector<Spring> springs;                // structural, then shearing, then bending (see buildTopology)
  // CSR adjacency: neighbours of point i are adjacency[offsets[i] .. offsets[i+1]), in a fixed order
  // (ascending spring index) so that force sums are the same on CPU and GPU.
  std::vector<std::uint32_t> offsets;
  std::vector<Neighbor> adjacency;
  std::vector<std::uint32_t> triangles;  // 3 indices each, counter-clockwise seen from +normal
  // The faces the triangles come from, for drawing (render/cloth_surface.hpp): the grid's cells and a mesh's
  // quads with their 4 corners in order around the face, the triangles wound as `triangles`, corner 3
  // kNoCorner; a mesh's larger polygons as their fan triangles. A quad's normal does not depend on which
  // diagonal `triangles` splits it along.
  std::vector<std::array<std::uint32_t, 4>> faces;
  std::vector<glm::vec2> uvs;  // grid: (x/(W-1), y/(H-1)); mesh: the file's or projected
  // Each point's share of the cloth's area (m^2); derived::pointMass and derived::dragArea follow it.
  std::vector<double> area;
  // The four points whose cross(x[1] - x[0], x[3] - x[2]) is a point's normal for wind: the grid's left,
  // right, down and up neighbours, clamped at the border.
  std::vector<std::array<std::uint32_t, 4>> normal_stencil;

  int pointCount() const { return int(initial_positions.size()); }
  std::size_t springCount(SpringType t) const;
};

// The six directions of a grid's springs, end b minus end a in (x, y), in the order buildTopology makes them:
// structural, shearing, bending, two of each (gridDirectionType). glsl/sim/limit_stretch_tiled.comp has the same
// table.
inline constexpr int kGridDirectionCount = 6;
inline constexpr int kGridDirections[kGridDirectionCount][2] = {{1, 0}, {0, 1}, {1, 1}, {-1, 1}, {2, 0}, {0, 2}};
inline constexpr SpringType gridDirectionType(int direction) {
  return SpringType(direction / 2);
}

Topology buildTopology(const ClothSpec& cloth);

// offsets and adjacency from topo.springs, for any cloth: each spring listed at both ends, in spring order. A grid's
// (buildTopology) come from its layout instead, in one pass, and are the same.
void buildAdjacency(Topology& topo);

// Deterministic offset in [-1e-3, 1e-3] for vertical cloths (seeded by the point index).
double verticalOffset(std::uint32_t index);

}  // namespace drape
