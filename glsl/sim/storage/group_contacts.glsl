// The one-dispatch kernel's way to a point's self-collision terms (phases/contacts.glsl): a grid of cell edge
// 2 * thickness, rebuilt every substep in shared memory, instead of the general path's candidate lists.
// Bucket b holds sGridPoints[sGridStart[b] .. sGridStart[b + 1]) in arrival order (atomics: any order; the
// sum picks its terms in ascending index within a cell, so the order never shows).
#pragma once

#include "../cells.glsl"
#ifndef GROUP_BUCKETS
#define GROUP_BUCKETS 128  // the in-group grid's buckets: a power of two, at most GROUP_SIZE
#endif

shared uint sGridStart[GROUP_BUCKETS + 1];
shared uint sGridPoints[GROUP_POINTS];

ivec3 orderCell(vec3 p) {
  return cellOf(p, params.inv_cell_size);
}

uint bucketOf(ivec3 cell) {
  return hashCell(cell) & uint(GROUP_BUCKETS - 1);
}

// Counting sort of the points into the buckets of their cells: counts by shared atomics, an inclusive
// scan (Hillis-Steele: log2(GROUP_BUCKETS) rounds, one bucket per invocation), then each point to its
// slot. Every invocation calls it (it has barriers).
void buildGroupGrid() {
  const uint lid = gl_LocalInvocationID.x;
  uint bucket[PER_INVOCATION], slot[PER_INVOCATION];
  if (lid <= GROUP_BUCKETS) sGridStart[lid] = 0u;
  syncGroup();
  for (uint k = 0u; k < PER_INVOCATION; ++k) {
    uint i = lid + k * GROUP_SIZE;
    if (i >= GROUP_POINTS) continue;
    bucket[k] = bucketOf(orderCell(loadX(i)));
    slot[k] = atomicAdd(sGridStart[bucket[k]], 1u);
  }
  syncGroup();
  uint count = lid < GROUP_BUCKETS ? sGridStart[lid] : 0u;
  uint sum = count;
  for (uint offset = 1u; offset < GROUP_BUCKETS; offset <<= 1u) {
    uint before = lid < GROUP_BUCKETS && lid >= offset ? sGridStart[lid - offset] : 0u;
    syncGroup();
    sum += before;
    if (lid < GROUP_BUCKETS) sGridStart[lid] = sum;
    syncGroup();
  }
  if (lid < GROUP_BUCKETS) sGridStart[lid] = sum - count;  // exclusive
  if (lid == 0u) sGridStart[GROUP_BUCKETS] = GROUP_POINTS;
  syncGroup();
  for (uint k = 0u; k < PER_INVOCATION; ++k) {
    uint i = lid + k * GROUP_SIZE;
    if (i < GROUP_POINTS) sGridPoints[sGridStart[bucket[k]] + slot[k]] = i;
  }
  syncGroup();
}

// The smallest index above `after` (any when after < 0) of a point in cell n, other than i, with a
// nonzero term; -1 if none. Buckets hold a few points, so the repeated scans cost little.
int nextInCell(uint i, vec3 x, ivec3 n, int after) {
  uint bucket = bucketOf(n);
  int best = -1;
  for (uint s = sGridStart[bucket]; s < sGridStart[bucket + 1u]; ++s) {
    uint j = sGridPoints[s];
    if (j == i || int(j) <= after || (best >= 0 && int(j) >= best)) continue;
    vec3 xj = loadX(j);
    if (orderCell(xj) != n || selfCollisionCorrection(x, xj, params.thickness) == vec3(0.0)) continue;
    best = int(j);
  }
  return best;
}

// Point i's nonzero terms in the order of the 27-cell query, ascending index within a cell
// (forEachOrderedPair in src/cpu/collision_pairs.hpp), summed, and how many there are.
void sumContactsInGroup(uint i, out vec3 sum_out, out int count) {
  precise vec3 x = loadX(i);
  ivec3 cell_i = orderCell(x);
  precise vec3 sum = vec3(0.0);
  count = 0;
  for (int order = 0; order < 27; ++order) {
    ivec3 n = cell_i + ivec3(order % 3 - 1, (order / 3) % 3 - 1, order / 9 - 1);
    for (int j = nextInCell(i, x, n, -1); j >= 0; j = nextInCell(i, x, n, j)) {
      sum += selfCollisionCorrection(x, loadX(uint(j)), params.thickness);
      ++count;
    }
  }
  sum_out = sum;
}
