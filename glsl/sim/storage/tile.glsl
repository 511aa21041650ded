// The tiled path's storage (docs/design.md section 4, "The tiled stretch limit"), for
// limit_stretch_tiled.comp and limit_stretch_forces_tiled.comp: each work group owns a TILE x TILE block of a
// grid cloth and copies the block and a ring of HALO points around it (both clipped to the cloth) into
// shared memory: 12 bytes of position and a pin bit a point, as the one-dispatch path. A point's result after
// the stretch colours depends on the points within a grid distance the solver works out from the colouring
// (gridColourReach in core/colouring.hpp), so with the ring that wide every block point comes out exactly
// as the per-colour dispatches leave it; the ring's own results, which miss springs to points outside the
// copy, are wrong and are never written.
//
// A slot is a point's place in the copy, row by row; invocation lid owns the slots lid + k * GROUP_SIZE and
// keeps their cloth index, pin flag and (block points only) displacement in registers. Defines the accessors
// of the phases: gridNeighbour(at), and those of stretch_in_group.glsl. The including kernel defines
// GROUP_SIZE, TILE and HALO.
#pragma once

#include "../common.glsl"
#include "../grid_springs.glsl"

#define REGION (TILE + 2 * HALO)
#define REGION_POINTS (REGION * REGION)
#define PER_INVOCATION ((REGION_POINTS + GROUP_SIZE - 1) / GROUP_SIZE)

uniform uint u_colours;  // spring colours
uniform uint u_passes;   // SimParams::stretch_passes

#define SHARED_POINTS REGION_POINTS
#include "shared_positions.glsl"

// The copy: the block clipped to the cloth, and the ring around it clipped too.
uvec2 tileLo, tileHi, copyLo, copyHi, copySize;
uint copyCount;

// The rest of slot lid + k * GROUP_SIZE's registers: its index in the cloth, and whether it is a block point
// (only those are written, and only they keep their displacement).
uint slotGlobal[PER_INVOCATION];
bool slotInside[PER_INVOCATION];

// Where grid point `at`, inside the copy, lies in it.
uint copyIndex(uvec2 at) {
  return (at.y - copyLo.y) * copySize.x + (at.x - copyLo.x);
}

// Only for points within 2 of the block (the forces' reach), which the copy holds; the pin flag is not kept.
vec4 gridNeighbour(ivec2 at) {
  return vec4(loadX(copyIndex(uvec2(at))), 0.0);
}

bool slotMovable(uint s, uint k) {
  return s < copyCount && !pinnedAt(s);
}

uint slotPoint(uint s, uint k) {
  return slotGlobal[k];
}

ivec2 slotAt(uint s, uint k) {
  return ivec2(copyLo + uvec2(s % copySize.x, s / copySize.x));
}

// A partner outside the copy makes this ring point's result wrong; by the choice of HALO that reaches no
// point the kernel writes.
bool slotOf(uint j, ivec2 at_j, out uint s) {
#if !GRID_SPRINGS
  at_j = gridAt(j);
#endif
  uvec2 at = uvec2(at_j);
  s = 0u;
  if (any(lessThan(at, copyLo)) || any(greaterThanEqual(at, copyHi))) return false;
  s = copyIndex(at);
  return true;
}

// Copies this work group's block and ring from *In.
void loadTile() {
  const uint lid = gl_LocalInvocationID.x;
  tileLo = gl_WorkGroupID.xy * uint(TILE);
  tileHi = min(tileLo + uint(TILE), u_grid);
  copyLo = uvec2(max(ivec2(tileLo) - HALO, ivec2(0)));
  copyHi = min(tileHi + uint(HALO), u_grid);
  copySize = copyHi - copyLo;
  copyCount = copySize.x * copySize.y;
  if (lid < (REGION_POINTS + 31) / 32) sPinned[lid] = 0u;
  syncGroup();
  for (uint k = 0u; k < PER_INVOCATION; ++k) {
    uint s = lid + k * uint(GROUP_SIZE);
    slotGlobal[k] = 0u;
    slotInside[k] = false;
    slotV[k] = vec3(0.0);
    slotPin[k] = 0.0;
    if (s >= copyCount) continue;
    uvec2 at = copyLo + uvec2(s % copySize.x, s / copySize.x);
    slotGlobal[k] = gridIndex(ivec2(at));
    slotInside[k] = all(greaterThanEqual(at, tileLo)) && all(lessThan(at, tileHi));
    vec4 p = posIn[slotGlobal[k]];
    storeX(s, p.xyz);
    slotPin[k] = p.w;
    if (isPinned(p)) atomicOr(sPinned[s >> 5u], 1u << (s & 31u));
    if (slotInside[k]) slotV[k] = loadDisp(slotGlobal[k]);
  }
  syncGroup();
}
