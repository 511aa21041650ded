// First pass of a list build: each point's position becomes its anchor and is counted into the hash
// grid (grid.glsl); the largest coordinate sets the build's safe travel (CollisionPairs::safeTravel).
#include "lists_each_point.glsl"
#include "pairs.glsl"

void eachIndex(uint i) {
  vec3 x = posIn[i].xyz;
  pairAnchor[i] = vec4(x, 1.0);
  countIntoGrid(i, x);
  // Non-negative floats order like their bits. A NaN position needs no care here: its travel check
  // fails whatever the travel, so every later substep rebuilds, as on the CPU.
  vec3 m = abs(x);
  atomicMax(pairState.extent_bits, floatBitsToUint(max(max(m.x, m.y), m.z)));
}
