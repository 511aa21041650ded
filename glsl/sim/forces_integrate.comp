// Forces and Verlet integration of each point (phases/integrate.glsl), its collisions where the plan fused
// them here, else, when a self-collision pass follows, whether it moved too far for the candidate lists
// (TRAVEL_CHECK). With PREDICT=1 it is XPBD's or VBD's prediction: no springs (xpbd_coloured.comp and
// vbd_coloured.comp solve them) and nothing fused after it, since the sweeps move the point first.
// Reads *In and writes *Out: the force gather reads the neighbours' positions while other invocations
// move theirs, so integrating in place would race.
#include "storage/device.glsl"
#include "storage/each_point.glsl"
#include "point_mass.glsl"
#if WIND
uniform float u_time;  // s, simulated time at the start of the substep (substeps * dt, as the CPU)

float windTime() {
  return u_time;
}
#endif
#include "phases/integrate.glsl"
#ifndef TRAVEL_CHECK
#define TRAVEL_CHECK 0
#endif
#if TRAVEL_CHECK
#include "pair_travel.glsl"
#endif

void eachPoint(uint i, vec3 x, vec3 v, float pin) {
  integratePoint(i, ivec2(0), x, v, pin, pointWeight(i));
#if TRAVEL_CHECK
  checkPairTravel(i, x);
#endif
  storePoint(i, x, v, pin);
}
