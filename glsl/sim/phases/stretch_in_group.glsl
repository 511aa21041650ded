// The Gauss-Seidel stretch limit seen from the points, on a copy of the cloth in shared memory: every colour
// of every pass with a work-group barrier in between (the one-dispatch kernel: the whole cloth; the tiled
// kernels: a block and its ring). A spring colour gives each point at most one spring, so each point moves by
// exactly what limit_stretch_coloured.comp gives that end (stretchOneEnd), and the colours run in the CPU's
// order: the same bits. With no colours (the Jacobi scheme, one-dispatch path only) a pass is one round of
// stretchJacobiOf.
//
// The storage (storage/group.glsl or storage/tile.glsl) holds its slots (invocation lid works on the slots
// lid + k * GROUP_SIZE, k < PER_INVOCATION) and defines: loadX(s), pinnedAt(s), syncGroup(),
// slotMovable(s, k), slotPoint(s, k) (the cloth index), slotAt(s, k) (the grid position, with GRID_SPRINGS),
// slotOf(j, at_j, out s) (where cloth point j is, false if outside the copy) and moveSlot(s, k, c).
#pragma once

#include "stretch.glsl"
#ifndef GRID_SPRINGS
#define GRID_SPRINGS 0
#endif
#if GRID_SPRINGS
// A flat grid (every direction's springs one rest length): a point's spring of colour c follows from the
// grid, and nothing per point is read but the state.
#include "../grid_springs.glsl"
#else
layout(std430, binding = kBindingColourPartners) readonly buffer ColourPartnersBuffer {
  ColourPartner colourPartners[];  // colour c, point i: colourPartners[c * point_count + i]
};
#endif

// Point i's spring of colour c, if it has one: the other end j (at_j on the grid, GRID_SPRINGS only),
// whether i is the spring's end b (the larger index), and the rest length.
bool colourPartner(uint i, ivec2 at, uint c, out uint j, out ivec2 at_j, out bool i_is_b, out float rest) {
  j = kNoPartner;
  at_j = ivec2(0);
  i_is_b = false;
  rest = 0.0;
#if GRID_SPRINGS
  if (!gridPartner(at, c, at_j, i_is_b)) return false;
  j = gridIndex(at_j);
  rest = u_rest[c / 2u];
#else
  ColourPartner p = colourPartners[c * params.point_count + i];
  if (p.other == kNoPartner) return false;
  j = p.other;
  i_is_b = i > p.other;
  rest = p.rest;
#endif
  return true;
}

// Slot s's move in colour c; false where it has no spring of the colour, or (in a tile's ring) its partner
// lies outside the copy. Such a slot is not touched at all: x + 0 would turn -0 into +0.
bool stretchColourOf(uint s, uint k, uint c, out vec3 corr) {
  corr = vec3(0.0);
  uint j, sj;
  ivec2 at_j;
  bool i_is_b;
  float rest;
  if (!colourPartner(slotPoint(s, k), slotAt(s, k), c, j, at_j, i_is_b, rest)) return false;
  if (!slotOf(j, at_j, sj)) return false;
  corr = stretchOneEnd(loadX(s), loadX(sj), i_is_b, pinnedAt(sj), rest, params.stretch_limit);
  return true;
}

// Slot s's Jacobi correction; a storage without the adjacency (the tiled kernels, Gauss-Seidel only) has none.
bool stretchJacobiRoundOf(uint s, uint k, out vec3 corr) {
#ifdef SIM_NO_SPRINGS
  corr = vec3(0.0);
  return false;
#else
  corr = stretchJacobiOf(slotPoint(s, k), loadX(s));
  return true;
#endif
}

// `passes` passes; Gauss-Seidel colour after colour, or with colours == 0 one Jacobi round a pass. Every
// invocation calls it (it has barriers), and every loop before a barrier has the same trip count in all of
// them (docs/design.md section 8).
void stretchInGroup(uint passes, uint colours) {
  const uint lid = gl_LocalInvocationID.x;
  for (uint pass = 0u; pass < passes; ++pass) {
    uint rounds = max(colours, 1u);
    for (uint c = 0u; c < rounds; ++c) {
      vec3 corr[PER_INVOCATION];
      bool moves[PER_INVOCATION];
      for (uint k = 0u; k < PER_INVOCATION; ++k) {
        uint s = lid + k * uint(GROUP_SIZE);
        corr[k] = vec3(0.0);
        moves[k] = slotMovable(s, k);
        if (!moves[k]) continue;
        if (colours > 0u)
          moves[k] = stretchColourOf(s, k, c, corr[k]);
        else
          moves[k] = stretchJacobiRoundOf(s, k, corr[k]);
      }
      syncGroup();
      for (uint k = 0u; k < PER_INVOCATION; ++k)
        if (moves[k]) moveSlot(lid + k * uint(GROUP_SIZE), k, corr[k]);
      syncGroup();
    }
  }
}
