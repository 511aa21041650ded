// The self-collision lists' per-point kernels (pairs_check, pairs_grid_count, grid_scatter, grid_rank,
// pairs_count): they need no springs, colliders or health flags (common.glsl: a storage block fewer each),
// and their main() hands each point's index to the kernel's eachIndex. A kernel includes this first and
// defines eachIndex below its other includes.
#pragma once

#define SIM_NO_SPRINGS
#define SIM_NO_COLLIDERS
#define SIM_NO_HEALTH
#include "common.glsl"

layout(local_size_x = kLocalSize) in;

void eachIndex(uint i);

void main() {
  uint i = globalIndex();
  if (i < params.point_count) eachIndex(i);
}
