// The collisions of each point as a pass of their own (phases/collide.glsl), for XPBD and VBD without
// self-collision: the constraint sweeps move the points after the prediction, so the plan cannot fuse
// collisions into forces_integrate.comp as it does for Verlet. Mirrors CpuSolver::collide. Reads *In and
// writes *Out, as the kernels it stands in for.
#define SIM_NO_SPRINGS
#define SIM_NO_HEALTH
#include "storage/device.glsl"
#include "phases/collide.glsl"

layout(local_size_x = kLocalSize) in;

void main() {
  uint i = globalIndex();
  if (i >= params.point_count) return;
  vec3 x, v;
  float pin;
  loadPoint(i, x, v, pin);
  if (pin == 0.0) collideObjects(x, v);
  storePoint(i, x, v, pin);
}
