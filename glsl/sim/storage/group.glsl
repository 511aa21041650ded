// The one-dispatch path's storage (docs/design.md section 4, "The one-dispatch path"): the whole cloth in one
// work group. The positions live in shared memory (`sx`, 12 bytes a point, and a pin bit), which every
// invocation reads; each invocation owns the slots lid, lid + GROUP_SIZE, ... and keeps their displacements,
// pin flags and weights in registers for the whole frame. A slot is the point's index in the cloth.
//
// Defines the accessors of the phases (glsl/sim/phases): neighbour(j), gridNeighbour(at) (GRID_SPRINGS), and
// those of stretch_in_group.glsl.
#pragma once

#include "../common.glsl"
#include "../point_mass.glsl"
#ifndef GROUP_SIZE
#define GROUP_SIZE 128  // invocations; the solver sets it (and GROUP_POINTS) per cloth
#endif
#ifndef GROUP_POINTS
#define GROUP_POINTS 256  // the cloth's points
#endif
#define PER_INVOCATION ((GROUP_POINTS + GROUP_SIZE - 1) / GROUP_SIZE)
#ifndef GRID_SPRINGS
#define GRID_SPRINGS 0
#endif
#if GRID_SPRINGS
#include "../grid_springs.glsl"
#endif

#define SHARED_POINTS GROUP_POINTS
#include "shared_positions.glsl"

// The rest of slot lid + k * GROUP_SIZE's registers: PointMass::weight.
vec4 slotWeight[PER_INVOCATION];

vec4 neighbour(uint j) {
  return vec4(loadX(j), pinnedAt(j) ? 1.0 : 0.0);
}

#if GRID_SPRINGS
vec4 gridNeighbour(ivec2 at) {
  return neighbour(gridIndex(at));
}
#endif

bool slotMovable(uint s, uint k) {
  return s < GROUP_POINTS && slotPin[k] == 0.0;
}

uint slotPoint(uint s, uint k) {
  return s;
}

ivec2 slotAt(uint s, uint k) {
#if GRID_SPRINGS
  return gridAt(s);
#else
  return ivec2(0);
#endif
}

bool slotOf(uint j, ivec2 at_j, out uint s) {
  s = j;
  return true;
}

// The state from device memory into the group: positions and pin bits to shared memory, the rest to registers.
void loadGroup() {
  const uint lid = gl_LocalInvocationID.x;
  for (uint k = 0u; k < PER_INVOCATION; ++k) {
    uint s = lid + k * GROUP_SIZE;
    slotV[k] = vec3(0.0);
    slotPin[k] = 0.0;
    slotWeight[k] = vec4(0.0);
    if (s >= GROUP_POINTS) continue;
    vec4 position = posIn[s];
    storeX(s, position.xyz);
    slotV[k] = loadDisp(s);
    slotPin[k] = position.w;
    slotWeight[k] = pointWeight(s);
  }
  for (uint w = lid; w < (GROUP_POINTS + 31) / 32; w += GROUP_SIZE) {
    uint bits = 0u;
    for (uint b = 0u; b < 32u && w * 32u + b < GROUP_POINTS; ++b)
      bits |= (isPinned(posIn[w * 32u + b]) ? 1u : 0u) << b;
    sPinned[w] = bits;
  }
  syncGroup();
}
