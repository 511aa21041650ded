// A colouring of the springs: springs of one colour share no point, so a Gauss-Seidel pass can treat
// every spring of a colour at once (one parallel loop, or one dispatch, per colour) and still update
// each point from the latest positions of its neighbours, as a sequential pass would.
#pragma once

#include "core/topology.hpp"

#include <cstdint>
#include <vector>

namespace drape {

struct SpringColouring {
  std::vector<std::uint32_t> springs;  // spring indices grouped by colour, ascending within a colour
  std::vector<std::uint32_t> start;    // colour c is springs[start[c] .. start[c+1])

  int colourCount() const { return start.empty() ? 0 : int(start.size()) - 1; }
};

// Greedy in spring order (the smallest colour free at both ends), so the same topology always gets the
// same colouring. A W x H grid's structural, shearing and bending springs take 12 colours this way.
SpringColouring colourSprings(const Topology& topo);

// A colouring of the points: points of one colour share no spring, so a per-point Gauss-Seidel pass
// (Vertex Block Descent) can move every point of a colour at once, each from its neighbours' latest
// positions, as a sequential pass would.
struct PointColouring {
  std::vector<std::uint32_t> points;  // point indices grouped by colour, ascending within a colour
  std::vector<std::uint32_t> start;   // colour c is points[start[c] .. start[c+1])

  int colourCount() const { return start.empty() ? 0 : int(start.size()) - 1; }
};

// Greedy in point order over every spring of the adjacency (the smallest colour no neighbour has), so the
// same topology always gets the same colouring. A grid with bending springs takes 7 colours this way.
PointColouring colourPoints(const Topology& topo);

}  // namespace drape
