// Forces and Verlet integration of one point (docs/design.md section 2, steps 1 and 2), then its collisions
// where the plan fused them here (COLLIDE_AFTER_INTEGRATE: no pass after this one moves the point first).
// Mirrors CpuSolver::accumulateForces and integrate (and collide). With PREDICT=1 it is XPBD's and VBD's
// prediction: gravity and wind only, the springs being solved implicitly afterwards.
//
// Reads the other points through the kernel's storage (glsl/sim/storage): neighbour(j), and on a flat grid
// (GRID_SPRINGS: every direction's springs one rest length) gridNeighbour(at) instead of the adjacency;
// with WIND, windTime(), the simulated time at the start of the substep.
#pragma once

#include "../common.glsl"
#include "../physics.glsl"
#include "collide.glsl"
#ifndef PREDICT
#define PREDICT 0
#endif
#ifndef GRID_SPRINGS
#define GRID_SPRINGS 0
#endif
#ifndef COLLIDE_AFTER_INTEGRATE
#define COLLIDE_AFTER_INTEGRATE 0
#endif
#if GRID_SPRINGS
#include "../grid_springs.glsl"
#endif
#if WIND
#include "../point_mass.glsl"
#endif

#if !PREDICT
// The springs' forces on point i (at grid position `at` with GRID_SPRINGS) in the adjacency's order,
// ascending spring index, which is the CPU's, so the sums round alike. Disabled spring types are in neither
// the GPU's adjacency nor u_rest.
void addSpringForces(uint i, ivec2 at, vec3 x, inout vec3 f_io) {
  precise vec3 f = f_io;
#if GRID_SPRINGS
  // Per direction, in the order topology.cpp makes them: the spring that ends here, then the one that starts here.
  for (int d = 0; d < 6; ++d) {
    float rest = u_rest[d];
    if (rest == 0.0) continue;
    float stiffness = params.stiffness[d / 2];
    ivec2 behind = at - kDirections[d], ahead = at + kDirections[d];
    if (inGrid(behind)) f += springForce(x, gridNeighbour(behind).xyz, rest, stiffness);
    if (inGrid(ahead)) f += springForce(x, gridNeighbour(ahead).xyz, rest, stiffness);
  }
#else
  for (uint e = offsets[i]; e < offsets[i + 1u]; ++e) {
    Neighbor nb = neighbors[e];
    f += springForce(x, neighbour(neighborIndex(nb)).xyz, nb.rest, params.stiffness[neighborType(nb)]);
  }
#endif
  f_io = f;
}
#endif

#if WIND
// CpuSolver::pointNormal: on a grid, central differences clamped at the border.
vec3 pointNormal(PointMass m) {
  return gridNormal(neighbour(m.normal_a).xyz, neighbour(m.normal_b).xyz, neighbour(m.normal_c).xyz,
                    neighbour(m.normal_d).xyz);
}

void addWindForce(uint i, vec3 x, vec3 v, inout vec3 f_io) {
  PointMass m = pointMass[i];
  precise vec3 f = f_io;
  precise vec3 air = windVelocity(x, windTime(), params.wind_velocity.xyz, params.wind_velocity.w, params.noise_scale,
                                  params.noise_speed);
  f += windForce(pointNormal(m), v / params.dt, air, m.drag_area);
  f_io = f;
}
#endif

// Point i's substep: x and v in, the new x and v out. `weight` is PointMass::weight (gravity * m, 1 / m).
void integratePoint(uint i, ivec2 at, inout vec3 x_io, inout vec3 v_io, float pin, vec4 weight) {
  precise vec3 x = x_io;
  precise vec3 v = v_io;
  if (pin != 0.0) {
    v = vec3(0.0);  // pinned points never move; their force is never needed
  } else {
    precise vec3 f = weight.xyz;
#if !PREDICT
    addSpringForces(i, at, x, f);
#endif
#if WIND
    addWindForce(i, x, v, f);
#endif
    v = integrateVerlet(v, f * weight.w, params.dt2, params.keep);
    x += v;
#if COLLIDE_AFTER_INTEGRATE
    collideObjects(x, v);
#endif
  }
  x_io = x;
  v_io = v;
}
