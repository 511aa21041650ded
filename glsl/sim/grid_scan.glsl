// Work-group prefix sums (kScanLocalSize invocations), shared by grid_scan.comp and grid_build.comp.
// Integer sums: exact, and independent of thread timing. By default they scan the hash grid's bucket
// counts; a kernel that defines PAIR_SCAN scans the self-collision lists' per-point counts instead.
#pragma once

#include "pairs.glsl"

#ifndef PAIR_SCAN
#define PAIR_SCAN 0
#endif
#if PAIR_SCAN
#define SCAN_IN gridCounts
#define SCAN_OUT pairStart
#define SCAN_LENGTH params.point_count
#else
#define SCAN_IN gridCounts
#define SCAN_OUT gridStart
#define SCAN_LENGTH params.bucket_count
#endif
#define SCAN_BLOCKS ((SCAN_LENGTH + kScanBlock - 1u) / kScanBlock)

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

// Block `block` of kScanBlock counts: each invocation sums kScanItems consecutive counts (and zeroes
// them, so the next grid build counts from zero), the work-group scan combines the invocations. Writes
// block-local exclusive prefixes to SCAN_OUT and returns the block's total.
uint scanBlock(uint block) {
  uint n = SCAN_LENGTH;
  uint first = block * kScanBlock + gl_LocalInvocationID.x * kScanItems;
  uint counts[kScanItems];
  uint sum = 0u;
  for (uint k = 0u; k < kScanItems; ++k) {
    uint b = first + k;
    counts[k] = b < n ? SCAN_IN[b] : 0u;
    if (b < n) SCAN_IN[b] = 0u;
    sum += counts[k];
  }
  uint total;
  uint prefix = groupExclusiveScan(sum, total);
  for (uint k = 0u; k < kScanItems; ++k) {
    uint b = first + k;
    if (b < n) SCAN_OUT[b] = prefix;
    prefix += counts[k];
  }
  return total;
}
