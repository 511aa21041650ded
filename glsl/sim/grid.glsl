// The hash grid the self-collision lists are built from (pairs.glsl): the same cells, buckets and
// per-bucket order as src/cpu/hash_grid.hpp (cell edge pair_reach), built by a counting sort whenever
// the lists are rebuilt:
//   count   (pairs_grid_count.comp) each point's cell and bucket; atomicAdd gives its arrival slot
//   scan    exclusive prefix sum of the bucket counts -> gridStart
//   scatter each point to gridStart[bucket] + arrival: grouped by bucket, in thread-timing order
//   rank    each point counts the smaller indices in its bucket and moves to that slot, so every bucket
//           lists ascending indices, whatever order the atomics ran in (the determinism the
//           self-collision sums need, and the CPU's order); the slot holds a copy of its anchor, so
//           a query reads a bucket's points as one contiguous range (GridEntry)
// Up to kScanBlock buckets, one work group does scan, scatter and rank in a single dispatch
// (grid_build.comp); beyond that they are separate dispatches (grid_scan.comp, grid_scatter.comp,
// grid_rank.comp).
#pragma once

#include "cells.glsl"
#include "common.glsl"
#include "physics.glsl"

// A kernel whose invocations read what others wrote in the same dispatch (grid_build.comp) defines
// GRID_MEMORY as coherent: barriers order such accesses only for coherent variables, others may be
// served from a cache. The other kernels leave the buffers cacheable.
#ifndef GRID_MEMORY
#define GRID_MEMORY
#endif
layout(std430, binding = kBindingGridPoints) GRID_MEMORY buffer GridPointsBuffer {
  GridPoint gridPoints[];
};
layout(std430, binding = kBindingGridCounts) GRID_MEMORY buffer GridCountsBuffer {
  uint gridCounts[];
};
layout(std430, binding = kBindingGridStart) GRID_MEMORY buffer GridStartBuffer {
  uint gridStart[];
};
layout(std430, binding = kBindingGridBlocks) GRID_MEMORY buffer GridBlocksBuffer {
  uint gridBlocks[];
};
layout(std430, binding = kBindingGridScatter) GRID_MEMORY buffer GridScatterBuffer {
  uint gridScatter[];
};
layout(std430, binding = kBindingGridSorted) GRID_MEMORY buffer GridSortedBuffer {
  GridEntry gridSorted[];
};

ivec3 gridCell(uint i) {
  GridPoint g = gridPoints[i];
  return ivec3(g.cell_x, g.cell_y, g.cell_z);
}

// The scan that follows reads and zeroes gridCounts, so counting starts from zero every substep.
void countIntoGrid(uint i, vec3 x) {
  ivec3 c = cellOf(x, params.inv_pair_cell);
  uint bucket = hashCell(c) & params.bucket_mask;
  uint arrival = atomicAdd(gridCounts[bucket], 1u);
  gridPoints[i] = GridPoint(c.x, c.y, c.z, bucket, arrival);
}

void scatterPoint(uint i) {
  GridPoint g = gridPoints[i];
  gridScatter[gridStart[g.bucket] + g.arrival] = i;
}

// O(bucket size) per point; buckets hold a handful of points (one bucket per point on average).
// `anchor`: the position the point was counted at.
void rankPoint(uint i, vec3 anchor) {
  uint bucket = gridPoints[i].bucket;
  uint first = gridStart[bucket], last = gridStart[bucket + 1u];
  uint rank = 0u;
  for (uint s = first; s < last; ++s)
    rank += gridScatter[s] < i ? 1u : 0u;
  gridSorted[first + rank] = GridEntry(anchor.x, anchor.y, anchor.z, i);
}

vec3 entryPosition(GridEntry e) {
  return vec3(e.x, e.y, e.z);
}
