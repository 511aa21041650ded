// The blow-up check of one point (src/core/health.hpp, scanHealth), run by health.comp after a frame's last
// pass and by the one-dispatch kernel on the frame's last state before writing it back. Reads the other
// points through the kernel's storage: neighbour(j).
#pragma once

#include "../common.glsl"
#include "../physics.glsl"

// A non-finite position or displacement, else a coordinate beyond the sane bound.
uint stateHealth(vec3 x, vec3 v) {
  if (any(isnan(x)) || any(isinf(x)) || any(isnan(v)) || any(isinf(v))) return kHealthNonFinite;
  if (any(greaterThan(abs(x), vec3(params.sane_bound)))) return kHealthOutOfBounds;
  return 0u;
}

// A spring longer than the blow-up limit. Each end checks it, so both ends are flagged, as in scanHealth.
bool springBlownUp(vec3 x, vec3 other, float rest) {
  return length3(other - x) > params.blow_up_stretch * rest;
}

// Point i's flags: its state, then its springs (disabled types are not in the adjacency, as scanHealth
// skips them) until one is blown up.
uint pointHealth(uint i, vec3 x, vec3 v) {
  uint flags = stateHealth(x, v);
  for (uint e = offsets[i]; e < offsets[i + 1u]; ++e) {
    Neighbor nb = neighbors[e];
    if (springBlownUp(x, neighbour(neighborIndex(nb)).xyz, nb.rest)) {
      flags |= kHealthOverstretched;
      break;
    }
  }
  return flags;
}

// An atomic only when something is already wrong.
void raiseHealth(uint flags, uint i) {
  if (flags == 0u) return;
  atomicOr(health.flags, flags);
  atomicMin(health.first_point, i);
}
