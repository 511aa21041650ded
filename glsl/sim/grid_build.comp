// The whole hash-grid build after the count (scan, scatter, rank; see grid.glsl) in one work group and
// one dispatch, for up to kScanBlock buckets: for small cloths the dispatches, not the work, are the
// cost. memoryBarrierBuffer + barrier make each phase's buffer writes visible to the whole group
// before the next phase reads them. Every invocation runs the same number of rounds (the excess ones
// idle): with a loop whose trip count differs between invocations before the barrier, Mesa 22.3's
// llvmpipe lost some of the following phase's writes (tests/gpu_grid_gl_test.cpp caught it).
// Needs no springs, colliders or health flags (common.glsl: a storage block fewer each).
#define SIM_NO_SPRINGS
#define SIM_NO_COLLIDERS
#define SIM_NO_HEALTH
#define GRID_MEMORY coherent
#include "grid_scan.glsl"

layout(local_size_x = kScanLocalSize) in;

void main() {
  uint total = scanBlock(0u);
  if (gl_LocalInvocationID.x == 0u) gridStart[params.bucket_count] = total;
  memoryBarrierBuffer();
  barrier();
  uint rounds = (params.point_count + kScanLocalSize - 1u) / kScanLocalSize;
  for (uint k = 0u; k < rounds; ++k) {
    uint i = k * kScanLocalSize + gl_LocalInvocationID.x;
    if (i < params.point_count) scatterPoint(i);
  }
  memoryBarrierBuffer();
  barrier();
  for (uint k = 0u; k < rounds; ++k) {
    uint i = k * kScanLocalSize + gl_LocalInvocationID.x;
    if (i < params.point_count) rankPoint(i, pairAnchor[i].xyz);
  }
}
