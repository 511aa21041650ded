// Provot (1995) stretch limit, Gauss-Seidel over a colouring of the springs (src/core/colouring.hpp;
// phases/stretch.glsl), mirroring CpuSolver::limitStretchColoured: one dispatch per colour, one invocation
// per spring of the colour, moving both of its ends in place. Springs of a colour share no point, so no two
// invocations write the same point, and the barrier between dispatches gives the next colour the moved points.
#define STATE_IN_PLACE
#include "storage/device.glsl"
#include "storage/each_in_colour.glsl"
#include "phases/stretch.glsl"

layout(std430, binding = kBindingColouredSprings) readonly buffer ColouredSpringsBuffer {
  ColouredSpring colouredSprings[];
};

void eachInColour(uint index) {
  ColouredSpring s = colouredSprings[index];
  vec4 pa = neighbour(s.a), pb = neighbour(s.b);
  bool pinned_a = isPinned(pa), pinned_b = isPinned(pb);
  vec3 ca, cb;
  stretchSpring(pa.xyz, pb.xyz, pinned_a, pinned_b, s.rest, ca, cb);
  if (!pinned_a) movePointInPlace(s.a, pa, ca);
  if (!pinned_b) movePointInPlace(s.b, pb, cb);
}
