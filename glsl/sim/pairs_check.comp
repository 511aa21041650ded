// The travel check on its own, for a state uploaded from the host (tests); in a normal substep it is
// fused into forces_integrate.comp.
// Needs no springs, colliders or health flags (common.glsl: a storage block fewer each).
#define SIM_NO_SPRINGS
#define SIM_NO_COLLIDERS
#define SIM_NO_HEALTH
#include "common.glsl"
#include "pair_travel.glsl"

layout(local_size_x = kLocalSize) in;

void main() {
  uint i = globalIndex();
  if (i < params.point_count) checkPairTravel(i, posIn[i].xyz);
}
