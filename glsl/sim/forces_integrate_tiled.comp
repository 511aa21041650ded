// forces_integrate.comp for a flat grid cloth (every direction's springs one rest length) on the tiled path:
// each work group copies a TILE x TILE block of positions and a ring of 2 points (the bending springs'
// reach) into shared memory, and each point gathers its springs from there by grid offset instead of the
// CSR adjacency: per point, 16 bytes of position read by the copy, not 12 adjacency entries and 12
// neighbour positions. The springs are summed in the adjacency's order (ascending spring index): per
// direction, in the order topology.cpp makes them, first the spring that ends at the point, then the one
// that starts there. Same bits as forces_integrate.comp, and so as the CPU. No wind (its normals would
// need the ring and the per-point drag): the solver keeps forces_integrate.comp for such scenes.
//
// Reads *In and writes *Out, as forces_integrate.comp.
#include "common.glsl"
#include "physics.glsl"
#include "collide.glsl"
#include "grid_springs.glsl"
#if SELF_COLLISION
#include "pair_travel.glsl"
#endif

#ifndef GROUP_SIZE
#define GROUP_SIZE 256  // invocations; the solver sets it and TILE
#endif
#ifndef TILE
#define TILE 44  // block edge, points
#endif
#define RING 2
#define REGION (TILE + 2 * RING)
#define REGION_POINTS (REGION * REGION)

layout(local_size_x = GROUP_SIZE) in;

shared float sx[3 * REGION_POINTS];

vec3 loadX(ivec2 at) {
  uint l = uint(at.y * REGION + at.x);
  return vec3(sx[3u * l], sx[3u * l + 1u], sx[3u * l + 2u]);
}

void main() {
  const uint lid = gl_LocalInvocationID.x;
  const ivec2 grid = ivec2(u_grid);
  const ivec2 tile_lo = ivec2(gl_WorkGroupID.xy) * TILE;
  const ivec2 lo = tile_lo - RING;  // the copy's origin; points outside the cloth are never read
  for (uint l = lid; l < uint(REGION_POINTS); l += uint(GROUP_SIZE)) {
    ivec2 at = lo + ivec2(int(l) % REGION, int(l) / REGION);
    if (any(lessThan(at, ivec2(0))) || any(greaterThanEqual(at, grid))) continue;
    vec3 p = posIn[at.y * grid.x + at.x].xyz;
    sx[3u * l] = p.x;
    sx[3u * l + 1u] = p.y;
    sx[3u * l + 2u] = p.z;
  }
  memoryBarrierShared();
  barrier();

  for (uint b = lid; b < uint(TILE * TILE); b += uint(GROUP_SIZE)) {
    ivec2 at = tile_lo + ivec2(int(b) % TILE, int(b) / TILE);
    if (any(greaterThanEqual(at, grid))) continue;
    uint i = uint(at.y * grid.x + at.x);
    ivec2 here = at - lo;
    precise vec3 x = loadX(here);
    // The position's w was read with the copy: the same bytes, not counted twice (GpuSolver::bytesPerPoint).
    float pin = posIn[i].w;
    precise vec3 v = loadDisp(i);
    if (pin != 0.0) {
      v = vec3(0.0);  // pinned points never move; their force is never needed
    } else {
      precise vec3 f = params.weight.xyz;
      for (int k = 0; k < 6; ++k) {
        float rest = u_rest[k];
        if (rest == 0.0) continue;
        float stiffness = params.stiffness[k / 2];
        ivec2 behind = at - kDirections[k], ahead = at + kDirections[k];
        if (inGrid(behind)) f += springForce(x, loadX(here - kDirections[k]), rest, stiffness);
        if (inGrid(ahead)) f += springForce(x, loadX(here + kDirections[k]), rest, stiffness);
      }
      v = integrateVerlet(v, f * params.weight.w, params.dt2, params.keep);
      x += v;
#if COLLIDERS && !SELF_COLLISION
      collideObjects(x, v);
#endif
    }
#if SELF_COLLISION
    checkPairTravel(i, x);
#endif
    posOut[i] = vec4(x, pin);
    storeDisp(i, v);
  }
}
