// Sphere and plane collisions of one point, fused into whichever kernel last moved it (integrate when
// the scene has no self-collision, else the self-collision kernel): collisions only read the point's
// own position and displacement, so they need no pass of their own.
#pragma once

#include "../common.glsl"
#include "../physics.glsl"
#if NUM_MESHES > 0
#include "mesh_collide.glsl"
#endif

// Each object in turn, each seeing the result of the previous one (CS184 order: spheres, then planes; then meshes),
// as CpuSolver::collide. Pinned points are skipped by the caller.
void collideObjects(inout vec3 x_io, inout vec3 v_io) {
#if COLLIDERS
  precise vec3 x = x_io;
  precise vec3 v = v_io;
  vec3 c;
  for (int s = 0; s < NUM_SPHERES; ++s) {
    Collider k = colliders[s];
    if (collideSphere(x, v, k.a.xyz, k.a.w, k.b.x, c)) {
      x += c;
      v += c;
    }
  }
  for (int p = 0; p < NUM_PLANES; ++p) {
    Collider k = colliders[NUM_SPHERES + p];
    if (collidePlane(x, v, k.a.xyz, k.b.xyz, k.a.w, c)) {
      x += c;
      v += c;
    }
  }
#if NUM_MESHES > 0
  for (int m = 0; m < NUM_MESHES; ++m) {
    if (collideField(x, v, uint(NUM_SPHERES + NUM_PLANES + 2 * m), c)) {
      x += c;
      v += c;
    }
  }
#endif
  x_io = x;
  v_io = v;
#endif
}
