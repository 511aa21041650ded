// Long-range attachments (phases/tether.glsl), mirroring CpuSolver::tether: each free point in place.
#define STATE_IN_PLACE
#define SIM_NO_SPRINGS
#define SIM_NO_COLLIDERS
#define SIM_NO_HEALTH
#include "storage/device.glsl"
#include "phases/tether.glsl"

layout(local_size_x = kLocalSize) in;

void main() {
  uint i = globalIndex();
  if (i >= params.point_count) return;
  vec3 x, v;
  float pin;
  loadPoint(i, x, v, pin);
  if (pin != 0.0) return;
  tetherPoint(i, x, v);
  storePointInPlace(i, x, v, pin);
}
