/*
 * Traditional deferred shading (the bandwidth-hungry baseline of Olsson & Assarsson 2011), host
 * side in src/techniques/deferred.cpp. Per frame:
 *   1. deferred_base   per pixel: the light-independent base (emission + ambient) and the
 *                      directional lights into a float4 accumulation buffer; background 0
 *   2. deferred_light  one launch per point or spot light over its screen rectangle (the
 *                      projected sphere or cone, computed on the host as a vertex stage would):
 *                      every covered pixel reads the G-buffer again, shades this one light and
 *                      read-modify-writes the accumulation buffer (the blend of a light volume's
 *                      fragments)
 * Launches follow each other on an in-order queue, so the read-modify-writes of successive lights
 * never overlap and the sum is taken in light order.
 *
 * Build-time constants: TS_STENCIL (the stencil optimisation: a pixel reads its depth first and
 * the rest of the G-buffer only when its position lies inside the light volume), TS_LANES
 * (kernels/lanes.h), the scene's features and the G-buffer layout (gbuffer.h).
 */
#include "gbuffer.h"


/* ---- 1. base ------------------------------------------------------------------------------ */

#if TS_LANES == 1
/* The light-independent base and the directional lights (a full-screen pass: they reach every
 * pixel, so they have no footprint to cull to). */
__kernel void deferred_base(float4 camera, float4 ambient, TS_GBUFFER_PARAMS,
                            TS_DIRECTIONAL_PARAMS, __global float4 *accum) {
  int x = get_global_id(0), y = get_global_id(1);
  int width = (int)camera.z, height = (int)camera.w;
  if (x >= width || y >= height) return;
  ts_surface s;
  float3 base = (float3)(0.0f);
  if (ts_load_surface(x, y, camera, ambient, TS_GBUFFER_ARGS, &s))
    base = ts_shade_directionals(&s, TS_DIRECTIONAL_ARGS) + s.base;
  accum[y * width + x] = (float4)(base, 0.0f);
}
#else
#include "lanes.h"
/* In lanes, the directional lights are shaded TS_LANES pixels at a time like every light of
 * these builds (kernels/lanes.h); `soa`: local memory from the host. */
__kernel void deferred_base(float4 camera, float4 ambient, TS_GBUFFER_PARAMS,
                            TS_DIRECTIONAL_PARAMS, __global float4 *accum, __local float *soa) {
  int x = get_global_id(0), y = get_global_id(1);
  int width = (int)camera.z, height = (int)camera.w;
  int inside = x < width && y < height;
  int lights = ts_directional_count(dir_light_count);
  ts_surface s;
  int lit = lights > 0 ? ts_lanes_store_pixel(soa, x, y, inside, camera, ambient, TS_GBUFFER_ARGS, &s)
                       : inside && ts_load_surface(x, y, camera, ambient, TS_GBUFFER_ARGS, &s);
  barrier(CLK_LOCAL_MEM_FENCE);
  int first = ts_lanes_first_slot();
  if (lights > 0 && first >= 0) {
    ts_lane_surface lanes = ts_lanes_get(soa, ts_lane_slots(), first);
    ts_lane_rgb sum = {(TS_LANE)0.0f, (TS_LANE)0.0f, (TS_LANE)0.0f};
    ts_lanes_add_directionals(&sum, &lanes, TS_DIRECTIONAL_ARGS);
    ts_lanes_put_rgb(soa, ts_lane_slots(), 0, first, &sum);
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  if (!inside) return;
  accum[y * width + x] = (float4)(ts_lanes_pixel_colour(soa, lit, lights > 0, &s), 0.0f);
}
#endif

/* ---- 2. one light ------------------------------------------------------------------------- */

/* Without TS_STENCIL every pixel of the rectangle is in. With it, the stencil test's effect:
 * depth alone decides whether the pixel's surface lies inside the light volume (the range sphere,
 * and a spot light's cone), with the shading function's own range cut and cone test evaluated on
 * the same reconstructed position, so no pixel it would light is skipped. (The physical model
 * has no range cut; like the rectangles and every technique's culling, this bounds it by the
 * range.) */
static inline int in_light_volume(int x, int y, float4 camera, __global const float *gb_depth,
                                  float4 pr, float4 spot) {
#ifdef TS_STENCIL
  int width = (int)camera.z;
  float depth = ts_load_depth(x, y, width, gb_depth);
  if (depth <= 0.0f) return 0;
  float3 P = ts_view_position(x, y, depth, camera.x, camera.y, width, (int)camera.w);
  return ts_light_volume_holds(pr, spot, P);
#else
  return 1;
#endif
}

#if TS_LANES == 1
/* rect = (x0, y0, x1, y1), x1/y1 exclusive; the NDRange is the rectangle rounded up to whole
 * work-groups, so work-items past its edge return. The ambient term is unused here (it is the
 * base pass's). */
__kernel void deferred_light(float4 camera, float4 ambient, TS_GBUFFER_PARAMS, TS_LIGHT_PARAMS,
                             int light, int4 rect, __global float4 *accum) {
  int x = rect.x + (int)get_global_id(0), y = rect.y + (int)get_global_id(1);
  if (x >= rect.z || y >= rect.w) return;
  if (!in_light_volume(x, y, camera, gb_depth, light_pos_range[light],
                       ts_light_spot(light_spot, (uint)light)))
    return;
  ts_surface s;
  if (!ts_load_surface(x, y, camera, ambient, TS_GBUFFER_ARGS, &s)) return;
  float3 c = ts_shade_punctual(&s, TS_LIGHT_ARGS, (uint)light);
  accum[y * (int)camera.z + x] += (float4)(c, 0.0f);
}
#else
/* In lanes (kernels/lanes.h): the pixels decode one per work-item, then one work-item per
 * TS_LANES pixels shades the light for all of them. `soa`: local memory from the host. */
__kernel void deferred_light(float4 camera, float4 ambient, TS_GBUFFER_PARAMS, TS_LIGHT_PARAMS,
                             int light, int4 rect, __global float4 *accum, __local float *soa) {
  int x = rect.x + (int)get_global_id(0), y = rect.y + (int)get_global_id(1);
  int wanted = x < rect.z && y < rect.w &&
               in_light_volume(x, y, camera, gb_depth, light_pos_range[light],
                               ts_light_spot(light_spot, (uint)light));
  ts_surface s;
  int lit = ts_lanes_store_pixel(soa, x, y, wanted, camera, ambient, TS_GBUFFER_ARGS, &s);
  barrier(CLK_LOCAL_MEM_FENCE);
  int first = ts_lanes_first_slot();
  if (first >= 0) {
    ts_lane_surface lanes = ts_lanes_get(soa, ts_lane_slots(), first);
    ts_lane_rgb sum = {(TS_LANE)0.0f, (TS_LANE)0.0f, (TS_LANE)0.0f};
    ts_lanes_add_light(&sum, &lanes, TS_LIGHT_ARGS, (uint)light);
    ts_lanes_put_rgb(soa, ts_lane_slots(), 0, first, &sum);
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  if (lit) accum[y * (int)camera.z + x] += (float4)(ts_lanes_pixel_sum(soa), 0.0f);
}
#endif
