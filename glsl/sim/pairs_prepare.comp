// Decides, on the GPU, whether this substep rebuilds the self-collision lists (pairs.glsl): the build's
// indirect dispatches get their full sizes when some point moved too far, zero work groups otherwise.
// Needs no springs, colliders or health flags (common.glsl: a storage block fewer each).
#define SIM_NO_SPRINGS
#define SIM_NO_COLLIDERS
#define SIM_NO_HEALTH
#include "common.glsl"
#include "pair_travel.glsl"

layout(local_size_x = 1) in;

void main() {
  bool rebuild = pairState.stale != 0u;
  for (uint k = 0u; k < 3u * kPairDispatchCount; ++k)
    pairDispatch.live[k] = rebuild ? pairDispatch.full[k] : 0u;
  if (rebuild) {
    pairState.stale = 0u;
    pairState.extent_bits = 0u;
    pairState.builds += 1u;
  }
}
