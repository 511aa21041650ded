// Long-range attachments (src/core/tethers.hpp), mirroring CpuSolver::tether: each free point moves back
// within stretch_limit times its rest distance of each of its anchors, slot after slot. In place: a point
// writes only itself and reads only pinned anchors, which this pass never moves.
#define STATE_IN_PLACE
#define SIM_NO_SPRINGS
#define SIM_NO_COLLIDERS
#define SIM_NO_HEALTH
#include "common.glsl"
#include "physics.glsl"

#ifndef TETHER_SLOTS
#define TETHER_SLOTS 1
#endif

layout(local_size_x = kLocalSize) in;

layout(std430, binding = kBindingTethers) readonly buffer TethersBuffer {
  Tether tethers[];
};

void main() {
  uint i = globalIndex();
  if (i >= params.point_count) return;
  vec4 position = posIn[i];
  if (isPinned(position)) return;
  precise vec3 x = position.xyz;
  precise vec3 v = loadDisp(i);
  for (uint s = 0u; s < uint(TETHER_SLOTS); ++s) {
    Tether t = tethers[i * uint(TETHER_SLOTS) + s];
    if (t.anchor == kNoTether) break;
    vec4 anchor = posIn[t.anchor];
    // A pin released in the viewer no longer anchors anything.
    if (!isPinned(anchor)) continue;
    precise vec3 c = tetherCorrection(x, anchor.xyz, t.rest, params.stretch_limit);
    x += c;
    v += c;  // x_prev stays where it was
  }
  posIn[i] = vec4(x, position.w);
  storeDispInPlace(i, v);
}
