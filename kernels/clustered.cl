/*
 * Clustered deferred shading (Olsson, Billeter & Assarsson 2012), host side in
 * src/techniques/clustered.cpp. A cluster is a screen tile (TILE_W x TILE_H pixels) times one of
 * SLICES depth slices; slices are exponential in view depth between the nearest and the farthest
 * geometry depth of the frame (zn, zf): slice k spans zn*(zf/zn)^(k/S) .. zn*(zf/zn)^((k+1)/S).
 * Per frame:
 *   1. frame_depth_range     min/max geometry depth of the whole frame: the slicing's zn, zf
 *      cluster_depth_bounds  one work-group per tile: each geometry pixel's slice (the cluster
 *                            key, stored per pixel), and per cluster its geometry depth min/max
 *                            and pixel count
 *   2. bin_clusters (COUNT)  per light: its tile rectangle x its slice range, each cluster tested
 *                            against the cluster's geometry depth range (and TS_CULL),
 *                            cluster_count[c]++
 *      exclusive_scan        cluster_offset = exclusive prefix sum of cluster_count; total
 *      bin_clusters (FILL)   the same traversal, writing light indices into the cluster lists
 *   3. shade_clustered       per pixel: loop over its cluster's list with the one shading function
 * Cluster c = tile * SLICES + slice (a tile's slices are adjacent). Clusters without geometry have
 * an empty depth range (min > max) and so get no lights.
 *
 * Build-time constants: TILE_W, TILE_H (pixels), SLICES, TS_CULL (per-cluster test, culling.h),
 * the scene's features and the G-buffer layout (gbuffer.h).
 */
#include "gbuffer.h"

#ifndef TS_CULL
#define TS_CULL TS_CULL_RECT
#endif
#include "light_lists.h"

/* The bit pattern of FLT_MAX: the "empty" minimum of the integer-atomic depth reductions. */
#define TS_DEPTH_EMPTY_MIN 0x7f7fffffu

/* Slicing from the frame's geometry range rather than the camera's znear/zfar: the camera range
 * (e.g. 0.1..500) would spend most slices on depths where no geometry is; the frame range costs
 * one extra read of the depth plane. scale = SLICES / log(zf / zn); 0 for a flat or empty range
 * (everything then lands in slice 0). */
static inline float ts_slice_scale(float zn, float zf) {
  return zf > zn ? (float)SLICES / log(zf / zn) : 0.0f;
}

/* Slice of depth z, for zn <= z <= zf (callers guarantee it, so log never sees z <= 0). */
static inline int ts_depth_slice(float z, float zn, float scale) {
  float f = clamp(log(z / zn) * scale, 0.0f, (float)(SLICES - 1));
  return (int)f;
}

/* ---- 1. depth range and cluster bounds ---------------------------------------------------- */

/* min/max of the geometry depth (depth > 0; background excluded) into depth_range[0], [1] as
 * float bits (initialized to TS_DEPTH_EMPTY_MIN, 0 by the host). Integer atomic_min/max order
 * floats correctly here only because every depth compared is positive: positive IEEE floats sort
 * like their bit patterns read as unsigned integers. Grid-stride loop, local tree, one pair of
 * global atomics per work-group. */
__kernel void frame_depth_range(__global const float *gb_depth, int pixels,
                                __global uint *depth_range) {
  __local float lmin[256];
  __local float lmax[256];
  int lid = get_local_id(0), lsize = get_local_size(0);
  float zmin = FLT_MAX, zmax = 0.0f;
  for (int i = get_global_id(0); i < pixels; i += get_global_size(0)) {
    float z = gb_depth[i];
    if (z > 0.0f) {
      zmin = fmin(zmin, z);
      zmax = fmax(zmax, z);
    }
  }
  lmin[lid] = zmin;
  lmax[lid] = zmax;
  barrier(CLK_LOCAL_MEM_FENCE);
  for (int s = lsize / 2; s > 0; s >>= 1) {
    if (lid < s) {
      lmin[lid] = fmin(lmin[lid], lmin[lid + s]);
      lmax[lid] = fmax(lmax[lid], lmax[lid + s]);
    }
    barrier(CLK_LOCAL_MEM_FENCE);
  }
  if (lid == 0) {
    atomic_min(&depth_range[0], as_uint(lmin[0]));
    atomic_max(&depth_range[1], as_uint(lmax[0]));
  }
}

/* One work-group per tile. Each geometry pixel goes to its slice: the slice is stored per pixel
 * (shading and the host's light assignment read this key, so every user sees the same cluster,
 * whatever the rounding of log), and the slice's min/max depth and pixel count are reduced in
 * local memory with integer atomics -- valid only because depths are positive (see above).
 * Output per cluster: (zmin, zmax), empty: zmin > zmax (FLT_MAX, 0); its geometry pixel count.
 * Background pixels get the key 0xffff. */
__kernel void cluster_depth_bounds(__global const float *gb_depth, int width, int height,
                                   __global const uint *depth_range,
                                   __global float2 *cluster_depth,
                                   __global uint *cluster_pixels,
                                   __global ushort *pixel_slice) {
  __local uint lmin[SLICES];
  __local uint lmax[SLICES];
  __local uint lcount[SLICES];
  int tiles_x = (width + TILE_W - 1) / TILE_W;
  int tile = get_group_id(0);
  int tx = tile % tiles_x, ty = tile / tiles_x;
  int lid = get_local_id(0), lsize = get_local_size(0);
  for (int s = lid; s < SLICES; s += lsize) {
    lmin[s] = TS_DEPTH_EMPTY_MIN;
    lmax[s] = 0u;
    lcount[s] = 0u;
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  float zn = as_float(depth_range[0]), zf = as_float(depth_range[1]);
  float scale = ts_slice_scale(zn, zf);
  for (int i = lid; i < TILE_W * TILE_H; i += lsize) {
    int x = tx * TILE_W + i % TILE_W, y = ty * TILE_H + i / TILE_W;
    if (x < width && y < height) {
      float z = gb_depth[y * width + x];
      ushort key = (ushort)0xffff;
      if (z > 0.0f) {
        int s = ts_depth_slice(z, zn, scale);
        atomic_min(&lmin[s], as_uint(z));
        atomic_max(&lmax[s], as_uint(z));
        atomic_inc(&lcount[s]);
        key = (ushort)s;
      }
      pixel_slice[y * width + x] = key;
    }
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  for (int s = lid; s < SLICES; s += lsize) {
    int c = tile * SLICES + s;
    cluster_depth[c] = (float2)(as_float(lmin[s]), as_float(lmax[s]));
    cluster_pixels[c] = lcount[s];
  }
}

/* ---- 2. light binning --------------------------------------------------------------------- */

/* One work-group per light; its work-items share the clusters of the light's tile rectangle x
 * slice range. The slice range comes from the light volume's depth extent clipped to [zn, zf] (no
 * geometry lies outside it), widened by one slice each way: a pixel's slice and the light's are
 * computed by the same function, but log is not guaranteed monotonic in the last ulp, and the
 * extra clusters cost one depth-range test each. The decisive test is the cluster's geometry
 * depth range, as in tiled.cl, then TS_CULL against the tile with the cluster's range.
 * fill == 0: count into cluster_count; fill == 1: append to the cluster lists (ts_bin_light). */
__kernel void bin_clusters(__global const float4 *light_pos_range,
                           __global const float4 *light_spot, int light_count, float4 camera,
                           float znear, __global const uint *depth_range,
                           __global const float2 *cluster_depth, int fill,
                           __global uint *cluster_count, __global const uint *cluster_offset,
                           __global uint *cluster_cursor, __global uint *cluster_lights,
                           uint capacity) {
  int light = get_group_id(0);
  if (light >= light_count) return;
  int width = (int)camera.z;
  int tiles_x = (width + TILE_W - 1) / TILE_W;
  ts_light_volume v = ts_load_light_volume(light_pos_range, light_spot, (uint)light);
  float zn = as_float(depth_range[0]), zf = as_float(depth_range[1]);
  float zlo = fmax(-v.hi.z, zn), zhi = fmin(-v.lo.z, zf);
  if (!(zlo <= zhi)) return; /* no geometry in the volume's depth extent (or none at all) */
  int x0, y0, x1, y1;
  if (!ts_light_tile_rect(&v, camera, znear, &x0, &y0, &x1, &y1)) return;
  float scale = ts_slice_scale(zn, zf);
  int s0 = max(ts_depth_slice(zlo, zn, scale) - 1, 0);
  int s1 = min(ts_depth_slice(zhi, zn, scale) + 1, SLICES - 1);
  int depth_n = s1 - s0 + 1;
  int rect_w = x1 - x0 + 1, rect_tiles = rect_w * (y1 - y0 + 1);
  int n = rect_tiles * depth_n;
  for (int i = get_local_id(0); i < n; i += get_local_size(0)) {
    int t = i / depth_n, s = s0 + i % depth_n;
    int tx = x0 + t % rect_w, ty = y0 + t / rect_w;
    int cluster = (ty * tiles_x + tx) * SLICES + s;
    if (ts_light_meets_bin(&v, tx, ty, cluster_depth[cluster], camera))
      ts_bin_light((uint)light, cluster, fill, cluster_count, cluster_offset, cluster_cursor,
                   cluster_lights, capacity);
  }
}

/* exclusive_scan: cluster_offset = exclusive prefix sum of cluster_count (shared with tiled.cl). */
#include "scan.h"

/* ---- 3. shading --------------------------------------------------------------------------- */

__kernel void shade_clustered(float4 camera, float4 ambient, TS_GBUFFER_PARAMS, TS_LIGHT_PARAMS,
                              TS_DIRECTIONAL_PARAMS, __global const ushort *pixel_slice,
                              __global const uint *cluster_count,
                              __global const uint *cluster_offset,
                              __global const uint *cluster_lights, uint capacity,
                              __global float4 *image) {
  int x = get_global_id(0), y = get_global_id(1);
  int width = (int)camera.z, height = (int)camera.w;
  if (x >= width || y >= height) return;
  ts_surface s;
  float3 sum = (float3)(0.0f);
  if (ts_load_surface(x, y, camera, ambient, TS_GBUFFER_ARGS, &s)) {
    int tile = (y / TILE_H) * ((width + TILE_W - 1) / TILE_W) + x / TILE_W;
    int cluster = tile * SLICES + pixel_slice[y * width + x];
    sum = ts_shade_bin(&s, cluster_offset[cluster], cluster_count[cluster], capacity,
                       cluster_lights, TS_LIGHT_ARGS);
    sum += ts_shade_directionals(&s, TS_DIRECTIONAL_ARGS) + s.base;
  }
  image[y * width + x] = (float4)(sum, 0.0f);
}
