/*
 * Writes, per pixel, the values the shading kernels actually use after decoding the G-buffer
 * (ts_load_surface in gbuffer.h): P.xyz N.xyz kd.rgb ks.rgb shininess ke.rgb mask = 17 floats.
 * Host side: `tileshade render --dump` (src/render/render_job.cpp) writes them to gbuffer.exr.
 */
#include "gbuffer.h"

#define DUMP_CHANNELS 17

__kernel void decode_gbuffer(float4 camera, TS_GBUFFER_PARAMS, __global float *out) {
  int x = get_global_id(0), y = get_global_id(1);
  int width = (int)camera.z, height = (int)camera.w;
  if (x >= width || y >= height) return;
  __global float *o = out + (size_t)(y * width + x) * DUMP_CHANNELS;
  ts_surface s;
  int mask = ts_load_surface(x, y, camera, TS_GBUFFER_ARGS, &s);
  if (!mask) {
    for (int c = 0; c < DUMP_CHANNELS; ++c) o[c] = 0.0f;
    return;
  }
  o[0] = s.P.x; o[1] = s.P.y; o[2] = s.P.z;
  o[3] = s.N.x; o[4] = s.N.y; o[5] = s.N.z;
  o[6] = s.kd.x; o[7] = s.kd.y; o[8] = s.kd.z;
  o[9] = s.ks.x; o[10] = s.ks.y; o[11] = s.ks.z;
  o[12] = s.shininess;
  o[13] = s.ke.x; o[14] = s.ke.y; o[15] = s.ke.z;
  o[16] = 1.0f;
}
