// Self-collision candidate lists on the GPU: the algorithm of src/cpu/collision_pairs.hpp (docs/design.md
// section 2, step 3). When some point has moved more than the safe travel from where it was at the last
// build (checkPairTravel, fused into integrate), the list is rebuilt from the current positions:
//   pairs_prepare     one invocation: turns the build's indirect dispatches on (or off: nothing to do)
//   pairs_grid_count  anchors the positions and counts them into the hash grid (grid.glsl), cell edge
//                     pair_reach, so the 27 cells around a point hold every point within pair_reach
//   grid_build        the grid's counting sort (or its five-dispatch form for many buckets)
//   pairs_count       each point counts its candidates: points closer than pair_reach
//   pairs_scan        prefix sum of the counts: where each point's list starts
//   pairs_fill        each point writes its candidates and sorts them ascending
// No read-back decides anything: the prepare kernel writes the indirect dispatch arguments. The counts
// go to gridCounts (free again once the grid's scan has read them).
#pragma once

#include "grid.glsl"
#include "pair_travel.glsl"
#include "rest.glsl"

layout(std430, binding = kBindingPairStart) buffer PairStartBuffer {
  uint pairStart[];
};
layout(std430, binding = kBindingPairList) buffer PairListBuffer {
  uint pairList[];
};

#ifndef PAIR_NO_ANCHOR
// The candidates of point i, the points within pair_reach of its anchor and not held at rest, in grid order (27 cells
// in z, y, x order, ascending within a cell), read from the grid's cell-ordered copies: a bucket is one contiguous
// range, and a copy's cell is worked out again from its anchor as the count did. Counts them; with `write`, also stores
// them from pairList[first] on, as far as the buffer's capacity allows.
uint gatherCandidates(uint i, bool write, uint first) {
  vec3 a = pairAnchor[i].xyz;
  ivec3 cell = cellOf(a, params.inv_pair_cell);  // gridCell(i), without the read
  uint found = 0u;
  for (int dz = -1; dz <= 1; ++dz) {
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        ivec3 n = cell + ivec3(dx, dy, dz);
        uint bucket = hashCell(n) & params.bucket_mask;
        uint last = gridStart[bucket + 1u];
        for (uint s = gridStart[bucket]; s < last; ++s) {
          GridEntry e = gridSorted[s];
          uint j = e.index;
          vec3 aj = entryPosition(e);
          if (j == i || cellOf(aj, params.inv_pair_cell) != n) continue;  // a bucket can hold other cells' points
          precise vec3 d = a - aj;
          if (dot3(d, d) >= params.pair_reach2 || heldPair(i, j)) continue;
          if (write && first + found < pairState.capacity) pairList[first + found] = j;
          ++found;
        }
      }
    }
  }
  return found;
}
#endif
