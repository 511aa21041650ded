// The blow-up check (src/core/health.hpp, scanHealth) on the state after a frame's last pass: a non-finite
// position or displacement, a coordinate beyond the sane bound, an enabled spring stretched beyond the
// blow-up limit. Reads the current state and writes only the Health flags, so it changes no position.
// A few compares per point; an atomic only when something is already wrong.
#include "common.glsl"
#include "physics.glsl"

layout(local_size_x = kLocalSize) in;

void main() {
  uint i = globalIndex();
  if (i >= params.point_count) return;
  vec3 x = posIn[i].xyz;
  vec3 v = dispIn[i].xyz;
  uint flags = 0u;
  if (any(isnan(x)) || any(isinf(x)) || any(isnan(v)) || any(isinf(v))) {
    flags = kHealthNonFinite;
  } else if (any(greaterThan(abs(x), vec3(params.sane_bound)))) {
    flags = kHealthOutOfBounds;
  }
  // Disabled spring types are not in the adjacency, as scanHealth skips them. Each end of a spring
  // checks it, so both ends are flagged, as in scanHealth.
  for (uint e = offsets[i]; e < offsets[i + 1u]; ++e) {
    Neighbor nb = neighbors[e];
    if (length3(posIn[neighborIndex(nb)].xyz - x) > params.blow_up_stretch * nb.rest) {
      flags |= kHealthOverstretched;
      break;
    }
  }
  if (flags != 0u) {
    atomicOr(health.flags, flags);
    atomicMin(health.first_point, i);
  }
}
