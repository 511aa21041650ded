// The blow-up check (src/core/health.hpp, scanHealth) on the state after a frame's last pass: a non-finite
// position or displacement, a coordinate beyond the sane bound, an enabled spring stretched beyond the
// blow-up limit. Reads the current state and writes only the Health flags, so it changes no position.
#include "common.glsl"
#include "health.glsl"

layout(local_size_x = kLocalSize) in;

void main() {
  uint i = globalIndex();
  if (i >= params.point_count) return;
  vec3 x = posIn[i].xyz;
  uint flags = stateHealth(x, loadDisp(i));
  // Disabled spring types are not in the adjacency, as scanHealth skips them.
  for (uint e = offsets[i]; e < offsets[i + 1u]; ++e) {
    Neighbor nb = neighbors[e];
    if (springBlownUp(x, posIn[neighborIndex(nb)].xyz, nb.rest)) {
      flags |= kHealthOverstretched;
      break;
    }
  }
  raiseHealth(flags, i);
}
