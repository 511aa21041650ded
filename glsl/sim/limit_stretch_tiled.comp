// Provot (1995) stretch limit, Gauss-Seidel over the spring colouring, every colour and stretch pass of a
// substep in one dispatch (docs/design.md section 4, "The tiled stretch limit"). limit_stretch_coloured.comp
// needs a dispatch, and a storage barrier, per colour: 12 a pass on a grid. Here each work group owns a
// TILE x TILE block of a grid cloth, copies the block and a ring of HALO points around it into shared
// memory, runs the colours one after another there with a work-group barrier in between, and writes only
// its block. A point's result after the colours depends on the points within a grid distance the solver
// works out from the colouring (gridColourReach in core/colouring.hpp) and passes as HALO, so every block
// point comes out exactly as the per-colour dispatches leave it; the ring's own results, which miss
// springs to points outside the copy, are thrown away. Same bits as CpuSolver::limitStretchColoured.
//
// Reads *In and writes *Out: the ring of one block is another block's interior, which that block writes.
#define SIM_NO_SPRINGS
#define SIM_NO_COLLIDERS
#define SIM_NO_HEALTH
#include "common.glsl"
#include "physics.glsl"

#ifndef GROUP_SIZE
#define GROUP_SIZE 256  // invocations; the solver sets it (and TILE, HALO) per cloth
#endif
#ifndef TILE
#define TILE 31  // block edge, points
#endif
#ifndef HALO
#define HALO 10  // ring width, points
#endif
#define REGION (TILE + 2 * HALO)
#define REGION_POINTS (REGION * REGION)
#define PER_INVOCATION ((REGION_POINTS + GROUP_SIZE - 1) / GROUP_SIZE)

layout(local_size_x = GROUP_SIZE) in;

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

void syncGroup() {
  memoryBarrierShared();
  barrier();
}

void main() {
  const uint lid = gl_LocalInvocationID.x;
  const uvec2 tile_lo = gl_WorkGroupID.xy * uint(TILE);
  const uvec2 tile_hi = min(tile_lo + uint(TILE), u_grid);
  const uvec2 lo = uvec2(max(ivec2(tile_lo) - HALO, ivec2(0)));
  const uvec2 hi = min(tile_hi + uint(HALO), u_grid);
  const uvec2 size = hi - lo;
  const uint count = size.x * size.y;

  // Registers per point of the copy: its index in the cloth, its w lanes, and for block points the
  // displacement, which moves with the position (x_prev stays where it was).
  uint global[PER_INVOCATION];
  bool inside[PER_INVOCATION];
  vec3 v[PER_INVOCATION];
  vec2 w[PER_INVOCATION];  // x: position's w, y: displacement's w (the pin flag, both)
  if (lid < (REGION_POINTS + 31) / 32) sPinned[lid] = 0u;
  syncGroup();
  for (uint k = 0u; k < PER_INVOCATION; ++k) {
    uint l = lid + k * uint(GROUP_SIZE);
    global[k] = 0u;
    inside[k] = false;
    v[k] = vec3(0.0);
    w[k] = vec2(0.0);
    if (l >= count) continue;
    uvec2 at = lo + uvec2(l % size.x, l / size.x);
    global[k] = gridIndex(ivec2(at));
    inside[k] = all(greaterThanEqual(at, tile_lo)) && all(lessThan(at, tile_hi));
    vec4 p = posIn[global[k]];
    storeX(l, p.xyz);
    w[k].x = p.w;
    if (isPinned(p)) atomicOr(sPinned[l >> 5u], 1u << (l & 31u));
    if (inside[k]) {
      vec4 d = dispIn[global[k]];
      v[k] = d.xyz;
      w[k].y = d.w;
    }
  }
  syncGroup();

  for (uint pass = 0u; pass < u_passes; ++pass) {
    for (uint c = 0u; c < u_colours; ++c) {
      vec3 corr[PER_INVOCATION];
      bool moves[PER_INVOCATION];
      for (uint k = 0u; k < PER_INVOCATION; ++k) {
        uint l = lid + k * uint(GROUP_SIZE);
        corr[k] = vec3(0.0);
        moves[k] = false;
        if (l >= count || pinnedAt(l)) continue;
#if GRID_PARTNERS
        ivec2 other;
        bool i_is_b;
        if (!gridPartner(ivec2(lo + uvec2(l % size.x, l / size.x)), c, other, i_is_b))
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
        // reaches no block point.
        if (any(lessThan(at, lo)) || any(greaterThanEqual(at, hi))) continue;
        uint j = (at.y - lo.y) * size.x + (at.x - lo.x);
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

  for (uint k = 0u; k < PER_INVOCATION; ++k) {
    if (!inside[k]) continue;
    uint l = lid + k * uint(GROUP_SIZE);
    posOut[global[k]] = vec4(loadX(l), w[k].x);
    dispOut[global[k]] = vec4(v[k], w[k].y);
  }
}
