// Cloth topology built once from a ClothSpec: initial positions, springs, the per-vertex CSR adjacency
// both solvers gather over, pin flags, and triangles/UVs for rendering. No GL here.
#pragma once

#include "core/scene.hpp"

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

struct Topology {
  int W = 0, H = 0;
  std::vector<glm::dvec3> initial_positions;  // index y*W + x
  std::vector<std::uint8_t> pinned;           // 1 if the point never moves
  std::vector<Spring> springs;                // structural, then shearing, then bending (see buildTopology)
  // CSR adjacency: neighbours of point i are adjacency[offsets[i] .. offsets[i+1]), in a fixed order
  // (ascending spring index) so that force sums are the same on CPU and GPU.
  std::vector<std::uint32_t> offsets;
  std::vector<Neighbor> adjacency;
  std::vector<std::uint32_t> triangles;  // 3 indices each, counter-clockwise seen from +normal
  std::vector<glm::vec2> uvs;            // (x/(W-1), y/(H-1))

  int pointCount() const { return W * H; }
  std::size_t springCount(SpringType t) const;
};

Topology buildTopology(const ClothSpec& cloth);

// Deterministic offset in [-1e-3, 1e-3] for vertical cloths (seeded by the point index).
double verticalOffset(std::uint32_t index);

}  // namespace drape
