// Provot (1995) stretch limit, Gauss-Seidel over the spring colouring, every colour and stretch pass of a
// substep in one dispatch of blocks in shared memory (storage/tile.glsl, phases/stretch_in_group.glsl).
// limit_stretch_coloured.comp needs a dispatch, and a storage barrier, per colour: 12 a pass on a grid. HALO
// is the colouring's reach, so every block point is right; only the block is written.
//
// Reads *In and writes *Out: the ring of one block is another block's interior, which that block writes.
#define SIM_NO_SPRINGS
#define SIM_NO_COLLIDERS
#define SIM_NO_HEALTH
#ifndef GROUP_SIZE
#define GROUP_SIZE 256  // invocations; the solver sets it (and TILE, HALO) per cloth
#endif
#ifndef TILE
#define TILE 31  // block edge, points
#endif
#ifndef HALO
#define HALO 10  // ring width, points: the colouring's reach
#endif
#include "storage/tile.glsl"
#include "phases/stretch_in_group.glsl"

layout(local_size_x = GROUP_SIZE) in;

void main() {
  loadTile();
  stretchInGroup(u_passes, u_colours);
  for (uint k = 0u; k < PER_INVOCATION; ++k) {
    if (!slotInside[k]) continue;
    uint s = gl_LocalInvocationID.x + k * uint(GROUP_SIZE);
    posOut[slotGlobal[k]] = vec4(loadX(s), slotPin[k]);
    storeDisp(slotGlobal[k], slotV[k]);
  }
}
