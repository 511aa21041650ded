// Cells of a uniform grid and the 27-cell order of the self-collision sums, shared by the hash grid
// (grid.glsl, pairs.glsl) and the one-dispatch kernel's in-group grid (one_group.comp). Declares no buffers.
#pragma once

// HashGrid::cellOf: a product with the host-rounded reciprocal. GLSL allows a division 2.5 ulp of
// error, which would move points on a cell border to the neighbouring cell; a product is exact-rounded.
// Clamped to +-2^30 cells, NaN to cell 0, as on the CPU: GLSL leaves the conversion of a non-finite or
// out-of-range float undefined, and a blown-up cloth reaches this before the frame's health check.
int clampCell(float q) {
  const float kLimit = 1073741824.0;
  return isnan(q) ? 0 : int(clamp(q, -kLimit, kLimit));
}

ivec3 cellOf(vec3 p, float inv_cell_size) {
  precise vec3 q = floor(p * inv_cell_size);
  return ivec3(clampCell(q.x), clampCell(q.y), clampCell(q.z));
}

// Where j lies around i in the 27-cell query of a grid of cell edge 2 * thickness (0..26, z then y then
// x), or -1 outside it: the order in which a point's self-collision sum visits its terms
// (cellOrder in src/cpu/collision_pairs.hpp).
int cellOrder(ivec3 cell_i, ivec3 cell_j) {
  ivec3 d = cell_j - cell_i;
  if (any(lessThan(d, ivec3(-1))) || any(greaterThan(d, ivec3(1)))) return -1;
  return (d.z + 1) * 9 + (d.y + 1) * 3 + (d.x + 1);
}
