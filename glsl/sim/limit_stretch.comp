// Provot (1995) stretch limit, the Jacobi scheme (phases/stretch.glsl), mirroring CpuSolver::limitStretch:
// one dispatch per stretch pass, every point moved by the average of its violated springs' corrections.
// Reads *In and writes *Out.
#include "storage/device.glsl"
#include "storage/each_point.glsl"
#include "phases/stretch.glsl"

void eachPoint(uint i, vec3 x, vec3 v, float pin) {
  precise vec3 c = pin == 0.0 ? stretchJacobiOf(i, x) : vec3(0.0);
  precise vec3 xc = x + c;
  precise vec3 vc = v + c;  // x_prev stays where it was
  storePoint(i, xc, vc, pin);
}
