// One substep's stretch limit fused with the next substep's forces, integration and collisions, for a
// flat grid cloth on the tiled path without self-collision, tethers or wind: the frame runs
// forces_integrate_tiled, then this kernel once per remaining substep, then limit_stretch_tiled
// (GpuPlan's frame plan). The order is the substeps' own; only the cuts between dispatches move.
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
#ifndef GROUP_SIZE
#define GROUP_SIZE 256  // invocations; the solver sets it (and TILE, HALO) per cloth
#endif
#ifndef TILE
#define TILE 27  // block edge, points
#endif
#ifndef HALO
#define HALO 12  // ring width, points: the colouring's reach + 2
#endif
#define GRID_SPRINGS 1  // the forces find springs from the grid, so the stretch limit does too
#include "storage/tile.glsl"
#include "phases/stretch_in_group.glsl"
#include "phases/integrate.glsl"

layout(local_size_x = GROUP_SIZE) in;

uniform bool u_stretch;  // false: the frame's first substep, whose forces follow no stretch limit

void main() {
  loadTile();
  if (u_stretch) stretchInGroup(u_passes, u_colours);
  for (uint k = 0u; k < PER_INVOCATION; ++k) {
    if (!slotInside[k]) continue;
    uint s = gl_LocalInvocationID.x + k * uint(GROUP_SIZE);
    vec3 x = loadX(s);
    integratePoint(slotGlobal[k], gridAt(slotGlobal[k]), x, slotV[k], slotPin[k], params.weight);
    posOut[slotGlobal[k]] = vec4(x, slotPin[k]);
    storeDisp(slotGlobal[k], slotV[k]);
  }
}
