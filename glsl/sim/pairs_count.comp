// Each point counts its candidates in the freshly built grid (pairs.glsl).
#include "lists_each_point.glsl"
#include "pairs.glsl"

void eachIndex(uint i) {
  gridCounts[i] = gatherCandidates(i, false, 0u);
}
