/*
 * The binned light lists shared by the tile and cluster techniques (tiled.cl, tiled_single.cl,
 * clustered.cl): the per-bin light test, the count/fill append of the paper's grid (per-bin
 * count + offset, one index list), and the shading loop over one bin's list.
 *
 * The includer defines TILE_W, TILE_H, TS_MODEL and TS_CULL and includes gbuffer.h first.
 */
#ifndef TS_LIGHT_LISTS_H
#define TS_LIGHT_LISTS_H

/* Whether the light sphere (c, r) may reach the pixels of tile (tx, ty) whose geometry depth lies
 * in zr = (zmin, zmax): the depth-range test, then the configured per-tile test (TS_CULL). The
 * caller has already placed the tile inside the light's screen rectangle. */
static inline int ts_light_meets_bin(float3 c, float r, int tx, int ty, float2 zr, float4 camera) {
  int width = (int)camera.z, height = (int)camera.w;
  if (!ts_sphere_meets_depth_range(c, r, zr.x, zr.y)) return 0;
  return ts_sphere_meets_tile(c, r, TS_CULL, tx * TILE_W, ty * TILE_H,
                              min((tx + 1) * TILE_W, width), min((ty + 1) * TILE_H, height), width,
                              height, camera.x, camera.y, zr.x, zr.y);
}

/* fill == 0: counts `light` into bin_count[bin].  fill == 1: appends it to the bin's list at
 * bin_offset[bin] + a slot from bin_cursor (zeroed before the pass). Entries past `capacity` are
 * not written; the host sees the total, grows the list and runs the frame again. */
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

#if TS_LANES == 1
/* The summed contributions of the `n` lights listed from `begin` at surface s. */
static inline float3 ts_shade_bin(const ts_surface *s, uint begin, uint n, uint capacity,
                                  __global const uint *bin_lights,
                                  __global const float4 *light_pos_range,
                                  __global const float4 *light_color) {
  float3 sum = (float3)(0.0f);
  n = ts_bin_written(begin, n, capacity);
  for (uint k = 0; k < n; ++k) {
    uint light = bin_lights[begin + k];
    sum += ts_shade_light(s, light_pos_range[light], light_color[light], TS_MODEL);
  }
  return sum;
}
#endif

#endif
