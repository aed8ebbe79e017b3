/*
 * sort_bins: puts every bin's light list in light index order after the fill pass (tiled.cl,
 * clustered.cl include it), so that a pixel sums its lights in the same order on every run.
 * The fill appends with an atomic cursor per bin (light_lists.h, ts_bin_light): the set of a
 * bin's lights is fixed, their order is whatever the scheduler made of the work-groups, and a
 * float sum in another order differs in its last bits. Sorting gives one order whatever the
 * device's scheduling; light indices in a bin are distinct, so the sorted list is unique.
 */
#ifndef TS_SORT_BINS_H
#define TS_SORT_BINS_H

/* Shell sort gaps (Ciura's, then x2.25), largest first; the sort is correct for any list length
 * (the last gap is 1, an insertion sort), the larger gaps keep a long shuffled list O(n^1.3). */
__constant uint ts_sort_gaps[] = {1149241u, 510774u, 227011u, 100894u, 44842u, 19930u, 8858u,
                                  3937u,    1750u,   701u,    301u,    132u,   57u,    23u,
                                  10u,      4u,      1u};

/* Sorts list[0, n) ascending in place. */
static inline void ts_sort_list(__global uint *list, uint n) {
  /* A nearly sorted list (what one work-item per light leaves: each tile gets its lights in
   * about the order the work-groups ran) costs an insertion sort about one pass; past a budget
   * of moves the shuffled rest goes to the Shell sort (which is correct from any state). */
  uint i, moves = 0u, budget = 4u * n;
  for (i = 1; i < n && moves <= budget; ++i) {
    uint v = list[i], j = i;
    for (; j >= 1 && list[j - 1] > v; --j) list[j] = list[j - 1];
    list[j] = v;
    moves += i - j;
  }
  if (i >= n) return;
  for (int g = 0; g < (int)(sizeof(ts_sort_gaps) / sizeof(ts_sort_gaps[0])); ++g) {
    uint gap = ts_sort_gaps[g];
    for (i = gap; i < n; ++i) {
      uint v = list[i], j = i;
      for (; j >= gap && list[j - gap] > v; j -= gap) list[j] = list[j - gap];
      list[j] = v;
    }
  }
}

/* One work-item per bin, in place in the list buffer. A list that overflowed the buffer is
 * sorted only as far as it was written (that frame is re-run). Work-items sort independent
 * segments, so the work needs no local memory and no barrier: the fill left most lists nearly
 * in order on CPU devices, where insertion sort passes are linear. */
__kernel void sort_bins(__global const uint *bin_count, __global const uint *bin_offset, int bins,
                        __global uint *bin_lights, uint capacity) {
  int bin = get_global_id(0);
  if (bin >= bins) return;
  uint begin = bin_offset[bin];
  ts_sort_list(bin_lights + begin, ts_bin_written(begin, bin_count[bin], capacity));
}

#endif
