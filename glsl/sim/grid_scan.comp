// Exclusive prefix sum of the bucket counts into gridStart for more than kScanBlock buckets, in three
// dispatches (SCAN_STAGE):
//   0  one work group per block of kScanBlock buckets: block-local prefixes and the block totals;
//   1  a single work group scans the block totals (in chunks) and writes the grand total;
//   2  one work group per block adds its block's offset.
// Up to kScanBlock buckets grid_build.comp does the whole build in one dispatch instead.
#include "grid_scan.glsl"

#ifndef SCAN_STAGE
#define SCAN_STAGE 0
#endif

layout(local_size_x = kScanLocalSize) in;

void main() {
#if SCAN_STAGE == 0
  uint total = scanBlock(gl_WorkGroupID.x);
  if (gl_LocalInvocationID.x == 0u) gridBlocks[gl_WorkGroupID.x] = total;
#elif SCAN_STAGE == 1
  uint carry = 0u;
  for (uint base = 0u; base < params.scan_blocks; base += kScanLocalSize) {
    uint b = base + gl_LocalInvocationID.x;
    uint value = b < params.scan_blocks ? gridBlocks[b] : 0u;
    uint total;
    uint prefix = groupExclusiveScan(value, total);
    if (b < params.scan_blocks) gridBlocks[b] = carry + prefix;
    carry += total;
  }
  if (gl_LocalInvocationID.x == 0u) gridStart[params.bucket_count] = carry;
#else
  uint offset = gridBlocks[gl_WorkGroupID.x];
  uint first = gl_WorkGroupID.x * kScanBlock + gl_LocalInvocationID.x * kScanItems;
  for (uint k = 0u; k < kScanItems; ++k) {
    uint b = first + k;
    if (b < params.bucket_count) gridStart[b] += offset;
  }
#endif
}
