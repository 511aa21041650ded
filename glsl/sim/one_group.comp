// The one-dispatch path: every substep of a frame in one work group, the cloth in shared memory
// (storage/group.glsl; docs/design.md section 4, "The one-dispatch path"). For cloths that fit
// (GpuPlan's path choice): on a real GPU a 50x50 frame of 30 substeps is then one dispatch of some
// microseconds of work instead of 30 x 13 dispatches, each a launch and a storage barrier.
//
// A substep runs the general path's phases (glsl/sim/phases), in its order, the bits u_phases selects
// (kPhase*, glsl/shared/layout.h): forces + integrate, self-collision, tethers, the stretch passes, the
// collisions again (COLLIDE_LAST); a
// work-group barrier stands where the general path has a storage barrier between dispatches. A frame ends
// with health.comp's check of the last state (u_check_health) before the state is written back.
#define STATE_IN_PLACE
#include "storage/group.glsl"
#if WIND
// Time as the CPU computes it, float(double(substep) * dt), needs the double product.
uniform double u_first_substep;  // substeps taken before this dispatch
uniform double u_dt;             // s, SimParams::dt() in double
float substepTime;

float windTime() {
  return substepTime;
}
#endif
#include "phases/integrate.glsl"
#include "phases/stretch_in_group.glsl"
#include "phases/health.glsl"
#if SELF_COLLISION
#include "storage/group_contacts.glsl"
#include "phases/contacts.glsl"
#endif
#ifndef TETHER_SLOTS
#define TETHER_SLOTS 0  // tethers per point; 0: the scene has none, and the phase is not compiled
#endif
#if TETHER_SLOTS > 0
#include "phases/tether.glsl"
#endif
#ifndef COLLIDE_LAST
#define COLLIDE_LAST 0  // 1: the collisions again after the tethers and the stretch limit (CpuSolver's collide_last)
#endif
#if COLLIDE_LAST
#include "phases/collide.glsl"
#endif

layout(local_size_x = GROUP_SIZE) in;

uniform uint u_substeps;        // substeps this dispatch runs
uniform uint u_phases;          // kPhase* bits: the phases each substep runs (all of them, or one for a test)
uniform uint u_stretch_passes;  // SimParams::stretch_passes
uniform uint u_colours;         // spring colours; 0: the Jacobi stretch scheme
uniform bool u_check_health;    // end with health.comp's check of the last state (a frame), so a frame is one dispatch

// Jacobi, as the general path's ping-pong: every force reads the positions before the substep.
void integrateGroup() {
  const uint lid = gl_LocalInvocationID.x;
  vec3 x_new[PER_INVOCATION];
  for (uint k = 0u; k < PER_INVOCATION; ++k) {
    uint s = lid + k * GROUP_SIZE;
    if (s >= GROUP_POINTS) continue;
    x_new[k] = loadX(s);
    integratePoint(s, slotAt(s, k), x_new[k], slotV[k], slotPin[k], slotWeight[k]);
  }
  syncGroup();
  for (uint k = 0u; k < PER_INVOCATION; ++k) {
    uint s = lid + k * GROUP_SIZE;
    if (s < GROUP_POINTS) storeX(s, x_new[k]);
  }
  syncGroup();
}

#if SELF_COLLISION
// Jacobi, as self_collide.comp: every sum reads the positions before the pass.
void contactsGroup() {
  const uint lid = gl_LocalInvocationID.x;
  buildGroupGrid();
  vec3 corr[PER_INVOCATION];
  bool moved[PER_INVOCATION];
  for (uint k = 0u; k < PER_INVOCATION; ++k) {
    uint s = lid + k * GROUP_SIZE;
    corr[k] = vec3(0.0);
    moved[k] = false;
    if (!slotMovable(s, k)) continue;
    vec3 sum;
    int count;
    sumContactsInGroup(s, sum, count);
    corr[k] = contactCorrection(sum, count);
    moved[k] = count > 0;
  }
  syncGroup();
  for (uint k = 0u; k < PER_INVOCATION; ++k) {
    uint s = lid + k * GROUP_SIZE;
    if (s >= GROUP_POINTS) continue;
    vec3 x = loadX(s);
    applyContact(corr[k], moved[k], slotPin[k], x, slotV[k]);
    storeX(s, x);
  }
  syncGroup();
}
#endif

#if TETHER_SLOTS > 0
// A point moves only itself and reads only pins, so no barrier between reading and writing.
void tethersGroup() {
  const uint lid = gl_LocalInvocationID.x;
  for (uint k = 0u; k < PER_INVOCATION; ++k) {
    uint s = lid + k * GROUP_SIZE;
    if (!slotMovable(s, k)) continue;
    vec3 x = loadX(s);
    tetherPoint(s, x, slotV[k]);
    storeX(s, x);
  }
  syncGroup();
}
#endif

#if COLLIDE_LAST
// A point moves only itself; the barrier lets the next substep's forces see the result.
void collideLastGroup() {
  const uint lid = gl_LocalInvocationID.x;
  for (uint k = 0u; k < PER_INVOCATION; ++k) {
    uint s = lid + k * GROUP_SIZE;
    if (!slotMovable(s, k)) continue;
    vec3 x = loadX(s);
    collideObjects(x, slotV[k]);
    storeX(s, x);
  }
  syncGroup();
}
#endif

// The state back to device memory, in place: the group read all of it before writing any.
void storeGroup() {
  const uint lid = gl_LocalInvocationID.x;
  for (uint k = 0u; k < PER_INVOCATION; ++k) {
    uint s = lid + k * GROUP_SIZE;
    if (s >= GROUP_POINTS) continue;
    vec3 x = loadX(s);
    if (u_check_health) raiseHealth(pointHealth(s, x, slotV[k]), s);
    posIn[s] = vec4(x, slotPin[k]);
    storeDispInPlace(s, slotV[k]);
  }
}

void main() {
  loadGroup();
  for (uint substep = 0u; substep < u_substeps; ++substep) {
#if WIND
    substepTime = float((u_first_substep + double(substep)) * u_dt);
#endif
    if ((u_phases & kPhaseIntegrate) != 0u) integrateGroup();
#if SELF_COLLISION
    if ((u_phases & kPhaseSelfCollide) != 0u) contactsGroup();
#endif
#if TETHER_SLOTS > 0
    if ((u_phases & kPhaseTether) != 0u) tethersGroup();
#endif
    if ((u_phases & kPhaseStretch) != 0u) stretchInGroup(u_stretch_passes, u_colours);
#if COLLIDE_LAST
    if ((u_phases & kPhaseCollideLast) != 0u) collideLastGroup();
#endif
  }
  storeGroup();
}
