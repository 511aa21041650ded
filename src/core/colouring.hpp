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

// Which of the grid's directions (kGridDirections, core/topology.hpp) a grid cloth's spring runs in.
int gridDirection(const Topology& topo, const Spring& s);

// A grid's springs by direction and parity: 12 colours, colour 2 * direction + the parity of the
// spring's start along it (of half of it for bending springs), each a set of parallel springs every other
// step (a change travels 10 points in a pass, gridColourReach). A mesh cloth's greedily in spring order (the
// smallest colour free at both ends). The same topology always gets the same colouring.
SpringColouring colourSprings(const Topology& topo);

// How far apart, in grid steps along x or y, a point of a grid cloth and a point its result depends on
// can be after `passes` Gauss-Seidel passes over `colouring`: each colour lets a point take on what its
// partner in that colour depended on, one spring further out.
// Springs whose type bit is clear in `type_mask` (bit t: SpringType t) are skipped, as disabled springs
// are. The tiled stretch kernel copies this many points around its block. Throws for a mesh cloth.
int gridColourReach(const Topology& topo, const SpringColouring& colouring, int passes, unsigned type_mask);

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
