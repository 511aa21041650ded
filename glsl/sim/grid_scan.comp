// Exclusive prefix sum of the bucket counts into gridStart (or with PAIR_SCAN, of the lists' point
// counts into pairStart) for more than kScanBlock of them, in three dispatches (SCAN_STAGE):
//   0  one work group per block of kScanBlock counts: block-local prefixes and the block totals;
//   1  a single work group scans the block totals (in chunks) and writes the grand total;
//   2  one work group per block adds its block's offset.
// Stage 3 is the whole scan of up to kScanBlock counts in one work group. (Up to kScanBlock buckets
// grid_build.comp does the whole grid build in one dispatch.)
// Needs no springs, colliders or health flags (common.glsl: a storage block fewer each).
#define SIM_NO_SPRINGS
#define SIM_NO_COLLIDERS
#define SIM_NO_HEALTH
#ifndef SCAN_STAGE
#define SCAN_STAGE 0
#endif
#include "grid_scan.glsl"

layout(local_size_x = kScanLocalSize) in;

void main() {
#if SCAN_STAGE == 3
  uint total = scanBlock(0u);
  if (gl_LocalInvocationID.x == 0u) SCAN_OUT[SCAN_LENGTH] = total;
#elif SCAN_STAGE == 0
  uint total = scanBlock(gl_WorkGroupID.x);
  if (gl_LocalInvocationID.x == 0u) gridBlocks[gl_WorkGroupID.x] = total;
#elif SCAN_STAGE == 1
  uint carry = 0u;
  uint blocks = SCAN_BLOCKS;
  for (uint base = 0u; base < blocks; base += kScanLocalSize) {
    uint b = base + gl_LocalInvocationID.x;
    uint value = b < blocks ? gridBlocks[b] : 0u;
    uint total;
    uint prefix = groupExclusiveScan(value, total);
    if (b < blocks) gridBlocks[b] = carry + prefix;
    carry += total;
  }
  if (gl_LocalInvocationID.x == 0u) SCAN_OUT[SCAN_LENGTH] = carry;
#else
  uint offset = gridBlocks[gl_WorkGroupID.x];
  uint first = gl_WorkGroupID.x * kScanBlock + gl_LocalInvocationID.x * kScanItems;
  for (uint k = 0u; k < kScanItems; ++k) {
    uint b = first + k;
    if (b < SCAN_LENGTH) SCAN_OUT[b] += offset;
  }
#endif
}
