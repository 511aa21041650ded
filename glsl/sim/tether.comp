// Long-range attachments (phases/tether.glsl), mirroring CpuSolver::tether: each free point in place.
#define STATE_IN_PLACE
#define SIM_NO_SPRINGS
#define SIM_NO_COLLIDERS
#define SIM_NO_HEALTH
#include "storage/device.glsl"
#include "storage/each_point.glsl"
#include "phases/tether.glsl"

void eachPoint(uint i, vec3 x, vec3 v, float pin) {
  if (pin != 0.0) return;
  tetherPoint(i, x, v);
  storePointInPlace(i, x, v, pin);
}
