// Provot (1995) stretch limit (docs/design.md section 2, step 6), the one correction (physics.glsl's
// stretchOneEnd) in the three views the kernels need: Gauss-Seidel per spring (both ends of a spring of one
// colour, limit_stretch_coloured.comp), Gauss-Seidel per point (the point's spring of one colour, on a copy in
// shared memory: stretch_in_group.glsl), and Jacobi per point (the average of its violated springs).
#pragma once

#include "../common.glsl"
#include "../physics.glsl"

// Spring (a, b), a < b, one of its colour: each free end's move. stretchOneEnd gives each end exactly what
// CpuSolver::limitStretchColoured gives it; with both ends free, b's is -a's (IEEE negation is exact),
// which is what stretchOneEnd would give b, without computing it twice.
void stretchSpring(vec3 xa, vec3 xb, bool pinned_a, bool pinned_b, float rest, out vec3 ca, out vec3 cb) {
  ca = pinned_a ? vec3(0.0) : stretchOneEnd(xa, xb, false, pinned_b, rest, params.stretch_limit);
  cb = pinned_b ? vec3(0.0) : pinned_a ? stretchOneEnd(xb, xa, true, true, rest, params.stretch_limit) : -ca;
}

#ifndef SIM_NO_SPRINGS
// Point i's Jacobi correction (CpuSolver::limitStretch), from the positions before the pass: averaged over
// its violated springs, not summed, since a hanging point's springs mostly pull the same way and their summed
// corrections overshoot and diverge. Reads the neighbours through the storage's neighbour(j), whose w (the pin
// flag) saves a gather of their displacements.
vec3 stretchJacobiOf(uint i, vec3 x) {
  precise vec3 sum = vec3(0.0);
  int violated = 0;
  for (uint e = offsets[i]; e < offsets[i + 1u]; ++e) {
    Neighbor nb = neighbors[e];
    vec4 xj = neighbour(neighborIndex(nb));
    float share = stretchShare(false, isPinned(xj));
    vec3 c = stretchCorrection(x, xj.xyz, nb.rest, params.stretch_limit, share);
    if (c != vec3(0.0)) {
      sum += c;
      ++violated;
    }
  }
  precise vec3 c = violated > 0 ? sum / float(violated) : vec3(0.0);
  return c;
}
#endif
