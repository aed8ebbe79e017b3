/*
 * Brute force, the naive baseline; host side in src/techniques/brute.cpp. Every pixel evaluates
 * every light; the range cut inside the shading function (kernels/shading.h) is the only culling.
 * Build-time constants: TS_LANES (kernels/lanes.h), the scene's features and the G-buffer layout
 * (gbuffer.h).
 */
#include "gbuffer.h"


#if TS_LANES == 1
/* One work-item per pixel. */
__kernel void shade_brute(float4 camera, float4 ambient, TS_GBUFFER_PARAMS, TS_LIGHT_PARAMS,
                          int light_count, TS_DIRECTIONAL_PARAMS, __global float4 *image) {
  int x = get_global_id(0), y = get_global_id(1);
  int width = (int)camera.z, height = (int)camera.w;
  if (x >= width || y >= height) return;
  ts_surface s;
  float3 sum = (float3)(0.0f);
  if (ts_load_surface(x, y, camera, ambient, TS_GBUFFER_ARGS, &s)) {
    for (int light = 0; light < light_count; ++light)
      sum += ts_shade_punctual(&s, TS_LIGHT_ARGS, (uint)light);
    sum += ts_shade_directionals(&s, TS_DIRECTIONAL_ARGS) + s.base;
  }
  image[y * width + x] = (float4)(sum, 0.0f);
}
#else
#include "lanes.h"
/* In lanes (kernels/lanes.h), as shade_tiled with every light listed. A light out of range of
 * all TS_LANES pixels costs only the range test, as it does per pixel. */
__kernel void shade_brute(float4 camera, float4 ambient, TS_GBUFFER_PARAMS, TS_LIGHT_PARAMS,
                          int light_count, TS_DIRECTIONAL_PARAMS, __global float4 *image,
                          __local float *soa) {
  int x = get_global_id(0), y = get_global_id(1);
  int width = (int)camera.z, height = (int)camera.w;
  int inside = x < width && y < height;
  ts_surface s;
  int lit = ts_lanes_store_pixel(soa, x, y, inside, camera, ambient, TS_GBUFFER_ARGS, &s);
  barrier(CLK_LOCAL_MEM_FENCE);
  int first = ts_lanes_first_slot();
  if (first >= 0) {
    ts_lane_surface lanes = ts_lanes_get(soa, ts_lane_slots(), first);
    ts_lane_rgb sum = {(TS_LANE)0.0f, (TS_LANE)0.0f, (TS_LANE)0.0f};
    for (int light = 0; light < light_count; ++light)
      ts_lanes_add_light(&sum, &lanes, TS_LIGHT_ARGS, (uint)light);
    ts_lanes_add_directionals(&sum, &lanes, TS_DIRECTIONAL_ARGS);
    ts_lanes_put_rgb(soa, ts_lane_slots(), 0, first, &sum);
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  if (!inside) return;
  image[y * width + x] = (float4)(ts_lanes_pixel_colour(soa, lit, 1, &s), 0.0f);
}
#endif
