// Long-range attachments (src/core/tethers.hpp, docs/design.md section 2, step 5), mirroring
// CpuSolver::tether: a free point moves back within stretch_limit times its rest distance of each of its
// anchors, slot after slot, nearest first. A point moves only itself and reads only pinned anchors, which
// this phase never moves, so it runs in place. Reads the anchors through the storage's neighbour(j).
#pragma once

#include "../common.glsl"
#include "../physics.glsl"
#ifndef TETHER_SLOTS
#define TETHER_SLOTS 1  // anchors a point; the solver sets it from the scene's tethers
#endif

layout(std430, binding = kBindingTethers) readonly buffer TethersBuffer {
  Tether tethers[];  // point i, slot s: tethers[i * TETHER_SLOTS + s]
};

void tetherPoint(uint i, inout vec3 x_io, inout vec3 v_io) {
  precise vec3 x = x_io;
  precise vec3 v = v_io;
  for (uint s = 0u; s < uint(TETHER_SLOTS); ++s) {
    Tether t = tethers[i * uint(TETHER_SLOTS) + s];
    if (t.anchor == kNoTether) break;
    vec4 anchor = neighbour(t.anchor);
    // A pin released in the viewer no longer anchors anything.
    if (!isPinned(anchor)) continue;
    precise vec3 c = tetherCorrection(x, anchor.xyz, t.rest, params.stretch_limit);
    x += c;
    v += c;  // x_prev stays where it was
  }
  x_io = x;
  v_io = v;
}
