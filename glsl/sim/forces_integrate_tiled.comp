// forces_integrate.comp for a flat grid cloth (every direction's springs one rest length) on the tiled path:
// each work group copies a TILE x TILE block of positions and a ring of 2 points (the bending springs'
// reach) into shared memory, and each point gathers its springs from there by grid offset instead of the
// CSR adjacency (phases/integrate.glsl with GRID_SPRINGS): per point, 16 bytes of position read by the copy,
// not 12 adjacency entries and 12 neighbour positions. Same bits as forces_integrate.comp, and so as the CPU.
// No wind (its normals would need the ring and the per-point drag): the plan keeps forces_integrate.comp
// for such scenes.
//
// Reads *In and writes *Out, as forces_integrate.comp.
#include "common.glsl"
#ifndef GROUP_SIZE
#define GROUP_SIZE 256  // invocations; the solver sets it and TILE
#endif
#ifndef TILE
#define TILE 44  // block edge, points
#endif
#define RING 2
#define REGION (TILE + 2 * RING)
#define REGION_POINTS (REGION * REGION)
#define GRID_SPRINGS 1

// The copy, positions only: point `at` of the cloth is at (at - copyOrigin) in the region.
#define SHARED_POINTS REGION_POINTS
#define SHARED_NO_PINS
#include "storage/shared_positions.glsl"
ivec2 copyOrigin;

vec4 gridNeighbour(ivec2 at) {
  return vec4(loadX(uint((at.y - copyOrigin.y) * REGION + (at.x - copyOrigin.x))), 0.0);
}

#include "phases/integrate.glsl"
#ifndef TRAVEL_CHECK
#define TRAVEL_CHECK 0
#endif
#if TRAVEL_CHECK
#include "pair_travel.glsl"
#endif

layout(local_size_x = GROUP_SIZE) in;

void main() {
  const uint lid = gl_LocalInvocationID.x;
  const ivec2 grid = ivec2(u_grid);
  const ivec2 tile_lo = ivec2(gl_WorkGroupID.xy) * TILE;
  copyOrigin = tile_lo - RING;  // points outside the cloth are never read
  for (uint l = lid; l < uint(REGION_POINTS); l += uint(GROUP_SIZE)) {
    ivec2 at = copyOrigin + ivec2(int(l) % REGION, int(l) / REGION);
    if (any(lessThan(at, ivec2(0))) || any(greaterThanEqual(at, grid))) continue;
    storeX(l, posIn[at.y * grid.x + at.x].xyz);
  }
  syncGroup();

  for (uint b = lid; b < uint(TILE * TILE); b += uint(GROUP_SIZE)) {
    ivec2 at = tile_lo + ivec2(int(b) % TILE, int(b) / TILE);
    if (any(greaterThanEqual(at, grid))) continue;
    uint i = uint(at.y * grid.x + at.x);
    vec3 x = gridNeighbour(at).xyz;
    // The position's w was read with the copy: the same bytes, not counted twice (the traffic model).
    float pin = posIn[i].w;
    vec3 v = loadDisp(i);
    integratePoint(i, at, x, v, pin, params.weight);
#if TRAVEL_CHECK
    checkPairTravel(i, x);
#endif
    posOut[i] = vec4(x, pin);
    storeDisp(i, v);
  }
}
