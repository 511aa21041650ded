// The face contacts (phases/faces.glsl), then the point's collisions again where the plan fused them here
// (COLLIDE_AFTER_FACES: this is the last pass to move the points, CpuSolver's collide_last). Mirrors
// CpuSolver::collideFaces (and collide). Jacobi: reads *In, writes *Out.
#define SIM_NO_SPRINGS
#define SIM_NO_HEALTH
#include "storage/device.glsl"
#include "storage/each_point.glsl"
#include "phases/faces.glsl"
#include "phases/collide.glsl"
#ifndef COLLIDE_AFTER_FACES
#define COLLIDE_AFTER_FACES 0
#endif

void eachPoint(uint i, vec3 x_in, vec3 v_in, float pin) {
  precise vec3 c = pin == 0.0 ? faceCorrection(i) : vec3(0.0);
  precise vec3 x = x_in + c;
  precise vec3 v = v_in + c;
#if COLLIDE_AFTER_FACES
  if (pin == 0.0) collideObjects(x, v);
#endif
  storePoint(i, x, v, pin);
}
