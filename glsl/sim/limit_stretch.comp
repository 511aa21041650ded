// Provot (1995) stretch limit as a per-point gather over the adjacency (docs/design.md section 2, step 5),
// mirroring CpuSolver::limitStretch: one dispatch per stretch pass, Jacobi (reads *In, writes *Out).
#include "common.glsl"
#include "physics.glsl"

layout(local_size_x = kLocalSize) in;

void main() {
  uint i = globalIndex();
  if (i >= params.point_count) return;
  vec4 position = posIn[i];
  precise vec3 x = position.xyz;
  precise vec3 v = loadDisp(i);
  float pin = position.w;
  precise vec3 sum = vec3(0.0);
  int violated = 0;
  if (pin == 0.0) {
    for (uint e = offsets[i]; e < offsets[i + 1u]; ++e) {
      Neighbor nb = neighbors[e];
      uint j = neighborIndex(nb);
      vec4 xj = posIn[j];  // w: its pin flag, so no gather of its displacement
      float share = stretchShare(false, isPinned(xj));
      vec3 c = stretchCorrection(x, xj.xyz, nb.rest, params.stretch_limit, share);
      if (c != vec3(0.0)) {
        sum += c;
        ++violated;
      }
    }
  }
  // Averaged over the violated springs, not summed: a hanging point's springs mostly pull the same
  // way, and their summed Jacobi corrections overshoot and diverge.
  precise vec3 c = violated > 0 ? sum / float(violated) : vec3(0.0);
  x += c;
  v += c;  // x_prev stays where it was
  posOut[i] = vec4(x, pin);
  storeDisp(i, v);
}
