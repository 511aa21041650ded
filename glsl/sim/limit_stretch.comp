// Provot (1995) stretch limit, the Jacobi scheme (phases/stretch.glsl), mirroring CpuSolver::limitStretch:
// one dispatch per stretch pass, every point moved by the average of its violated springs' corrections.
// Reads *In and writes *Out.
#include "storage/device.glsl"
#include "phases/stretch.glsl"

layout(local_size_x = kLocalSize) in;

void main() {
  uint i = globalIndex();
  if (i >= params.point_count) return;
  vec3 x, v;
  float pin;
  loadPoint(i, x, v, pin);
  precise vec3 c = pin == 0.0 ? stretchJacobiOf(i, x) : vec3(0.0);
  precise vec3 xc = x + c;
  precise vec3 vc = v + c;  // x_prev stays where it was
  storePoint(i, xc, vc, pin);
}
