// The blow-up check (phases/health.glsl) on the state after a frame's last pass: a non-finite position or
// displacement, a coordinate beyond the sane bound, an enabled spring stretched beyond the blow-up limit.
// Reads the current state and writes only the Health flags, so it changes no position.
#include "storage/device.glsl"
#include "storage/each_point.glsl"
#include "phases/health.glsl"

void eachPoint(uint i, vec3 x, vec3 v, float pin) {
  raiseHealth(pointHealth(i, x, v), i);
}
