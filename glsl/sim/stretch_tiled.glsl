// The tiled Gauss-Seidel stretch limit (docs/design.md section 4, "The tiled stretch limit"), shared by
// limit_stretch_tiled.comp and limit_stretch_forces_tiled.comp. Each work group owns a TILE x TILE block
// of a grid cloth, copies the block and a ring of HALO points around it into shared memory, and runs the
// colours one after another there with a work-group barrier in between. A point's result after the
// colours depends on the points within a grid distance the solver works out from the colouring
// (gridColourReach in core/colouring.hpp), so every point at least that far inside the copy comes out
// exactly as the per-colour dispatches leave it; the others, which miss springs to points outside the
// copy, are wrong and must not be written. Same bits as CpuSolver::limitStretchColoured.
//
// The including kernel defines GROUP_SIZE, TILE and HALO and includes common.glsl and physics.glsl.
#pragma once

#define REGION (TILE + 2 * HALO)
#define REGION_POINTS (REGION * REGION)
#define PER_INVOCATION ((REGION_POINTS + GROUP_SIZE - 1) / GROUP_SIZE)

uniform uint u_colours;  // spring colours
uniform uint u_passes;   // SimParams::stretch_passes

#ifndef GRID_PARTNERS
#define GRID_PARTNERS 0
#endif
// Where every spring of a direction has the same rest length (a flat grid, GRID_PARTNERS), the partner and
// rest of a point's spring of colour c follow from the grid: nothing per point is read but the state.
// Otherwise they come from the ColourPartner table.
#include "grid_springs.glsl"
#if !GRID_PARTNERS
layout(std430, binding = kBindingColourPartners) readonly buffer ColourPartnersBuffer {
  ColourPartner colourPartners[];  // colour c, point i: colourPartners[c * point_count + i]
};
#endif

// 12 bytes a point, as one_group.comp: vec3[] may be padded to 16.
shared float sx[3 * REGION_POINTS];
shared uint sPinned[(REGION_POINTS + 31) / 32];

// The copy: the block clipped to the cloth, and the ring around it clipped too.
uvec2 tileLo, tileHi, copyLo, copyHi, copySize;
uint copyCount;

// Registers per point of the copy (point l = lid + k * GROUP_SIZE): its index in the cloth, whether it is
// a block point, its position's w (the pin flag), and for block points the displacement, which moves with
// the position (x_prev stays where it was).
uint global[PER_INVOCATION];
bool inside[PER_INVOCATION];
vec3 v[PER_INVOCATION];
float w[PER_INVOCATION];

vec3 loadX(uint l) {
  return vec3(sx[3u * l], sx[3u * l + 1u], sx[3u * l + 2u]);
}

void storeX(uint l, vec3 x) {
  sx[3u * l] = x.x;
  sx[3u * l + 1u] = x.y;
  sx[3u * l + 2u] = x.z;
}

bool pinnedAt(uint l) {
  return ((sPinned[l >> 5u] >> (l & 31u)) & 1u) != 0u;
}

// Where grid point `at`, inside the copy, lies in it.
uint copyIndex(uvec2 at) {
  return (at.y - copyLo.y) * copySize.x + (at.x - copyLo.x);
}

void syncGroup() {
  memoryBarrierShared();
  barrier();
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
    uint l = lid + k * uint(GROUP_SIZE);
    global[k] = 0u;
    inside[k] = false;
    v[k] = vec3(0.0);
    w[k] = 0.0;
    if (l >= copyCount) continue;
    uvec2 at = copyLo + uvec2(l % copySize.x, l / copySize.x);
    global[k] = gridIndex(ivec2(at));
    inside[k] = all(greaterThanEqual(at, tileLo)) && all(lessThan(at, tileHi));
    vec4 p = posIn[global[k]];
    storeX(l, p.xyz);
    w[k] = p.w;
    if (isPinned(p)) atomicOr(sPinned[l >> 5u], 1u << (l & 31u));
    if (inside[k]) v[k] = loadDisp(global[k]);
  }
  syncGroup();
}

// Every colour of every pass on the copy; ends with the group synchronised.
void limitStretchTile() {
  const uint lid = gl_LocalInvocationID.x;
  for (uint pass = 0u; pass < u_passes; ++pass) {
    for (uint c = 0u; c < u_colours; ++c) {
      vec3 corr[PER_INVOCATION];
      bool moves[PER_INVOCATION];
      for (uint k = 0u; k < PER_INVOCATION; ++k) {
        uint l = lid + k * uint(GROUP_SIZE);
        corr[k] = vec3(0.0);
        moves[k] = false;
        if (l >= copyCount || pinnedAt(l)) continue;
#if GRID_PARTNERS
        ivec2 other;
        bool i_is_b;
        if (!gridPartner(ivec2(copyLo + uvec2(l % copySize.x, l / copySize.x)), c, other, i_is_b))
          continue;  // untouched: x + 0 would turn -0 into +0
        uvec2 at = uvec2(other);
        float rest = u_rest[c / 2u];
#else
        ColourPartner p = colourPartners[c * params.point_count + global[k]];
        if (p.other == kNoPartner) continue;  // untouched: x + 0 would turn -0 into +0
        uvec2 at = uvec2(gridAt(p.other));
        bool i_is_b = global[k] > p.other;
        float rest = p.rest;
#endif
        // A partner outside the copy: this ring point's result is wrong and, by the choice of HALO,
        // reaches no point the kernel writes.
        if (any(lessThan(at, copyLo)) || any(greaterThanEqual(at, copyHi))) continue;
        uint j = copyIndex(at);
        corr[k] = stretchOneEnd(loadX(l), loadX(j), i_is_b, pinnedAt(j), rest, params.stretch_limit);
        moves[k] = true;
      }
      syncGroup();
      for (uint k = 0u; k < PER_INVOCATION; ++k) {
        if (!moves[k]) continue;
        uint l = lid + k * uint(GROUP_SIZE);
        precise vec3 x = loadX(l) + corr[k];
        storeX(l, x);
        precise vec3 vc = v[k] + corr[k];
        v[k] = vc;
      }
      syncGroup();
    }
  }
}
