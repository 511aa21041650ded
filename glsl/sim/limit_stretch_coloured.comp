// Provot (1995) stretch limit, Gauss-Seidel over a colouring of the springs (src/core/colouring.hpp),
// mirroring CpuSolver::limitStretchColoured: one dispatch per colour, one invocation per spring of the
// colour, moving both of its ends in place. Springs of a colour share no point, so no two invocations
// write the same point, and the barrier between dispatches gives the next colour the moved points.
#define STATE_IN_PLACE
#include "common.glsl"
#include "physics.glsl"

layout(local_size_x = kLocalSize) in;

layout(std430, binding = kBindingColouredSprings) readonly buffer ColouredSpringsBuffer {
  ColouredSpring colouredSprings[];
};

uniform uint u_first;  // the colour's first spring
uniform uint u_count;  // springs in the colour

void main() {
  uint k = globalIndex();
  if (k >= u_count) return;
  ColouredSpring s = colouredSprings[u_first + k];
  vec4 pa = posIn[s.a], pb = posIn[s.b];
  bool pinned_a = isPinned(pa), pinned_b = isPinned(pb);
  float share_a = stretchShare(pinned_a, pinned_b);
  float share_b = stretchShare(pinned_b, pinned_a);
  precise vec3 xa = pa.xyz;
  precise vec3 xb = pb.xyz;
  precise vec3 ca = stretchCorrection(xa, xb, s.rest, params.stretch_limit, share_a);
  // Equal shares: end b's correction is exactly -ca in IEEE arithmetic, as on the CPU.
  precise vec3 cb = share_a == share_b ? -ca : stretchCorrection(xb, xa, s.rest, params.stretch_limit, share_b);
  if (!pinned_a) {
    posIn[s.a] = vec4(xa + ca, pa.w);
    storeDispInPlace(s.a, loadDisp(s.a) + ca);  // x_prev stays where it was
  }
  if (!pinned_b) {
    posIn[s.b] = vec4(xb + cb, pb.w);
    storeDispInPlace(s.b, loadDisp(s.b) + cb);
  }
}
