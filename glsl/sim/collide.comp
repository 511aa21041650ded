// The collisions of each point as a pass of their own (phases/collide.glsl), for XPBD and VBD without
// self-collision: the constraint sweeps move the points after the prediction, so the plan cannot fuse
// collisions into forces_integrate.comp as it does for Verlet. Mirrors CpuSolver::collide. Reads *In and
// writes *Out, as the kernels it stands in for.
#define SIM_NO_SPRINGS
#define SIM_NO_HEALTH
#include "storage/device.glsl"
#include "storage/each_point.glsl"
#include "phases/collide.glsl"

void eachPoint(uint i, vec3 x, vec3 v, float pin) {
  if (pin == 0.0) collideObjects(x, v);
  storePoint(i, x, v, pin);
}
