// The collisions of each point as a pass of their own, for XPBD without self-collision: the constraint
// sweeps move the points after the prediction, so collisions cannot be fused into forces_integrate.comp
// as they are for Verlet. Mirrors CpuSolver::collide. Reads *In and writes *Out, as the kernels it
// stands in for.
#define SIM_NO_SPRINGS
#define SIM_NO_HEALTH
#include "common.glsl"
#include "physics.glsl"
#include "collide.glsl"

layout(local_size_x = kLocalSize) in;

void main() {
  uint i = globalIndex();
  if (i >= params.point_count) return;
  vec4 position = posIn[i];
  precise vec3 x = position.xyz;
  precise vec3 v = loadDisp(i);
  float pin = position.w;
  if (pin == 0.0) collideObjects(x, v);
  posOut[i] = vec4(x, pin);
  storeDisp(i, v);
}
