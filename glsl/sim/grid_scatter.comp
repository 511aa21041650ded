// Each point to its bucket's range, at the slot its atomic arrival gave it (see grid.glsl).
// Needs no springs, colliders or health flags (common.glsl: a storage block fewer each).
#define SIM_NO_SPRINGS
#define SIM_NO_COLLIDERS
#define SIM_NO_HEALTH
#include "grid.glsl"

layout(local_size_x = kLocalSize) in;

void main() {
  uint i = globalIndex();
  if (i < params.point_count) scatterPoint(i);
}
