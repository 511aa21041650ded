// Each point writes its candidates from pairStart[i] on and sorts them ascending, the CPU list's order
// (CollisionPairs::build); point 0 also records the build's total and safe travel.
// Needs no springs, colliders or health flags (common.glsl: a storage block fewer each).
#define SIM_NO_SPRINGS
#define SIM_NO_COLLIDERS
#define SIM_NO_HEALTH
#include "common.glsl"
#include "pairs.glsl"

layout(local_size_x = kLocalSize) in;

// CollisionPairs::safeTravel in float: half the margin, less 16 ulps of the largest coordinate.
float safeTravel(float margin, float extent) {
  const float kEpsilon = 1.1920929e-7;  // FLT_EPSILON
  precise float r = 0.5 * margin - 16.0 * kEpsilon * extent;
  return r;
}

void main() {
  uint i = globalIndex();
  if (i >= params.point_count) return;
  uint first = pairStart[i], last = pairStart[i + 1u];
  gatherCandidates(i, true, first);
  // Insertion sort: lists are short (tens), and only a build pays for it. A list the buffer could not
  // hold is left as it is: self_collide serves that point from the grid.
  if (last <= pairState.capacity) {
    for (uint s = first + 1u; s < last; ++s) {
      uint j = pairList[s];
      uint t = s;
      for (; t > first && pairList[t - 1u] > j; --t)
        pairList[t] = pairList[t - 1u];
      pairList[t] = j;
    }
  }
  if (i == 0u) {
    uint total = pairStart[params.point_count];
    pairState.total = total;
    if (total > pairState.capacity) pairState.overflow = 1u;
    float extent = max(params.pair_reach, uintBitsToFloat(pairState.extent_bits));
    precise float travel = safeTravel(params.pair_margin, extent + params.pair_margin);
    pairState.travel2 = travel > 0.0 ? travel * travel : -1.0;
  }
}
