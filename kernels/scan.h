/*
 * exclusive_scan: the one prefix-sum kernel of the binning techniques (tiled.cl, clustered.cl
 * include it), turning per-bin light counts into list offsets.
 */
#ifndef TS_SCAN_H
#define TS_SCAN_H

/* Exclusive prefix sum of n counts by a single work-group, total[0] = sum. The bins are tiles
 * (~10^4) or clusters (tiles x slices, ~10^5): one group is enough, needs no second pass for the
 * block sums and keeps the order deterministic. Each work-item sums a contiguous chunk of the
 * counts, the chunk sums are scanned in local memory (Hillis-Steele), and each work-item writes
 * its chunk's offsets: two reads of the counts in all, where a scan of the whole array in
 * group-sized steps took two barriers per step for each of log2(group) steps (0.6-1 ms for 57600
 * clusters on PoCL). The group has a power of two of at most SCAN_MAX_GROUP work-items, as many
 * as the device allows (src/cl/work_group.h). */
#define SCAN_MAX_GROUP 256
__kernel void exclusive_scan(__global const uint *count, int n, __global uint *offset,
                             __global uint *total) {
  __local uint tmp[SCAN_MAX_GROUP];
  const int group = (int)get_local_size(0);
  int lid = get_local_id(0);
  int chunk = (n + group - 1) / group;
  int begin = min(lid * chunk, n), end = min(begin + chunk, n);
  uint sum = 0u;
  for (int i = begin; i < end; ++i) sum += count[i];
  tmp[lid] = sum;
  barrier(CLK_LOCAL_MEM_FENCE);
  for (int s = 1; s < group; s <<= 1) {
    uint add = lid >= s ? tmp[lid - s] : 0u;
    barrier(CLK_LOCAL_MEM_FENCE);
    tmp[lid] += add;
    barrier(CLK_LOCAL_MEM_FENCE);
  }
  uint running = tmp[lid] - sum; /* the counts before this chunk */
  for (int i = begin; i < end; ++i) {
    uint c = count[i];
    offset[i] = running;
    running += c;
  }
  if (lid == group - 1) total[0] = tmp[lid];
}

#endif
