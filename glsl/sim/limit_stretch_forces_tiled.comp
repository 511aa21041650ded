// One substep's stretch limit fused with the next substep's forces, integration and collisions, for a
// flat grid cloth on the tiled path without self-collision, tethers or wind: the frame runs
// forces_integrate_tiled, then this kernel once per remaining substep, then limit_stretch_tiled
// (GpuSolver::stepFrame). The order is the substeps' own; only the cuts between dispatches move.
//
// Cut there, rather than after the stretch limit, because the forces need only positions around a block
// (a ring of 2, the bending springs' reach) and the stretch limit changes a ring point's displacement
// only by its correction: the copy is positions with a ring of the colouring's reach plus 2 (HALO, set
// by the solver), and displacements only for the block. The stretch limit then leaves every point within
// 2 of the block right, the forces read only those, and the block is integrated and written. Fused the
// other way round (forces, then the stretch limit), the ring's points would have to be integrated, their
// displacements copied too.
//
// Reads *In and writes *Out, as both kernels it fuses. Same bits as running them in turn.
#define SIM_NO_SPRINGS
#define SIM_NO_HEALTH
#include "common.glsl"
#include "physics.glsl"
#include "collide.glsl"

#ifndef GROUP_SIZE
#define GROUP_SIZE 256  // invocations; the solver sets it (and TILE, HALO) per cloth
#endif
#ifndef TILE
#define TILE 27  // block edge, points
#endif
#ifndef HALO
#define HALO 12  // ring width, points: the colouring's reach + 2
#endif
#ifndef GRID_PARTNERS
#define GRID_PARTNERS 1  // the forces find springs from the grid, so the stretch limit does too
#endif

layout(local_size_x = GROUP_SIZE) in;

#include "stretch_tiled.glsl"

uniform bool u_stretch;  // false: the frame's first substep, whose forces follow no stretch limit

void main() {
  loadTile();
  if (u_stretch) limitStretchTile();
  // forces_integrate_tiled.comp's per-point work on the stretched copy.
  for (uint k = 0u; k < PER_INVOCATION; ++k) {
    if (!inside[k]) continue;
    uint l = gl_LocalInvocationID.x + k * uint(GROUP_SIZE);
    ivec2 at = gridAt(global[k]);
    precise vec3 x = loadX(l);
    precise vec3 vk = v[k];
    if (w[k] != 0.0) {
      vk = vec3(0.0);  // pinned points never move; their force is never needed
    } else {
      precise vec3 f = params.weight.xyz;
      for (int d = 0; d < 6; ++d) {
        float rest = u_rest[d];
        if (rest == 0.0) continue;
        float stiffness = params.stiffness[d / 2];
        ivec2 behind = at - kDirections[d], ahead = at + kDirections[d];
        if (inGrid(behind)) f += springForce(x, loadX(copyIndex(uvec2(behind))), rest, stiffness);
        if (inGrid(ahead)) f += springForce(x, loadX(copyIndex(uvec2(ahead))), rest, stiffness);
      }
      vk = integrateVerlet(vk, f * params.weight.w, params.dt2, params.keep);
      x += vk;
#if COLLIDERS
      collideObjects(x, vk);
#endif
    }
    posOut[global[k]] = vec4(x, w[k]);
    storeDisp(global[k], vk);
  }
}
