// XPBD distance constraint of one spring (Macklin et al. 2016, with the Small Steps of 2019; docs/design.md
// section 2, "XPBD"), mirroring CpuSolver::solveXpbd: the ends' moves and the multiplier's new value.
#pragma once

#include "../common.glsl"
#include "../physics.glsl"

// Spring (a, b) of type `type` with inverse masses wa, wb (0 for a pinned end) and multiplier `lambda`
// (0 at the start of a substep): ca and cb, added to the ends' positions and displacements (x_prev stays:
// v = x - x_prev is the constrained displacement), and lambda + dlambda.
float xpbdSpring(vec3 xa, vec3 xb, float wa, float wb, float rest, uint type, float lambda, out vec3 ca, out vec3 cb) {
  precise float w_sum = wa + wb;
  vec3 p;
  precise float dlambda = xpbdDistanceCorrection(xa, xb, rest, w_sum, params.alpha_tilde[type], lambda, p);
  precise vec3 a = (-wa) * p;
  precise vec3 b = wb * p;
  ca = a;
  cb = b;
  precise float next = lambda + dlambda;
  return next;
}
