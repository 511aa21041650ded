// Each point counts its candidates in the freshly built grid (pairs.glsl).
// Needs no springs, colliders or health flags (common.glsl: a storage block fewer each).
#define SIM_NO_SPRINGS
#define SIM_NO_COLLIDERS
#define SIM_NO_HEALTH
#include "common.glsl"
#include "pairs.glsl"

layout(local_size_x = kLocalSize) in;

void main() {
  uint i = globalIndex();
  if (i < params.point_count) gridCounts[i] = gatherCandidates(i, false, 0u);
}
