// A flat grid cloth's springs found from the grid instead of read from the adjacency or the ColourPartner
// table, where every spring of a direction has one rest length (gpu::uniformGridRests, src/gpu/path_choice.cpp). The
// six directions are kGridDirections of src/core/topology.hpp, in the order topology.cpp makes them; a spring of
// direction d runs from `start` to start + kDirections[d], and colourGridSprings gives it colour 2 * d + its parity
// along d. The solver sets u_grid and u_rest.
#pragma once

uniform uvec2 u_grid;     // the cloth's points along x (W) and y (H); point (x, y) is y * W + x
uniform float u_rest[6];  // per direction: the rest length, 0 where its springs are disabled

const ivec2 kDirections[6] = ivec2[6](ivec2(1, 0), ivec2(0, 1), ivec2(1, 1), ivec2(-1, 1), ivec2(2, 0), ivec2(0, 2));

bool inGrid(ivec2 at) {
  return all(greaterThanEqual(at, ivec2(0))) && all(lessThan(at, ivec2(u_grid)));
}

ivec2 gridAt(uint i) {
  return ivec2(int(i % u_grid.x), int(i / u_grid.x));
}

uint gridIndex(ivec2 at) {
  return uint(at.y) * u_grid.x + uint(at.x);
}

// The parity colourGridSprings gives a spring of direction d starting at `start` (in the grid).
uint springParity(ivec2 start, int d) {
  int along = kDirections[d].y == 0 ? start.x : start.y;
  return uint((d >= 4 ? along / 2 : along) % 2);
}

// The point's spring of colour c, if it has one (and the direction is enabled): the other end, and whether
// the point is the spring's end b (the later one, where the spring ends).
bool gridPartner(ivec2 here, uint c, out ivec2 other, out bool i_is_b) {
  int d = int(c / 2u);
  other = here;
  i_is_b = false;
  if (u_rest[d] == 0.0) return false;
  ivec2 ahead = here + kDirections[d], behind = here - kDirections[d];
  if (inGrid(ahead) && springParity(here, d) == c % 2u) {
    other = ahead;
    return true;
  }
  if (inGrid(behind) && springParity(behind, d) == c % 2u) {
    other = behind;
    i_is_b = true;
    return true;
  }
  return false;
}
