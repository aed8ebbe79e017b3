/*
 * Multi-kernel tiled deferred shading (Olsson & Assarsson 2011, the CUDA variant), host side in
 * src/techniques/tiled.cpp. Per frame:
 *   1. tile_depth_bounds  one work-group per tile: min/max linear depth of the tile's geometry
 *   2. light_tile_rects   per light: screen-space tile rectangle of its volume (sphere or cone);
 *                         lights of many tiles listed as big
 *      bin_lights, bin_big_lights (COUNT)  per light (a work-item each; a work-group each for the
 *                         big ones): each tile of its rectangle tested against the tile's depth
 *                         range, tile_count[t]++
 *      exclusive_scan     tile_offset = exclusive prefix sum of tile_count; total
 *      bin_lights, bin_big_lights (FILL)  the same traversal, writing light indices into the
 *                         tile light list
 *      sort_bins          each tile's list in light index order (the fill's order is the
 *                         scheduler's: sorted, a pixel sums its lights alike on every run)
 *   3. shade_tiled        per pixel: loop over its tile's list with the one shading function
 * The grid is the paper's: per-tile (offset, count) + tile light index list + the global light
 * list (the frame's light buffers).
 *
 * Build-time constants: TILE_W, TILE_H (pixels), TS_CULL (per-tile test, culling.h), TS_LANES
 * (shading in lanes on CPU devices, lanes.h), the scene's features and the G-buffer layout
 * (gbuffer.h). Directional lights are not binned: every pixel adds them after its tile's list.
 */
#include "gbuffer.h"

#ifndef TS_CULL
#define TS_CULL TS_CULL_RECT
#endif
#include "light_lists.h"

/* ---- 1. depth bounds ---------------------------------------------------------------------- */

/* Background pixels (depth 0) are left out: they would stretch the range to the far plane.
 * gb_depth holds `samples` planes of width x height (sample-major; 1 without MSAA: tiled-forward-
 * prez's pre-pass with --msaa gives one per sample), and a tile's range covers every sample of
 * its pixels, so no sample's surface is culled.
 * Depths are compared as floats in local memory, so no integer-atomic trick (which only orders
 * non-negative floats) is involved.
 * Output per tile: (zmin, near_max, far_min, zmax). With TS_DEPTH_SPLIT (the depth-split knob),
 * the range is split at its middle and each half shrunk to the depths it holds — [zmin,
 * near_max] and [far_min, zmax] — so a tile with a foreground edge in front of a far background
 * (a depth discontinuity) does not take every light in between (the 2.5D culling idea of Harada
 * et al.). Without it, the second range is empty and the first is [zmin, zmax]. An empty tile
 * gets two empty ranges (min > max). */
__kernel void tile_depth_bounds(__global const float *gb_depth, int width, int height,
                                int samples, __global float4 *tile_depth) {
  __local float lmin[256];
  __local float lmax[256];
  int tiles_x = (width + TILE_W - 1) / TILE_W;
  int tile = get_group_id(0);
  int tx = tile % tiles_x, ty = tile / tiles_x;
  int lid = get_local_id(0), lsize = get_local_size(0);
  float4 result = (float4)(FLT_MAX, 0.0f, FLT_MAX, 0.0f);
  float zmid = 0.0f;
  /* Pass 0: the whole range; pass 1 (split): the near half's max and the far half's min. */
  for (int pass = 0; pass < (TS_DEPTH_SPLIT ? 2 : 1); ++pass) {
    float lo = FLT_MAX, hi = 0.0f;
    for (int i = lid; i < TILE_W * TILE_H * samples; i += lsize) {
      int p = i % (TILE_W * TILE_H), k = i / (TILE_W * TILE_H);
      int x = tx * TILE_W + p % TILE_W, y = ty * TILE_H + p / TILE_W;
      if (x < width && y < height) {
        float z = gb_depth[(size_t)k * width * height + y * width + x];
        if (pass == 0 && z > 0.0f) {
          lo = fmin(lo, z);
          hi = fmax(hi, z);
        } else if (pass == 1 && z > 0.0f) {
          if (z <= zmid) hi = fmax(hi, z); /* near half: its max */
          else lo = fmin(lo, z);           /* far half: its min */
        }
      }
    }
    lmin[lid] = lo;
    lmax[lid] = hi;
    barrier(CLK_LOCAL_MEM_FENCE);
    for (int s = lsize / 2; s > 0; s >>= 1) {
      if (lid < s) {
        lmin[lid] = fmin(lmin[lid], lmin[lid + s]);
        lmax[lid] = fmax(lmax[lid], lmax[lid + s]);
      }
      barrier(CLK_LOCAL_MEM_FENCE);
    }
    float rmin = lmin[0], rmax = lmax[0];
    barrier(CLK_LOCAL_MEM_FENCE); /* everyone has read them before the next pass writes */
    if (pass == 0) {
      result = (float4)(rmin, rmax, FLT_MAX, 0.0f);
      zmid = 0.5f * (rmin + rmax);
    } else if (rmin <= result.y) { /* the far half holds depths: split */
      result = (float4)(result.x, rmax, rmin, result.y);
    }
  }
  if (lid == 0) tile_depth[tile] = result;
}

/* ---- 2. light binning --------------------------------------------------------------------- */

/* Per light: its volume's tile rectangle, then the rectangle's tiles tested against their depth
 * ranges, twice (count, then fill). One work-item per light, not the first form's work-group of
 * 64 per light, whose every work-item computed the volume's screen bounds (1.8 us per light and
 * pass on PoCL at 64k lights; bench/RESULTS.md, "Binning at 1k-256k lights"). */

static inline int rect_tiles(int4 r) { return r.z < r.x ? 0 : (r.z - r.x + 1) * (r.w - r.y + 1); }

/* light_tile_rects: per light the tile rectangle (x0, y0, x1, y1) of its volume's screen bounds
 * (empty: x1 < x0), computed once for both passes, in a kernel of its own: straight-line code
 * that the CPU compiler vectorises across work-items (inside the binning loop it cost 3x more).
 * A light of more than `alone_tiles` tiles is appended to big_lights (big_count zeroed by the
 * host first; their order does not matter: sort_bins orders every list) and binned by a whole
 * work-group (bin_big_lights), so on a GPU one screen-covering light does not hold a work-item,
 * and its wave, for every tile. The host sets the threshold per device (TileLightGrid). */
__kernel void light_tile_rects(__global const float4 *light_pos_range,
                               __global const float4 *light_spot, int light_count, float4 camera,
                               float znear, int alone_tiles, __global int4 *light_rect,
                               __global uint *big_lights, __global uint *big_count) {
  int light = get_global_id(0);
  if (light >= light_count) return;
  ts_light_volume v = ts_load_light_volume(light_pos_range, light_spot, (uint)light);
  int x0, y0, x1, y1;
  int on = ts_light_tile_rect(&v, camera, znear, &x0, &y0, &x1, &y1);
  int4 r = on ? (int4)(x0, y0, x1, y1) : (int4)(0, 0, -1, -1);
  light_rect[light] = r;
  if (rect_tiles(r) > alone_tiles) big_lights[atomic_inc(big_count)] = (uint)light;
}

/* Tile (tx, ty) of light volume v's rectangle: tested against the tile's depth ranges, then
 * counted (fill == 0) or appended (fill == 1) by ts_bin_light. */
static inline void bin_light_tile(const ts_light_volume *v, uint light, int tx, int ty,
                                  int tiles_x, float4 camera, __global const float4 *tile_depth,
                                  int fill, __global uint *tile_count,
                                  __global const uint *tile_offset, __global uint *tile_cursor,
                                  __global uint *tile_lights, uint capacity) {
  int tile = ty * tiles_x + tx;
  if (ts_light_meets_split_bin(v, tx, ty, tile_depth[tile], camera))
    ts_bin_light(light, tile, fill, tile_count, tile_offset, tile_cursor, tile_lights, capacity);
}

/* bin_lights: one work-item per light of at most `alone_tiles` tiles, which tests them all.
 * No barrier and no local memory: on PoCL a kernel with a barrier (a local queue of the big
 * lights, the first form of this split) binned 3.5x slower. */
__kernel void bin_lights(__global const float4 *light_pos_range,
                         __global const float4 *light_spot, int light_count, float4 camera,
                         int alone_tiles, __global const int4 *light_rect,
                         __global const float4 *tile_depth, int fill, __global uint *tile_count, __global const uint *tile_offset,
                         __global uint *tile_cursor, __global uint *tile_lights, uint capacity) {
  int light = get_global_id(0);
  if (light >= light_count) return;
  int4 r = light_rect[light];
  int n = rect_tiles(r);
  if (n == 0 || n > alone_tiles) return;
  int tiles_x = ((int)camera.z + TILE_W - 1) / TILE_W;
  ts_light_volume v = ts_load_light_volume(light_pos_range, light_spot, (uint)light);
  for (int ty = r.y; ty <= r.w; ++ty)
    for (int tx = r.x; tx <= r.z; ++tx)
      bin_light_tile(&v, (uint)light, tx, ty, tiles_x, camera, tile_depth, fill, tile_count,
                     tile_offset, tile_cursor, tile_lights, capacity);
}

/* bin_big_lights: the lights above `alone_tiles`, one at a time per work-group (a fixed number
 * of groups, as many as the host launches, striding over the list), its work-items sharing the
 * light's tiles. */
__kernel void bin_big_lights(__global const float4 *light_pos_range,
                             __global const float4 *light_spot, float4 camera,
                             __global const int4 *light_rect, __global const uint *big_lights,
                             __global const uint *big_count, __global const float4 *tile_depth,
                             int fill, __global uint *tile_count, __global const uint *tile_offset,
                             __global uint *tile_cursor, __global uint *tile_lights,
                             uint capacity) {
  int tiles_x = ((int)camera.z + TILE_W - 1) / TILE_W;
  uint big = big_count[0];
  for (uint b = get_group_id(0); b < big; b += get_num_groups(0)) {
    uint light = big_lights[b];
    int4 r = light_rect[light];
    int w = r.z - r.x + 1, n = rect_tiles(r);
    ts_light_volume v = ts_load_light_volume(light_pos_range, light_spot, light);
    for (int i = get_local_id(0); i < n; i += get_local_size(0))
      bin_light_tile(&v, light, r.x + i % w, r.y + i / w, tiles_x, camera, tile_depth, fill,
                     tile_count, tile_offset, tile_cursor, tile_lights, capacity);
  }
}

/* exclusive_scan: tile_offset = exclusive prefix sum of tile_count (shared with clustered.cl). */
#include "scan.h"
/* sort_bins: each tile's list in light index order, the same on every run (shared too). */
#include "sort_bins.h"

/* ---- 3. shading --------------------------------------------------------------------------- */

#if TS_LANES == 1
/* One work-item per pixel. */
__kernel void shade_tiled(float4 camera, float4 ambient, TS_GBUFFER_PARAMS, TS_LIGHT_PARAMS,
                          TS_DIRECTIONAL_PARAMS, __global const uint *tile_count,
                          __global const uint *tile_offset, __global const uint *tile_lights,
                          uint capacity, __global float4 *image) {
  int x = get_global_id(0), y = get_global_id(1);
  int width = (int)camera.z, height = (int)camera.w;
  if (x >= width || y >= height) return;
  ts_surface s;
  float3 sum = (float3)(0.0f);
  if (ts_load_surface(x, y, camera, ambient, TS_GBUFFER_ARGS, &s)) {
    int tile = group_tile(width);
    sum = ts_shade_bin(&s, tile_offset[tile], tile_count[tile], capacity, tile_lights,
                       TS_LIGHT_ARGS);
    sum += ts_shade_directionals(&s, TS_DIRECTIONAL_ARGS) + s.base;
  }
  image[y * width + x] = (float4)(sum, 0.0f);
}
#else
#include "lanes.h"
/* In lanes (kernels/lanes.h): every work-item decodes its pixel, then one work-item per TS_LANES
 * pixels runs the tile's list (and the directional lights) for all of them. `soa`: TS_LANE_PLANES
 * floats per pixel slot of local memory, from the host. */
__kernel void shade_tiled(float4 camera, float4 ambient, TS_GBUFFER_PARAMS, TS_LIGHT_PARAMS,
                          TS_DIRECTIONAL_PARAMS, __global const uint *tile_count,
                          __global const uint *tile_offset, __global const uint *tile_lights,
                          uint capacity, __global float4 *image, __local float *soa) {
  int x = get_global_id(0), y = get_global_id(1);
  int width = (int)camera.z, height = (int)camera.w;
  int inside = x < width && y < height;
  int tile = group_tile(width);
  uint begin = tile_offset[tile];
  uint n = ts_bin_written(begin, tile_count[tile], capacity);
  int lights = (int)n + ts_directional_count(dir_light_count);
  ts_surface s;
  /* A tile without lights (most of them, with small lights) skips the trip through local
   * memory (1.7x faster shading of the atrium's small lights on PoCL). Every item still reaches
   * both barriers: a uniform early return before them corrupted PoCL's heap. */
  int lit = lights > 0 ? ts_lanes_store_pixel(soa, x, y, inside, camera, ambient, TS_GBUFFER_ARGS, &s)
                       : inside && ts_load_surface(x, y, camera, ambient, TS_GBUFFER_ARGS, &s);
  barrier(CLK_LOCAL_MEM_FENCE);
  int first = ts_lanes_first_slot();
  if (lights > 0 && first >= 0) {
    ts_lane_surface lanes = ts_lanes_get(soa, ts_lane_slots(), first);
    ts_lane_rgb sum = {(TS_LANE)0.0f, (TS_LANE)0.0f, (TS_LANE)0.0f};
    for (uint k = 0; k < n; ++k)
      ts_lanes_add_light(&sum, &lanes, TS_LIGHT_ARGS, tile_lights[begin + k]);
    ts_lanes_add_directionals(&sum, &lanes, TS_DIRECTIONAL_ARGS);
    ts_lanes_put_rgb(soa, ts_lane_slots(), 0, first, &sum);
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  if (!inside) return;
  image[y * width + x] = (float4)(ts_lanes_pixel_colour(soa, lit, lights > 0, &s), 0.0f);
}
#endif

/* ---- --msaa: the edges' samples (kernels/msaa_edges.h) ----------------------------------- */

#include "msaa_edges.h"

#if TS_LANES == 1
/* shade_tiled has shaded every pixel's sample 0 (the planes' first); here each edge pixel
 * (msaa_edge_mask) shades its samples 1..samples-1 with its tile's list as shade_tiled shades a
 * pixel, adds them to sample 0's shade and divides by the samples (equal weights: OpenGL's box
 * resolve, the reference's averageSamples). One work-item per pixel, the others return at once;
 * built without lanes only (kernels/gbuffer.h's scalar shading; the host builds tiled.cl a
 * second time for it when shade_tiled has lanes): edge pixels are few and scattered over a
 * tile, a poor fit for lanes of neighbouring pixels. plane_bytes as
 * msaa_edge_mask's: a plane's element type is not always one pixel (fp16's half: a quarter). */
__kernel void shade_tiled_edge_samples(float4 camera, float4 ambient, TS_GBUFFER_PARAMS,
                                       TS_LIGHT_PARAMS, TS_DIRECTIONAL_PARAMS,
                                       __global const uint *tile_count,
                                       __global const uint *tile_offset,
                                       __global const uint *tile_lights, uint capacity,
                                       __global const uchar *edge, int samples,
                                       int4 plane_bytes, __global float4 *image) {
  int x = get_global_id(0), y = get_global_id(1);
  int width = (int)camera.z, height = (int)camera.w;
  if (x >= width || y >= height) return;
  size_t i = (size_t)y * (size_t)width + (size_t)x, plane = (size_t)width * (size_t)height;
  if (!edge[i]) return;
  int tile = (y / TILE_H) * ((width + TILE_W - 1) / TILE_W) + x / TILE_W;
  uint begin = tile_offset[tile];
  uint n = ts_bin_written(begin, tile_count[tile], capacity);
  float3 sum = image[i].xyz;
  for (int k = 1; k < samples; ++k) {
    size_t o = (size_t)k * plane;
    ts_surface s;
    if (TS_LOAD_SAMPLE_SURFACE(x, y, camera, ambient, o, plane_bytes, &s)) {
      float3 shade = (float3)(0.0f);
      for (uint l = 0; l < n; ++l) shade += ts_shade_punctual(&s, TS_LIGHT_ARGS, tile_lights[begin + l]);
      shade += ts_shade_directionals(&s, TS_DIRECTIONAL_ARGS) + s.base;
      sum += shade;
    }
  }
  image[i] = (float4)(sum / (float)samples, 0.0f);
}
#endif
