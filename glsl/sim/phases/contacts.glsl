// Self-collision (docs/design.md section 2, step 3) of one point once its terms are summed: the average,
// divided by steps_per_frame as in CS184, added to x and v (x_prev stays where it was), then the point's
// collisions where the plan fused them here (COLLIDE_AFTER_CONTACTS: the self-collision pass is the last to
// move the point before them). The terms themselves are the storage's to find, in the CPU's order (the
// 27-cell order of forEachOrderedPair, ascending index within a cell): from the candidate lists
// (self_collide.comp) or from the one-dispatch kernel's grid in shared memory (storage/group_contacts.glsl).
#pragma once

#include "../common.glsl"
#include "../physics.glsl"
#include "collide.glsl"
#ifndef COLLIDE_AFTER_CONTACTS
#define COLLIDE_AFTER_CONTACTS 0
#endif

// The move of a point whose `count` nonzero terms sum to `sum` (Jacobi: from the positions before the pass).
vec3 contactCorrection(vec3 sum, int count) {
  precise vec3 c = count > 0 ? sum / (float(count) * params.steps_per_frame) : vec3(0.0);
  return c;
}

// x and v moved by `correction` where the point had terms (moved); the others keep their bits, as on the CPU,
// whose pass visits only the points with terms (x + 0 would turn a -0 into +0).
void applyContact(vec3 correction, bool moved, float pin, inout vec3 x_io, inout vec3 v_io) {
  precise vec3 x = moved ? x_io + correction : x_io;
  precise vec3 v = moved ? v_io + correction : v_io;
#if COLLIDE_AFTER_CONTACTS
  if (pin == 0.0) collideObjects(x, v);
#endif
  x_io = x;
  v_io = v;
}
