// Vertex Block Descent (phases/vbd.glsl) on the springs, Gauss-Seidel over the point colouring, mirroring
// CpuSolver::solveVbd: one dispatch per colour and sweep, one invocation per point of the colour, which moves
// itself in place by the Newton step of its block. Points of a colour share no spring, so no invocation
// reads a point another one writes, and the barrier between dispatches gives the next colour the moved
// points. Needs neither the colliders nor the health flags (storage blocks: common.glsl).
#define STATE_IN_PLACE
#define SIM_NO_COLLIDERS
#define SIM_NO_HEALTH
#include "storage/device.glsl"
#include "storage/each_in_colour.glsl"
#include "phases/vbd.glsl"
#if !UNIFORM_MASS
#include "point_mass.glsl"
#endif

#ifndef VBD_INERTIA
#define VBD_INERTIA 0
#endif

layout(std430, binding = kBindingColouredPoints) readonly buffer ColouredPointsBuffer {
  uint colouredPoints[];
};
#if VBD_INERTIA
// Only with more than one sweep per substep: in the first a point is still at its prediction y (only its
// own invocation moves it), so the inertia's gradient is 0 and y is kept here for the later sweeps.
layout(std430, binding = kBindingVbdInertia) buffer InertiaBuffer {
  vec4 inertiaTarget[];
};
uniform uint u_sweep;  // 0: the substep's first sweep
#endif

void eachInColour(uint index) {
  uint i = colouredPoints[index];
  vec4 position = posIn[i];
  if (isPinned(position)) return;
#if UNIFORM_MASS
  float w = params.weight.w;
#else
  float w = pointMass[i].weight.w;
#endif
  precise vec3 x = position.xyz;
  precise float inertia = 1.0 / (w * params.dt2);  // m / dt^2
  vec3 pull = vec3(0.0);
#if VBD_INERTIA
  if (u_sweep > 0u) {
    precise vec3 p = (-inertia) * (x - inertiaTarget[i].xyz);
    pull = p;
  } else {
    inertiaTarget[i] = vec4(x, 0.0);
  }
#endif
  // x_prev stays: v = x - x_prev is the solved displacement.
  movePointInPlace(i, position, vbdStepOf(i, x, inertia, pull));
}
