/*
 * Clustered deferred shading (Olsson, Billeter & Assarsson 2012), host side in
 * src/techniques/clustered.cpp. A cluster is a screen tile (TILE_W x TILE_H pixels) times one of
 * SLICES depth slices; slices are exponential in view depth between the nearest and the farthest
 * geometry depth of the frame (zn, zf): slice k spans zn*(zf/zn)^(k/S) .. zn*(zf/zn)^((k+1)/S).
 * Per frame:
 *   1. frame_depth_range     min/max geometry depth of the whole frame: the slicing's zn, zf
 *      pixel_slices          per pixel: its slice (the cluster key, stored per pixel)
 *      cluster_depth_bounds  one work-group per tile: per cluster its geometry depth min/max
 *                            and pixel count
 *   2. bin_clusters (COUNT)  per light: its tile rectangle x its slice range, each cluster tested
 *                            against the cluster's geometry depth range (and TS_CULL),
 *                            cluster_count[c]++
 *      exclusive_scan        cluster_offset = exclusive prefix sum of cluster_count; total
 *      bin_clusters (FILL)   the same traversal, writing light indices into the cluster lists
 *      sort_bins             each cluster's list in light index order (repeatable sums)
 *   3. shade_clustered       per pixel: loop over its cluster's list with the one shading function
 *                            (in lanes: each vector of pixels runs the lists of its slices)
 * Cluster c = tile * SLICES + slice (a tile's slices are adjacent). Clusters without geometry have
 * an empty depth range (min > max) and so get no lights.
 *
 * Build-time constants: TILE_W, TILE_H (pixels), SLICES, TS_CULL (per-cluster test, culling.h),
 * TS_LANES (shading in lanes on CPU devices, lanes.h), the scene's features and the G-buffer
 * layout (gbuffer.h).
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

/* Slice of depth z, for zn <= z <= zf (callers guarantee it, so log never sees z <= 0); the
 * slice is the integer part of ts_depth_slice_f, written for float and floatN. */
#define ts_depth_slice_f(z, zn, scale) clamp(log((z) / (zn)) * (scale), 0.0f, (float)(SLICES - 1))
static inline int ts_depth_slice(float z, float zn, float scale) {
  return (int)ts_depth_slice_f(z, zn, scale);
}

/* ---- 1. depth range and cluster bounds ---------------------------------------------------- */

/* min/max of the geometry depth (depth > 0; background excluded) into depth_range[0], [1] as
 * float bits (initialized to TS_DEPTH_EMPTY_MIN, 0 by the host). Integer atomic_min/max order
 * floats correctly here only because every depth compared is positive: positive IEEE floats sort
 * like their bit patterns read as unsigned integers. Grid-stride loop over float16 vectors (PoCL
 * does not vectorise a per-pixel loop: 1.4 -> 0.25 ms at 1280x720) and then the pixels past the last
 * whole vector, local tree, one pair of global atomics per work-group. */
#define DEPTH_RANGE_GROUP 64
__kernel void frame_depth_range(__global const float *gb_depth, int pixels,
                                __global uint *depth_range) {
  __local float lmin[DEPTH_RANGE_GROUP];
  __local float lmax[DEPTH_RANGE_GROUP];
  int lid = get_local_id(0), lsize = get_local_size(0);
  int id = get_global_id(0), size = get_global_size(0);
  float16 vmin = (float16)FLT_MAX, vmax = (float16)0.0f;
  for (int v = id; v < pixels / 16; v += size) {
    float16 z = vload16(v, gb_depth);
    int16 geometry = z > 0.0f;
    vmin = fmin(vmin, select((float16)FLT_MAX, z, geometry));
    vmax = fmax(vmax, select((float16)0.0f, z, geometry));
  }
  float8 m8 = fmin(vmin.lo, vmin.hi), x8 = fmax(vmax.lo, vmax.hi);
  float4 m4 = fmin(m8.lo, m8.hi), x4 = fmax(x8.lo, x8.hi);
  float2 m2 = fmin(m4.lo, m4.hi), x2 = fmax(x4.lo, x4.hi);
  float zmin = fmin(m2.x, m2.y), zmax = fmax(x2.x, x2.y);
  for (int i = pixels / 16 * 16 + id; i < pixels; i += size) {
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

/* Every pixel's slice: the cluster key that cluster_depth_bounds, the shading and the host's
 * light assignment read, so every user sees the same cluster whatever the rounding of log.
 * Background pixels get the key 0xffff. One work-item per 16 pixels of the depth plane read as
 * one array, in float16 vectors: PoCL did not vectorise the per-pixel form, whose scalar logs
 * took 17 ms at 1280x720 (the tail past the last whole vector goes pixel by pixel). */
__kernel void pixel_slices(__global const float *gb_depth, int pixels,
                           __global const uint *depth_range, __global ushort *pixel_slice) {
  float zn = as_float(depth_range[0]), zf = as_float(depth_range[1]);
  float scale = ts_slice_scale(zn, zf);
  int first = get_global_id(0) * 16;
  if (first + 16 <= pixels) {
    float16 z = vload16(0, gb_depth + first);
    int16 geometry = z > 0.0f;
    float16 f = ts_depth_slice_f(select((float16)zn, z, geometry), zn, scale);
    vstore16(select((ushort16)0xffff, convert_ushort16(f), convert_short16(geometry)), 0,
             pixel_slice + first);
  } else {
    for (int i = first; i < pixels; ++i) {
      float z = gb_depth[i];
      pixel_slice[i] = z > 0.0f ? (ushort)ts_depth_slice(z, zn, scale) : (ushort)0xffff;
    }
  }
}

/* One work-group per tile, one work-item per row of it: per cluster its geometry depth min/max
 * and pixel count, reduced in local memory with integer atomics -- valid only because depths are
 * positive (see above). A work-item walks its row and merges a run of pixels of one slice with
 * one set of atomics when the slice changes: neighbouring pixels mostly share a slice, and on a
 * CPU three atomics per pixel cost more than the rest of this kernel.
 * Output per cluster: (zmin, zmax), empty: zmin > zmax (FLT_MAX, 0); its geometry pixel count.
 * --msaa: gb_depth and pixel_slice hold `samples` planes (sample-major, as kernels/msaa_edges.h
 * reads them), and every sample's surface counts, so a cluster that only an edge's other sample
 * falls in exists and is binned (the count is then of samples).
 * Per tile: its first and last slice holding geometry (empty tile: first > last), so that
 * binning tests only the clusters between them. */
static inline void merge_run(int slice, uint zmin, uint zmax, uint count, __local uint *lmin,
                             __local uint *lmax, __local uint *lcount) {
  if (count == 0u) return;
  atomic_min(&lmin[slice], zmin);
  atomic_max(&lmax[slice], zmax);
  atomic_add(&lcount[slice], count);
}

__kernel void cluster_depth_bounds(__global const float *gb_depth, int width, int height,
                                   __global const ushort *pixel_slice,
                                   __global float2 *cluster_depth,
                                   __global uint *cluster_pixels,
                                   __global int2 *tile_slices, int samples) {
  __local uint lmin[SLICES];
  __local uint lmax[SLICES];
  __local uint lcount[SLICES];
  __local int lfirst, llast;
  int tiles_x = (width + TILE_W - 1) / TILE_W;
  int tile = get_group_id(0);
  int tx = tile % tiles_x, ty = tile / tiles_x;
  int lid = get_local_id(0), lsize = get_local_size(0);
  for (int s = lid; s < SLICES; s += lsize) {
    lmin[s] = TS_DEPTH_EMPTY_MIN;
    lmax[s] = 0u;
    lcount[s] = 0u;
  }
  if (lid == 0) {
    lfirst = SLICES;
    llast = -1;
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  int x0 = tx * TILE_W, x1 = min(x0 + TILE_W, width);
  size_t plane = (size_t)width * (size_t)height;
  for (int k = 0; k < samples; ++k)
    for (int y = ty * TILE_H + lid; y < min((ty + 1) * TILE_H, height); y += lsize) {
      size_t row = (size_t)k * plane + (size_t)y * (size_t)width;
      int run = 0; /* the slice of the current run, its depth bits' min/max and pixel count */
      uint run_min = TS_DEPTH_EMPTY_MIN, run_max = 0u, run_count = 0u;
      for (int x = x0; x < x1; ++x) {
        int s = pixel_slice[row + x];
        if (s == 0xffff) continue; /* background */
        if (s != run) {
          merge_run(run, run_min, run_max, run_count, lmin, lmax, lcount);
          run = s;
          run_min = TS_DEPTH_EMPTY_MIN;
          run_max = 0u;
          run_count = 0u;
        }
        uint z = as_uint(gb_depth[row + x]);
        run_min = min(run_min, z);
        run_max = max(run_max, z);
        ++run_count;
      }
      merge_run(run, run_min, run_max, run_count, lmin, lmax, lcount);
    }
  barrier(CLK_LOCAL_MEM_FENCE);
  for (int s = lid; s < SLICES; s += lsize) {
    int c = tile * SLICES + s;
    cluster_depth[c] = (float2)(as_float(lmin[s]), as_float(lmax[s]));
    cluster_pixels[c] = lcount[s];
    if (lcount[s] != 0u) {
      atomic_min(&lfirst, s);
      atomic_max(&llast, s);
    }
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  if (lid == 0) tile_slices[tile] = (int2)(lfirst, llast);
}

/* ---- 2. light binning --------------------------------------------------------------------- */

/* The relative widening of a light's depth extent before it is turned into slices: a pixel's
 * slice and the light's come from the same function, but log is not guaranteed monotonic in the
 * last ulps (nor identical between a kernel's scalar and vector code). Widening the depths by
 * 1e-3 moves their logs by 1e-3, far more than the few ulps of error of log (<= 3 ulp, or 2^-21
 * absolute under -cl-fast-relaxed-math) on values below 200, so every pixel depth inside the
 * extent gets a slice inside the light's range; the extra clusters cost one depth-range test
 * each. (A whole slice each way, as before, tested 2 more clusters per tile.) */
#define TS_SLICE_SLACK 1e-3f

/* The clusters light `light` may reach, for the group: its tile rectangle (x0, y0)-(x1, y1) and
 * slices s0..s1; empty (x1 < x0) when it misses the screen or all geometry depths. */
static inline void light_clusters(__global const float4 *light_pos_range,
                                  __global const float4 *light_spot, int light, float4 camera,
                                  float znear, __global const uint *depth_range,
                                  __local int *range) {
  int x0 = 0, y0 = 0, x1 = -1, y1 = -1, s0 = 0, s1 = -1;
  ts_light_volume v = ts_load_light_volume(light_pos_range, light_spot, (uint)light);
  float zn = as_float(depth_range[0]), zf = as_float(depth_range[1]);
  float zlo = fmax(-v.hi.z, zn), zhi = fmin(-v.lo.z, zf);
  /* no geometry in the volume's depth extent (or none at all), or off screen */
  if (zlo <= zhi && ts_light_tile_rect(&v, camera, znear, &x0, &y0, &x1, &y1)) {
    float scale = ts_slice_scale(zn, zf);
    s0 = ts_depth_slice(fmax(zlo * (1.0f - TS_SLICE_SLACK), zn), zn, scale);
    s1 = ts_depth_slice(fmin(zhi * (1.0f + TS_SLICE_SLACK), zf), zn, scale);
  } else {
    x1 = x0 - 1;
  }
  range[0] = x0;
  range[1] = y0;
  range[2] = x1;
  range[3] = y1;
  range[4] = s0;
  range[5] = s1;
}

/* One work-group per light; its work-items share the tiles of the light's tile rectangle, each
 * testing the tile's clusters in the light's slice range. The rectangle and the slice range (from
 * the light volume's depth extent clipped to [zn, zf], where all geometry lies) are found once
 * per group by its first work-item: on a CPU, where a group's work-items run one after the other,
 * every work-item computing them (three logs and the volume's screen bounds) cost more than the
 * tests. The decisive test is the cluster's geometry depth range, as in tiled.cl, then TS_CULL
 * against the tile with the cluster's range.
 * fill == 0: count into cluster_count; fill == 1: append to the cluster lists (ts_bin_light). */
__kernel void bin_clusters(__global const float4 *light_pos_range,
                           __global const float4 *light_spot, int light_count, float4 camera,
                           float znear, __global const uint *depth_range,
                           __global const float2 *cluster_depth,
                           __global const int2 *tile_slices, int fill,
                           __global uint *cluster_count, __global const uint *cluster_offset,
                           __global uint *cluster_cursor, __global uint *cluster_lights,
                           uint capacity) {
  __local int range[6];
  int light = get_group_id(0);
  if (get_local_id(0) == 0) {
    if (light < light_count)
      light_clusters(light_pos_range, light_spot, light, camera, znear, depth_range, range);
    else
      range[0] = 0, range[2] = -1; /* no such light: nothing to bin */
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  int x0 = range[0], y0 = range[1], s0 = range[4], s1 = range[5];
  int rect_w = range[2] - x0 + 1, rect_tiles = rect_w * (range[3] - y0 + 1);
  if (rect_w <= 0) return;
  int tiles_x = ((int)camera.z + TILE_W - 1) / TILE_W;
  ts_light_volume v = ts_load_light_volume(light_pos_range, light_spot, (uint)light);
  for (int i = get_local_id(0); i < rect_tiles; i += get_local_size(0)) {
    int tx = x0 + i % rect_w, ty = y0 + i / rect_w;
    int tile = ty * tiles_x + tx, first = tile * SLICES;
    int2 geometry = tile_slices[tile]; /* the tile's slices that hold geometry */
    for (int s = max(s0, geometry.x); s <= min(s1, geometry.y); ++s)
      if (ts_light_meets_bin(&v, tx, ty, cluster_depth[first + s], camera))
        ts_bin_light((uint)light, first + s, fill, cluster_count, cluster_offset, cluster_cursor,
                     cluster_lights, capacity);
  }
}

/* exclusive_scan: cluster_offset = exclusive prefix sum of cluster_count (shared with tiled.cl). */
#include "scan.h"
/* sort_bins: each cluster's list in light index order, the same on every run (shared too). */
#include "sort_bins.h"

/* ---- 3. shading --------------------------------------------------------------------------- */

#if TS_LANES == 1
/* One work-item per pixel (the GPU form). */
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
#else
#include "lanes.h"
/* The most work-items of a shading work-group (the host's tileDividingGroup: at most 16 x 16),
 * which are also whole vectors for every TS_LANES. */
#define CLUSTER_SHADE_SLOTS 256

/* The sum of every cluster list the lanes from `first` use. The pixels of one vector may lie in
 * several slices, i.e. use several lists: for each distinct slice among its lanes, the slice's
 * list runs on the vector with its other lanes unlit (ts_lanes_keep), and its sums go to the
 * lanes of that slice. Each lane thus adds exactly its own cluster's lights in list order, as per
 * pixel; a light that reaches no lane of the slice exits at the range test. */
static inline ts_lane_rgb shade_vector_clusters(const ts_lane_surface *lanes,
                                                __local const int *slot_slice, int first,
                                                int tile, __global const uint *cluster_count,
                                                __global const uint *cluster_offset,
                                                __global const uint *cluster_lights,
                                                uint capacity, TS_LIGHT_PARAMS) {
  ts_lane_rgb sum = {(TS_LANE)0.0f, (TS_LANE)0.0f, (TS_LANE)0.0f};
  TS_LANE_MASK slices = TS_LANE_VLOAD(TS_LANES)(0, slot_slice + first);
  uint todo = 0u; /* lanes whose slice is still to shade, one bit each */
  for (int j = 0; j < TS_LANES; ++j) todo |= (slot_slice[first + j] >= 0 ? 1u : 0u) << j;
  for (int j = 0; j < TS_LANES && todo != 0u; ++j) {
    if (!(todo & (1u << j))) continue;
    int slice = slot_slice[first + j];
    for (int i = j; i < TS_LANES; ++i)
      if (slot_slice[first + i] == slice) todo &= ~(1u << i);
    TS_LANE_MASK keep = slices == (TS_LANE_MASK)slice;
    ts_lane_surface only = ts_lanes_keep(lanes, keep);
    int cluster = tile * SLICES + slice;
    uint begin = cluster_offset[cluster];
    uint n = ts_bin_written(begin, cluster_count[cluster], capacity);
    ts_lane_rgb part = {(TS_LANE)0.0f, (TS_LANE)0.0f, (TS_LANE)0.0f};
    for (uint k = 0; k < n; ++k)
      ts_lanes_add_light(&part, &only, TS_LIGHT_ARGS, cluster_lights[begin + k]);
    sum.r = select(sum.r, part.r, keep);
    sum.g = select(sum.g, part.g, keep);
    sum.b = select(sum.b, part.b, keep);
  }
  return sum;
}

/* Whether any of the TS_LANES slots from `first` holds geometry. */
static inline int any_geometry(__local const int *slot_slice, int first) {
  return any(TS_LANE_VLOAD(TS_LANES)(0, slot_slice + first) >= 0);
}

/* In lanes (kernels/lanes.h): every work-item decodes its pixel and stores its slice (-1: no
 * geometry); then one work-item per TS_LANES pixels shades them (shade_vector_clusters) and adds
 * the directional lights. The host launches work-groups inside one tile (tileDividingGroup), so a
 * group's clusters are one tile's. `soa`: TS_LANE_PLANES floats per pixel slot, from the host. */
__kernel void shade_clustered(float4 camera, float4 ambient, TS_GBUFFER_PARAMS, TS_LIGHT_PARAMS,
                              TS_DIRECTIONAL_PARAMS, __global const ushort *pixel_slice,
                              __global const uint *cluster_count,
                              __global const uint *cluster_offset,
                              __global const uint *cluster_lights, uint capacity,
                              __global float4 *image, __local float *soa) {
  __local int slot_slice[CLUSTER_SHADE_SLOTS];
  int x = get_global_id(0), y = get_global_id(1);
  int width = (int)camera.z, height = (int)camera.w;
  int inside = x < width && y < height;
  int tile = group_tile(width);
  /* The tile's clusters are adjacent, so their lists are one stretch of the index list. */
  int last = tile * SLICES + SLICES - 1;
  uint entries = cluster_offset[last] + cluster_count[last] - cluster_offset[tile * SLICES];
  int lights = (int)entries + ts_directional_count(dir_light_count);
  ts_surface s;
  /* As in tiled.cl: a tile without lights skips local memory, and every item reaches both
   * barriers. */
  int lit = lights > 0 ? ts_lanes_store_pixel(soa, x, y, inside, camera, ambient, TS_GBUFFER_ARGS, &s)
                       : inside && ts_load_surface(x, y, camera, ambient, TS_GBUFFER_ARGS, &s);
  if (lights > 0) {
    int item = ts_lane_item(), group_size = (int)(get_local_size(0) * get_local_size(1));
    slot_slice[ts_lane_pixel_slot()] = lit ? (int)pixel_slice[y * width + x] : -1;
    for (int i = group_size + item; i < ts_lane_slots(); i += group_size) slot_slice[i] = -1;
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  int first = ts_lanes_first_slot();
  /* A vector without geometry (sky) is skipped: its sums are never read. */
  if (lights > 0 && first >= 0 && any_geometry(slot_slice, first)) {
    ts_lane_surface lanes = ts_lanes_get(soa, ts_lane_slots(), first);
    ts_lane_rgb sum = shade_vector_clusters(&lanes, slot_slice, first, tile, cluster_count,
                                            cluster_offset, cluster_lights, capacity,
                                            TS_LIGHT_ARGS);
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
/* As tiled.cl's shade_tiled_edge_samples, with each sample's own cluster: shade_clustered has
 * shaded every pixel's sample 0; here each edge pixel shades its samples 1..samples-1, each with
 * the list of the cluster its depth falls in (pixel_slice holds every sample's key), adds them to
 * sample 0's shade and divides by the samples (OpenGL's box resolve, the reference's
 * averageSamples). One work-item per pixel; built without lanes only (the host builds
 * clustered.cl a second time for it when shade_clustered has lanes). */
__kernel void shade_clustered_edge_samples(float4 camera, float4 ambient, TS_GBUFFER_PARAMS,
                                           TS_LIGHT_PARAMS, TS_DIRECTIONAL_PARAMS,
                                           __global const ushort *pixel_slice,
                                           __global const uint *cluster_count,
                                           __global const uint *cluster_offset,
                                           __global const uint *cluster_lights, uint capacity,
                                           __global const uchar *edge, int samples,
                                           int4 plane_bytes, __global float4 *image) {
  int x = get_global_id(0), y = get_global_id(1);
  int width = (int)camera.z, height = (int)camera.w;
  if (x >= width || y >= height) return;
  size_t i = (size_t)y * (size_t)width + (size_t)x, plane = (size_t)width * (size_t)height;
  if (!edge[i]) return;
  int tile = (y / TILE_H) * ((width + TILE_W - 1) / TILE_W) + x / TILE_W;
  float3 sum = image[i].xyz;
  for (int k = 1; k < samples; ++k) {
    size_t o = (size_t)k * plane;
    ts_surface s;
    if (TS_LOAD_SAMPLE_SURFACE(x, y, camera, ambient, o, plane_bytes, &s)) {
      int cluster = tile * SLICES + pixel_slice[o + i];
      float3 shade = ts_shade_bin(&s, cluster_offset[cluster], cluster_count[cluster], capacity,
                                  cluster_lights, TS_LIGHT_ARGS);
      shade += ts_shade_directionals(&s, TS_DIRECTIONAL_ARGS) + s.base;
      sum += shade;
    }
  }
  image[i] = (float4)(sum / (float)samples, 0.0f);
}
#endif
