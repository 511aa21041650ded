// The blow-up check (phases/health.glsl) on the state after a frame's last pass: a non-finite position or
// displacement, a coordinate beyond the sane bound, an enabled spring stretched beyond the blow-up limit.
// Reads the current state and writes only the Health flags, so it changes no position.
#include "storage/device.glsl"
#include "phases/health.glsl"

layout(local_size_x = kLocalSize) in;

void main() {
  uint i = globalIndex();
  if (i >= params.point_count) return;
  vec3 x, v;
  float pin;
  loadPoint(i, x, v, pin);
  raiseHealth(pointHealth(i, x, v), i);
}
