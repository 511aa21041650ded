// First pass of a list build: each point's position becomes its anchor and is counted into the hash
// grid (grid.glsl); the largest coordinate sets the build's safe travel (CollisionPairs::safeTravel).
// Needs no springs, colliders or health flags (common.glsl: a storage block fewer each).
#define SIM_NO_SPRINGS
#define SIM_NO_COLLIDERS
#define SIM_NO_HEALTH
#include "common.glsl"
#include "pairs.glsl"

layout(local_size_x = kLocalSize) in;

void main() {
  uint i = globalIndex();
  if (i >= params.point_count) return;
  vec3 x = posIn[i].xyz;
  pairAnchor[i] = vec4(x, 1.0);
  countIntoGrid(i, x);
  // Non-negative floats order like their bits. A NaN position needs no care here: its travel check
  // fails whatever the travel, so every later substep rebuilds, as on the CPU.
  vec3 m = abs(x);
  atomicMax(pairState.extent_bits, floatBitsToUint(max(max(m.x, m.y), m.z)));
}
