// XPBD distance constraints (phases/xpbd.glsl), Gauss-Seidel over the spring colouring, mirroring
// CpuSolver::solveXpbd: one dispatch per colour and sweep, one invocation per spring of the colour, moving
// both of its ends in place. Springs of a colour share no point, so no two invocations write the same point,
// and the barrier between dispatches gives the next colour the moved points. Needs neither the adjacency,
// the colliders nor the health flags (storage blocks: common.glsl).
#define STATE_IN_PLACE
#define SIM_NO_SPRINGS
#define SIM_NO_COLLIDERS
#define SIM_NO_HEALTH
#include "storage/device.glsl"
#include "storage/each_in_colour.glsl"
#include "point_mass.glsl"
#include "phases/xpbd.glsl"

#ifndef XPBD_LAMBDA
#define XPBD_LAMBDA 0
#endif

layout(std430, binding = kBindingColouredSprings) readonly buffer ColouredSpringsBuffer {
  ColouredSpring colouredSprings[];
};
#if XPBD_LAMBDA
// Only with more than one sweep per substep: a single sweep starts every multiplier at 0 and never reads it.
layout(std430, binding = kBindingXpbdLambda) buffer LambdaBuffer {
  float lambdas[];
};
uniform uint u_sweep;  // 0: the substep's first sweep, which starts every multiplier at 0
#endif

void eachInColour(uint index) {
  ColouredSpring s = colouredSprings[index];
  vec4 pa = neighbour(s.a), pb = neighbour(s.b);
  bool pinned_a = isPinned(pa), pinned_b = isPinned(pb);
  if (pinned_a && pinned_b) return;
  float wa = pinned_a ? 0.0 : pointMass[s.a].weight.w;
  float wb = pinned_b ? 0.0 : pointMass[s.b].weight.w;
  float lambda = 0.0;
#if XPBD_LAMBDA
  if (u_sweep > 0u) lambda = lambdas[index];
#endif
  vec3 ca, cb;
  float next = xpbdSpring(pa.xyz, pb.xyz, wa, wb, s.rest, s.type, lambda, ca, cb);
#if XPBD_LAMBDA
  lambdas[index] = next;
#endif
  // x_prev stays: v = x - x_prev is the constrained displacement.
  if (!pinned_a) movePointInPlace(s.a, pa, ca);
  if (!pinned_b) movePointInPlace(s.b, pb, cb);
}
