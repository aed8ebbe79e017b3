/*
 * The binned light lists shared by the tile and cluster techniques (tiled.cl, tiled_single.cl,
 * clustered.cl): the per-bin light test, the count/fill append of the paper's grid (per-bin
 * count + offset, one index list), and the shading loop over one bin's list.
 *
 * The includer defines TILE_W, TILE_H and TS_CULL and includes gbuffer.h first.
 */
#ifndef TS_LIGHT_LISTS_H
#define TS_LIGHT_LISTS_H

/* Whether light volume v (kernels/culling.h) may reach the pixels of tile (tx, ty) whose
 * geometry depth lies in zr = (zmin, zmax): the depth-range test, then the per-tile test (TS_CULL;
 * cones always). The caller has already placed the tile inside the light's screen rectangle. */
static inline int ts_light_meets_bin(const ts_light_volume *v, int tx, int ty, float2 zr,
                                     float4 camera) {
  int width = (int)camera.z, height = (int)camera.w;
  if (!ts_light_meets_depth_range(v, zr.x, zr.y)) return 0;
  return ts_light_meets_tile(v, TS_CULL, tx * TILE_W, ty * TILE_H,
                             min((tx + 1) * TILE_W, width), min((ty + 1) * TILE_H, height), width,
                             height, camera.x, camera.y, zr.x, zr.y);
}

/* The same for a tile whose geometry depths lie in two ranges zr = (zmin, near_max, far_min,
 * zmax) (kernels/tiled.cl, tile_depth_bounds; the second is empty when not split). Without
 * the knob the second test is compiled out: its run-time check cost ~1 ms of binning per frame
 * on street/many at 1280x720 (PoCL). */
static inline int ts_light_meets_split_bin(const ts_light_volume *v, int tx, int ty, float4 zr,
                                           float4 camera) {
#if TS_DEPTH_SPLIT
  return ts_light_meets_bin(v, tx, ty, zr.xy, camera) ||
         (zr.z <= zr.w && ts_light_meets_bin(v, tx, ty, zr.zw, camera));
#else
  return ts_light_meets_bin(v, tx, ty, zr.xy, camera);
#endif
}

/* The tile rectangle (x0, y0)-(x1, y1) of light volume v; 0 when it misses the screen. */
static inline int ts_light_tile_rect(const ts_light_volume *v, float4 camera, float znear,
                                     int *x0, int *y0, int *x1, int *y1) {
  float4 b = ts_light_ndc_bounds(v, znear, camera.x, camera.y);
  return ts_ndc_bounds_to_tiles(b, (int)camera.z, (int)camera.w, TILE_W, TILE_H, x0, y0, x1, y1);
}

/* fill == 0: counts `light` into bin_count[bin].  fill == 1: appends it to the bin's list at
 * bin_offset[bin] + a slot from bin_cursor (zeroed before the pass), in whatever order the
 * work-groups run: sort_bins (sort_bins.h) then puts each list in light index order. Entries past
 * `capacity` are not written; the host sees the total, grows the list and runs the frame again. */
static inline void ts_bin_light(uint light, int bin, int fill, __global uint *bin_count,
                                __global const uint *bin_offset, __global uint *bin_cursor,
                                __global uint *bin_lights, uint capacity) {
  if (!fill) {
    atomic_inc(&bin_count[bin]);
  } else {
    uint pos = bin_offset[bin] + atomic_inc(&bin_cursor[bin]);
    if (pos < capacity) bin_lights[pos] = light;
  }
}

/* How many of a bin's `n` entries from `begin` were written: a list that overflowed the buffer
 * is read only as far as it was written (that frame is re-run). */
static inline uint ts_bin_written(uint begin, uint n, uint capacity) {
  return begin >= capacity ? 0u : min(n, capacity - begin);
}

/* The tile of this work-group, for shading kernels whose host launches groups that divide the
 * tile (tileDividingGroup): the compiler sees one tile (one light list) per work-group and keeps
 * its loads uniform (1.7x faster shading on PoCL than deriving it from x/y). */
static inline int group_tile(int width) {
  return (int)(get_group_id(1) * get_local_size(1) / TILE_H) * ((width + TILE_W - 1) / TILE_W) +
         (int)(get_group_id(0) * get_local_size(0) / TILE_W);
}

#if TS_LANES == 1
/* The summed contributions of the `n` lights listed from `begin` at surface s. */
static inline float3 ts_shade_bin(const ts_surface *s, uint begin, uint n, uint capacity,
                                  __global const uint *bin_lights, TS_LIGHT_PARAMS) {
  float3 sum = (float3)(0.0f);
  n = ts_bin_written(begin, n, capacity);
  for (uint k = 0; k < n; ++k) sum += ts_shade_punctual(s, TS_LIGHT_ARGS, bin_lights[begin + k]);
  return sum;
}
#endif

#endif
