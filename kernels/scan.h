/*
 * exclusive_scan: the one prefix-sum kernel of the binning techniques (tiled.cl, clustered.cl
 * include it), turning per-bin light counts into list offsets.
 */
#ifndef TS_SCAN_H
#define TS_SCAN_H

/* Exclusive prefix sum of n counts by a single work-group, total[0] = sum. The bins are tiles
 * (~10^4) or clusters (tiles x slices, ~10^5): one group sweeping in chunks is enough, needs no
 * second pass for the block sums and keeps the order deterministic. The group has a power of two
 * of at most SCAN_MAX_GROUP work-items, as many as the device allows (src/cl/work_group.h). */
#define SCAN_MAX_GROUP 256
__kernel void exclusive_scan(__global const uint *count, int n, __global uint *offset,
                             __global uint *total) {
  __local uint tmp[SCAN_MAX_GROUP];
  const int group = (int)get_local_size(0);
  int lid = get_local_id(0);
  uint carry = 0;
  for (int base = 0; base < n; base += group) {
    int i = base + lid;
    uint v = i < n ? count[i] : 0u;
    tmp[lid] = v;
    barrier(CLK_LOCAL_MEM_FENCE);
    /* Hillis-Steele inclusive scan in local memory. */
    for (int s = 1; s < group; s <<= 1) {
      uint add = lid >= s ? tmp[lid - s] : 0u;
      barrier(CLK_LOCAL_MEM_FENCE);
      tmp[lid] += add;
      barrier(CLK_LOCAL_MEM_FENCE);
    }
    if (i < n) offset[i] = carry + tmp[lid] - v;
    uint chunk_sum = tmp[group - 1];
    barrier(CLK_LOCAL_MEM_FENCE);
    carry += chunk_sum;
  }
  if (lid == 0) total[0] = carry;
}

#endif
