/*
 * Single-kernel tiled deferred shading (Andersson 2009, Lauritzen 2010), host side in
 * src/techniques/tiled_single.cpp. One work-group per tile does everything in local memory:
 *   1. reduce the tile's geometry depth to [zmin, zmax] (background pixels left out);
 *   2. test every light of the frame against the tile (a cheap pre-test first, culling.h's
 *      ts_light_may_meet_tile, so most lights skip the full test), appending accepted lights to
 *      a list in local memory, in light index order: each batch of tests sets one bit per
 *      accepted light (atomic_or: the result does not depend on the order) and one work-item
 *      then appends the set bits' lights in bit order, so the list, and each pixel's sum, is
 *      the same on every run and every device (an atomic_inc cursor gave the order the
 *      work-items ran in);
 *   3. shade the tile's pixels over that list.
 * Every tile repeats the light tests that the multi-kernel variant (tiled.cl) does once per light
 * rectangle: simple, but redundant per-tile work. The per-tile test is the same as tiled.cl's
 * (the light volume's rectangle, depth range, then the tile test), so both build identical tile
 * sets. Directional lights are not tested: every pixel adds them.
 *
 * The local list holds LIST_CAPACITY lights. A tile that accepts more is shaded in chunks: when
 * the next batch of tests could overflow the list, the list is shaded into private accumulators
 * and emptied. No light is ever dropped.
 *
 * With TS_LANES > 1 (CPU devices, kernels/lanes.h) a tile that lists lights is decoded once into
 * local memory before its first chunk is shaded, and each chunk is shaded TS_LANES pixels at a
 * time.
 *
 * Build-time constants: TILE_W, TILE_H (pixels), GROUP_W, GROUP_H (work-group shape, at most the
 * tile), LIST_CAPACITY (>= GROUP_W*GROUP_H), TS_CULL, TS_LANES, the scene's features and the
 * G-buffer layout (gbuffer.h).
 */
#include "gbuffer.h"

#ifndef TS_CULL
#define TS_CULL TS_CULL_RECT
#endif
#include "light_lists.h"

#define GROUP_SIZE (GROUP_W * GROUP_H)
/* Lights each work-item tests per batch: as many as the list holds (at most 16), so that a batch
 * never overflows an emptied list. PoCL runs every barrier region as a loop over the work-group's
 * work-items: one batch of 1 024 lights (the default list) has a quarter of the regions of four
 * batches of 256 (bench/RESULTS.md, issue #19). */
#define TESTS_PER_ITEM (LIST_CAPACITY / GROUP_SIZE < 16 ? LIST_CAPACITY / GROUP_SIZE : 16)
#define BATCH_LIGHTS (TESTS_PER_ITEM * GROUP_SIZE)
/* Words of the accept bits of one batch (one bit per light of the batch). */
#define ACCEPT_WORDS ((BATCH_LIGHTS + 31) / 32)
/* Pixels of the tile each work-item owns (the tile may be larger than the work-group). */
#define PIXELS_PER_ITEM (((TILE_W + GROUP_W - 1) / GROUP_W) * ((TILE_H + GROUP_H - 1) / GROUP_H))

/* Does light volume v reach tile (tx, ty) with depth range zr? The same decisions as tiled.cl's
 * bin_lights: inside the light's tile rectangle, then the bin test. */
static int light_meets_tile(const ts_light_volume *v, int tx, int ty, float2 zr, float4 camera,
                            float znear) {
  int x0, y0, x1, y1;
  if (!ts_light_tile_rect(v, camera, znear, &x0, &y0, &x1, &y1)) return 0;
  if (tx < x0 || tx > x1 || ty < y0 || ty > y1) return 0;
  return ts_light_meets_bin(v, tx, ty, zr, camera);
}

/* The work-group's depth range from each work-item's (lmin, lmax, written before a barrier), in
 * two barrier regions: the first work-item of each row reduces its row into the row's first
 * entry, then every work-item reduces those GROUP_H entries. PoCL runs every barrier region as a
 * loop over the work-items: a tree took log2(GROUP_SIZE) regions. */
static float2 group_depth_range(__local float *lmin, __local float *lmax) {
  int row = get_local_id(1);
  if (get_local_id(0) == 0) {
    float lo = lmin[row * GROUP_W], hi = lmax[row * GROUP_W];
    for (int i = 1; i < GROUP_W; ++i) {
      lo = fmin(lo, lmin[row * GROUP_W + i]);
      hi = fmax(hi, lmax[row * GROUP_W + i]);
    }
    lmin[row * GROUP_W] = lo;
    lmax[row * GROUP_W] = hi;
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  float2 zr = (float2)(FLT_MAX, 0.0f);
  for (int r = 0; r < GROUP_H; ++r) {
    zr = (float2)(fmin(zr.x, lmin[r * GROUP_W]), fmax(zr.y, lmax[r * GROUP_W]));
  }
  return zr;
}

/* Screen position of the k-th pixel owned by this work-item; returns 0 when it is off the tile
 * or off the screen. */
static int owned_pixel(int k, int tx, int ty, int width, int height, int *x, int *y) {
  const int cols = (TILE_W + GROUP_W - 1) / GROUP_W;
  int px = get_local_id(0) + (k % cols) * GROUP_W, py = get_local_id(1) + (k / cols) * GROUP_H;
  *x = tx * TILE_W + px;
  *y = ty * TILE_H + py;
  return px < TILE_W && py < TILE_H && *x < width && *y < height;
}

#if TS_LANES == 1
/* Adds the listed lights' contributions to this work-item's pixels. The last call (`image` not
 * null) also adds the directional lights and the light-independent base and writes the pixels,
 * so the common single-chunk tile decodes each pixel's G-buffer once. */
static void shade_list(__local const uint *list, uint n, int tx, int ty, float4 camera,
                       float4 ambient, TS_GBUFFER_PARAMS, TS_LIGHT_PARAMS, TS_DIRECTIONAL_PARAMS,
                       float3 *sum, __global float4 *image) {
  int width = (int)camera.z, height = (int)camera.w;
  for (int k = 0; k < PIXELS_PER_ITEM; ++k) {
    int x, y;
    ts_surface s;
    if (!owned_pixel(k, tx, ty, width, height, &x, &y)) continue;
    if (!ts_load_surface(x, y, camera, ambient, TS_GBUFFER_ARGS, &s)) {
      if (image) image[y * width + x] = (float4)(0.0f);
      continue;
    }
    for (uint i = 0; i < n; ++i) sum[k] += ts_shade_punctual(&s, TS_LIGHT_ARGS, list[i]);
    if (image)
      image[y * width + x] =
          (float4)(sum[k] + ts_shade_directionals(&s, TS_DIRECTIONAL_ARGS) + s.base, 0.0f);
  }
}
#else
#include "lanes.h"
/* In lanes, `soa` holds TILE_PLANES planes of TILE_SLOTS floats: the shading terms of every pixel
 * of the tile (lanes.h), then its running r, g, b sums, which start at the pixel's base. */
#define TILE_SLOTS ((TILE_W * TILE_H + TS_LANES - 1) / TS_LANES * TS_LANES)
#define SUM_PLANE TS_LANE_PLANES
#define TILE_PLANES (TS_LANE_PLANES + 3)

/* The tile-local slot (row-major) of the k-th pixel this work-item owns; -1 off the tile. */
static int owned_slot(int k) {
  const int cols = (TILE_W + GROUP_W - 1) / GROUP_W;
  int px = get_local_id(0) + (k % cols) * GROUP_W, py = get_local_id(1) + (k / cols) * GROUP_H;
  return px < TILE_W && py < TILE_H ? py * TILE_W + px : -1;
}

/* Decodes this work-item's pixels into their slots (unlit off screen and for background) and
 * its share of the padding slots. A barrier must follow. */
static void lanes_store_tile(__local float *soa, int tx, int ty, float4 camera, float4 ambient,
                             TS_GBUFFER_PARAMS) {
  int width = (int)camera.z, height = (int)camera.w;
  int lid = get_local_id(1) * GROUP_W + get_local_id(0);
  for (int k = 0; k < PIXELS_PER_ITEM; ++k) {
    int slot = owned_slot(k), x, y;
    if (slot < 0) continue;
    ts_surface s;
    int lit = owned_pixel(k, tx, ty, width, height, &x, &y) &&
              ts_load_surface(x, y, camera, ambient, TS_GBUFFER_ARGS, &s);
    ts_lanes_put(soa, TILE_SLOTS, slot, lit ? &s : 0);
    float3 base = lit ? s.base : (float3)(0.0f);
    soa[SUM_PLANE * TILE_SLOTS + slot] = base.x;
    soa[(SUM_PLANE + 1) * TILE_SLOTS + slot] = base.y;
    soa[(SUM_PLANE + 2) * TILE_SLOTS + slot] = base.z;
  }
  for (int i = TILE_W * TILE_H + lid; i < TILE_SLOTS; i += GROUP_SIZE) {
    ts_lanes_put(soa, TILE_SLOTS, i, 0);
    for (int c = 0; c < 3; ++c) soa[(SUM_PLANE + c) * TILE_SLOTS + i] = 0.0f;
  }
}

/* Adds the listed lights (and, in the last chunk, the directional lights: `dir_count` of them)
 * to the sums of every slot of the tile, TS_LANES slots per step. */
static void lanes_shade_list(__local const uint *list, uint n, __local float *soa,
                             TS_LIGHT_PARAMS, TS_DIRECTIONAL_PARAMS) {
  int lid = get_local_id(1) * GROUP_W + get_local_id(0);
  if (n == 0 && dir_light_count == 0) return;
  for (int first = lid * TS_LANES; first < TILE_SLOTS; first += GROUP_SIZE * TS_LANES) {
    ts_lane_surface lanes = ts_lanes_get(soa, TILE_SLOTS, first);
    ts_lane_rgb sum = ts_lanes_get_rgb(soa, TILE_SLOTS, SUM_PLANE, first);
    for (uint i = 0; i < n; ++i) ts_lanes_add_light(&sum, &lanes, TS_LIGHT_ARGS, list[i]);
    ts_lanes_add_directionals(&sum, &lanes, TS_DIRECTIONAL_ARGS);
    ts_lanes_put_rgb(soa, TILE_SLOTS, SUM_PLANE, first, &sum);
  }
}

/* Writes this work-item's on-screen pixels of a tile that lists no light: the base alone. */
static void write_base_tile(int tx, int ty, float4 camera, float4 ambient, TS_GBUFFER_PARAMS,
                            __global float4 *image) {
  int width = (int)camera.z, height = (int)camera.w;
  for (int k = 0; k < PIXELS_PER_ITEM; ++k) {
    int x, y;
    ts_surface s;
    if (!owned_pixel(k, tx, ty, width, height, &x, &y)) continue;
    image[y * width + x] = ts_load_surface(x, y, camera, ambient, TS_GBUFFER_ARGS, &s)
                               ? (float4)(s.base, 0.0f)
                               : (float4)(0.0f);
  }
}

/* Writes this work-item's on-screen pixels from their sums. */
static void lanes_write_tile(__local const float *soa, int tx, int ty, float4 camera,
                             __global float4 *image) {
  int width = (int)camera.z, height = (int)camera.w;
  for (int k = 0; k < PIXELS_PER_ITEM; ++k) {
    int x, y, slot = owned_slot(k);
    if (!owned_pixel(k, tx, ty, width, height, &x, &y)) continue;
    image[y * width + x] = (float4)(soa[SUM_PLANE * TILE_SLOTS + slot],
                                    soa[(SUM_PLANE + 1) * TILE_SLOTS + slot],
                                    soa[(SUM_PLANE + 2) * TILE_SLOTS + slot], 0.0f);
  }
}
#endif

/* Appends the batch's accepted lights (bit b of word w: light base + 32 w + b) to the list after
 * its first `len` entries, in light index order, and clears the bits; returns the new length.
 * Run by one work-item: a serial scan of ACCEPT_WORDS words and the few accepted lights costs
 * less than every work-item counting its rank in its own barrier region. */
static uint append_accepted(__local uint *accept_bits, int words, int base, __local uint *list,
                            uint len) {
  for (int w = 0; w < words; ++w) {
    uint bits = accept_bits[w];
    accept_bits[w] = 0u;
    for (; bits != 0u; bits &= bits - 1u)
      list[len++] = (uint)(base + w * 32) + (31u - clz(bits & (~bits + 1u)));
  }
  return len;
}

/* With record_stride > 0, copies a chunk of n listed lights to the tile's record after the
 * `accepted` lights of the chunks before it. */
static void record_chunk(__local const uint *list, uint n, uint accepted, int tile,
                         uint record_stride, __global uint *tile_lights) {
  if (record_stride == 0) return;
  int lid = get_local_id(1) * GROUP_W + get_local_id(0);
  for (uint i = lid; i < n; i += GROUP_SIZE)
    tile_lights[(size_t)tile * record_stride + accepted + i] = list[i];
}

/* tile_count[tile] receives the number of lights the tile accepted. When record_stride > 0 the
 * accepted light indices are also written to tile_lights[tile * record_stride + ...] (for tests and
 * statistics; record_stride must then be >= light_count). `list` is the local light list of
 * LIST_CAPACITY entries, passed from the host (PoCL miscompiles a kernel-scope __local array
 * handed to a helper function; an argument works everywhere). */
__kernel __attribute__((reqd_work_group_size(GROUP_W, GROUP_H, 1))) void shade_tiled_single(
    float4 camera, float4 ambient, float znear, TS_GBUFFER_PARAMS, TS_LIGHT_PARAMS,
    int light_count, TS_DIRECTIONAL_PARAMS, __global uint *tile_count, __global uint *tile_lights, uint record_stride,
    __global float4 *image, __local uint *list
#if TS_LANES > 1
    , __local float *soa
#endif
    ) {
  __local float lmin[GROUP_SIZE];
  __local float lmax[GROUP_SIZE];
  __local uint accept_bits[ACCEPT_WORDS];
  __local uint list_end; /* list_len after the last batch, written by work-item 0 */
  int width = (int)camera.z, height = (int)camera.w;
  int tx = get_group_id(0), ty = get_group_id(1);
  int tile = ty * get_num_groups(0) + tx;
  int lid = get_local_id(1) * GROUP_W + get_local_id(0);

  /* 1. Depth bounds of the tile's geometry (float min/max in local memory, no atomics). */
  float zmin = FLT_MAX, zmax = 0.0f;
  for (int k = 0; k < PIXELS_PER_ITEM; ++k) {
    int x, y;
    if (!owned_pixel(k, tx, ty, width, height, &x, &y)) continue;
    float z = ts_load_depth(x, y, width, gb_depth);
    if (z > 0.0f) {
      zmin = fmin(zmin, z);
      zmax = fmax(zmax, z);
    }
  }
  lmin[lid] = zmin;
  lmax[lid] = zmax;
  for (int i = lid; i < ACCEPT_WORDS; i += GROUP_SIZE) accept_bits[i] = 0u;
  if (lid == 0) list_end = 0u;
  barrier(CLK_LOCAL_MEM_FENCE);
  float2 zr = group_depth_range(lmin, lmax);

  /* 2 + 3. Test the lights a batch of GROUP_SIZE at a time; shade and empty the list whenever the
   * next batch might not fit.
   *
   * Every barrier below is reached by every work-item on every pass, outside any `if` (the
   * conditions are the same for the whole work-group, but are only used around the work between
   * barriers). PoCL 3.1 miscompiled the earlier form, which flushed a chunk inside
   * `if (n + GROUP_SIZE > LIST_CAPACITY) { ...; barrier(); }` (and decoded the tile in lanes inside
   * `if (first_chunk) { ...; barrier(); }`): LLVM computes owned_pixel's on-screen test once, before
   * the first barrier, and after PoCL's work-group loops had replicated the barrier's branches it
   * branched on that per-work-item value *once for the whole group*, taking the last work-item's
   * value. In a tile that crosses the frame's edge, the last work-item's pixel is off screen: with
   * the `loops` method no pixel of the tile was written, with `loopvec` (the default) every pixel
   * was, off-screen ones included, past the end of the image buffer — heap corruption once a tile
   * listed more than one chunk of lights (issue #12;
   * tests/techniques/tiled_single_chunks_test.cpp). */
#if TS_LANES == 1
  float3 sum[PIXELS_PER_ITEM];
  for (int k = 0; k < PIXELS_PER_ITEM; ++k) sum[k] = (float3)(0.0f);
#endif
  /* list_len counts every light the tile accepted (the same in every work-item); the list holds
   * those after the first `accepted`, which earlier chunks have shaded, so emptying the list
   * needs no write. */
  uint list_len = 0, accepted = 0;
  int any_geometry = zr.x <= zr.y;
  /* The cheap pre-test's planes (culling.h): most lights miss the tile and skip the full test. */
  float4 pre_slopes = ts_pretest_slopes(tx * TILE_W, ty * TILE_H, (tx + 1) * TILE_W,
                                        (ty + 1) * TILE_H, width, height, camera.x, camera.y);
  float4 pre_norms = ts_pretest_norms(pre_slopes);
  for (int base = 0; any_geometry && base < light_count; base += BATCH_LIGHTS) {
    barrier(CLK_LOCAL_MEM_FENCE); /* the last batch's appends are done */
    list_len = list_end;
    uint n = list_len - accepted;
    int flush = n + BATCH_LIGHTS > LIST_CAPACITY;
#if TS_LANES == 1
    if (flush)
      shade_list(list, n, tx, ty, camera, ambient, TS_GBUFFER_ARGS, TS_LIGHT_ARGS,
                 TS_DIRECTIONAL_ARGS, sum, 0);
#else
    /* The first chunk decodes the tile into local memory, so a tile that lists no light never
     * pays for that trip. Directional lights are added once, with the last chunk. */
    if (flush && accepted == 0) lanes_store_tile(soa, tx, ty, camera, ambient, TS_GBUFFER_ARGS);
    barrier(CLK_LOCAL_MEM_FENCE);
    if (flush) lanes_shade_list(list, n, soa, TS_LIGHT_ARGS, TS_DIRECTIONAL_ARGS_COUNT(0));
#endif
    if (flush) {
      record_chunk(list, n, accepted, tile, record_stride, tile_lights);
      accepted += n;
    }
    /* Work-item i tests lights i, i + GROUP_SIZE, ...: consecutive lights in the vector lanes PoCL
     * makes of consecutive work-items. The list is only read above and written below the next
     * barrier, so no barrier is needed here. */
    for (int j = 0; j < TESTS_PER_ITEM; ++j) {
      int slot = j * GROUP_SIZE + lid, light = base + slot;
      if (light < light_count &&
          ts_light_may_meet_tile(light_pos_range[light], ts_light_spot(light_spot, (uint)light),
                                 pre_slopes, pre_norms, zr.x, zr.y)) {
        ts_light_volume v = ts_load_light_volume(light_pos_range, light_spot, (uint)light);
        if (light_meets_tile(&v, tx, ty, zr, camera, znear))
          atomic_or(&accept_bits[slot / 32], 1u << (slot % 32));
      }
    }
    barrier(CLK_LOCAL_MEM_FENCE); /* every accept bit is set */
    if (lid == 0) {
      int words = min(ACCEPT_WORDS, (light_count - base + 31) / 32);
      list_end = accepted + append_accepted(accept_bits, words, base, list, list_len - accepted);
    }
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  list_len = list_end;
  uint n = list_len - accepted;
#if TS_LANES == 1
  shade_list(list, n, tx, ty, camera, ambient, TS_GBUFFER_ARGS, TS_LIGHT_ARGS, TS_DIRECTIONAL_ARGS,
             sum, image);
#else
  int dir_count = ts_directional_count(dir_light_count);
  int lit_tile = accepted + n > 0 || dir_count > 0;
  if (lit_tile && accepted == 0) lanes_store_tile(soa, tx, ty, camera, ambient, TS_GBUFFER_ARGS);
  barrier(CLK_LOCAL_MEM_FENCE);
  if (lit_tile) lanes_shade_list(list, n, soa, TS_LIGHT_ARGS, TS_DIRECTIONAL_ARGS_COUNT(dir_count));
  barrier(CLK_LOCAL_MEM_FENCE);
  if (lit_tile) lanes_write_tile(soa, tx, ty, camera, image);
  else write_base_tile(tx, ty, camera, ambient, TS_GBUFFER_ARGS, image);
#endif
  record_chunk(list, n, accepted, tile, record_stride, tile_lights);
  if (lid == 0) tile_count[tile] = accepted + n;
}
