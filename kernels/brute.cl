/*
 * Brute force, the naive baseline; host side in src/techniques/brute.cpp. Every pixel evaluates
 * every light; the range cut inside the shading function (kernels/shading.h) is the only culling.
 * Build-time constants: TS_MODEL, the G-buffer layout (gbuffer.h).
 */
#include "gbuffer.h"

#ifndef TS_MODEL
#define TS_MODEL TS_MODEL_WINDOWED
#endif

__kernel void shade_brute(float4 camera, float4 ambient, TS_GBUFFER_PARAMS,
                          __global const float4 *light_pos_range,
                          __global const float4 *light_color, int light_count,
                          __global float4 *image) {
  int x = get_global_id(0), y = get_global_id(1);
  int width = (int)camera.z, height = (int)camera.w;
  if (x >= width || y >= height) return;
  ts_surface s;
  float3 sum = (float3)(0.0f);
  if (ts_load_surface(x, y, camera, TS_GBUFFER_ARGS, &s)) {
    for (int light = 0; light < light_count; ++light)
      sum += ts_shade_light(&s, light_pos_range[light], light_color[light], TS_MODEL);
    sum += ts_surface_base(s.ke, s.kd, ambient.xyz);
  }
  image[y * width + x] = (float4)(sum, 0.0f);
}
