// Forces and Verlet integration of one point in one kernel (docs/design.md section 2, steps 1 and 2),
// followed by what else only needs the point's own new state: its collisions when no self-collision
// pass sits in between, else the check whether it moved too far for the self-collision lists. Mirrors
// CpuSolver::accumulateForces, integrate (and collide). With PREDICT=1 it is PREDICT's or VBD's prediction
// instead: no spring gather (the springs are solved implicitly, xpbd_coloured.comp or vbd_coloured.comp)
// and nothing fused after it, since the sweeps move the point before collisions and the lists' travel
// check may look at it.
// Reads *In and writes *Out: the force gather reads the neighbours' positions while other invocations
// move theirs, so integrating in place would race.
#include "common.glsl"
#include "physics.glsl"
#include "collide.glsl"
#ifndef PREDICT
#define PREDICT 0
#endif
#if SELF_COLLISION && !PREDICT
#include "pair_travel.glsl"
#endif

layout(local_size_x = kLocalSize) in;

layout(std430, binding = kBindingPointMass) readonly buffer PointMassBuffer {
  PointMass pointMass[];
};

#if WIND
uniform float u_time;  // s, simulated time at the start of the substep (substeps * dt, as the CPU)

// CpuSolver::pointNormal: on a grid, central differences clamped at the border.
vec3 pointNormal(PointMass m) {
  return gridNormal(posIn[m.normal_a].xyz, posIn[m.normal_b].xyz, posIn[m.normal_c].xyz, posIn[m.normal_d].xyz);
}
#endif

void main() {
  uint i = globalIndex();
  if (i >= params.point_count) return;
  vec4 position = posIn[i];
  precise vec3 x = position.xyz;
  precise vec3 v = loadDisp(i);
  float pin = position.w;
  if (pin != 0.0) {
    v = vec3(0.0);  // pinned points never move; their force is never needed
  } else {
#if UNIFORM_MASS
    vec4 weight = params.weight;
#else
    vec4 weight = pointMass[i].weight;
#endif
    precise vec3 f = weight.xyz;
#if !PREDICT
    // Ascending spring index, the CPU's order, so the sums round alike. Disabled spring types are not
    // in the GPU's adjacency at all.
    for (uint e = offsets[i]; e < offsets[i + 1u]; ++e) {
      Neighbor nb = neighbors[e];
      f += springForce(x, posIn[neighborIndex(nb)].xyz, nb.rest, params.stiffness[neighborType(nb)]);
    }
#endif
#if WIND
    PointMass m = pointMass[i];
    precise vec3 air = windVelocity(x, u_time, params.wind_velocity.xyz, params.wind_velocity.w, params.noise_scale,
                                    params.noise_speed);
    f += windForce(pointNormal(m), v / params.dt, air, m.drag_area);
#endif
    v = integrateVerlet(v, f * weight.w, params.dt2, params.keep);
    x += v;
#if COLLIDERS && !SELF_COLLISION && !PREDICT
    collideObjects(x, v);
#endif
  }
#if SELF_COLLISION && !PREDICT
  checkPairTravel(i, x);
#endif
  posOut[i] = vec4(x, pin);
  storeDisp(i, v);
}
