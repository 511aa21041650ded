// Stable order within each bucket: a point's slot is the number of smaller indices in its bucket.
// Needs no springs, colliders or health flags (common.glsl: a storage block fewer each).
#define SIM_NO_SPRINGS
#define SIM_NO_COLLIDERS
#define SIM_NO_HEALTH
#include "grid.glsl"
#include "pair_travel.glsl"

layout(local_size_x = kLocalSize) in;

void main() {
  uint i = globalIndex();
  if (i < params.point_count) rankPoint(i, pairAnchor[i].xyz);
}
