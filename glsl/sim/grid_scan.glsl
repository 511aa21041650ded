// Work-group prefix sums over the bucket counts (kScanLocalSize invocations), shared by grid_scan.comp
// and grid_build.comp. Integer sums: exact, and independent of thread timing.
#pragma once

#include "grid.glsl"

shared uint partial[kScanLocalSize];

// Hillis-Steele over the work group: returns the exclusive prefix of `value`, and the group's total.
uint groupExclusiveScan(uint value, out uint total) {
  uint t = gl_LocalInvocationID.x;
  partial[t] = value;
  barrier();
  for (uint offset = 1u; offset < kScanLocalSize; offset <<= 1) {
    uint add = t >= offset ? partial[t - offset] : 0u;
    barrier();
    partial[t] += add;
    barrier();
  }
  total = partial[kScanLocalSize - 1u];
  uint exclusive = partial[t] - value;
  barrier();  // partial[] may be reused by the caller's next scan
  return exclusive;
}

// Block `block` of kScanBlock buckets: each invocation sums kScanItems consecutive counts (and zeroes
// them, so the next substep counts from zero), the work-group scan combines the invocations. Writes
// block-local exclusive prefixes to gridStart and returns the block's total.
uint scanBlock(uint block) {
  uint n = params.bucket_count;
  uint first = block * kScanBlock + gl_LocalInvocationID.x * kScanItems;
  uint counts[kScanItems];
  uint sum = 0u;
  for (uint k = 0u; k < kScanItems; ++k) {
    uint b = first + k;
    counts[k] = b < n ? gridCounts[b] : 0u;
    if (b < n) gridCounts[b] = 0u;
    sum += counts[k];
  }
  uint total;
  uint prefix = groupExclusiveScan(sum, total);
  for (uint k = 0u; k < kScanItems; ++k) {
    uint b = first + k;
    if (b < n) gridStart[b] = prefix;
    prefix += counts[k];
  }
  return total;
}
