/*
 * Writes, per pixel, the values the shading kernels read after decoding the G-buffer
 * (kernels/gbuffer.h) in DUMP_CHANNELS floats, the material terms as a rasterized G-buffer holds
 * them (src/gbuffer/gbuffer.h) whatever the layout stores:
 *   0-2 P.xyz   3-5 N.xyz (renormalised)   13-15 ke.rgb   16 mask
 *   Blinn-Phong          6-8 kd.rgb     9-11 ks.rgb      12 shininess
 *   metallic-roughness   6-8 base.rgb   9 roughness, 10-12 0   (metallic: host side)
 * Host side: src/render/gbuffer_dump.cpp (`tileshade render --dump`; dumpKernelChannels() names
 * the channels).
 */
#include "gbuffer.h"

#define DUMP_CHANNELS 17

__kernel void decode_gbuffer(float4 camera, TS_GBUFFER_PARAMS, __global float *out) {
  int x = get_global_id(0), y = get_global_id(1);
  int width = (int)camera.z, height = (int)camera.w;
  if (x >= width || y >= height) return;
  __global float *o = out + (size_t)(y * width + x) * DUMP_CHANNELS;
  for (int c = 0; c < DUMP_CHANNELS; ++c) o[c] = 0.0f;
  int i = y * width + x;
  float depth = gb_depth[i];
  if (depth <= 0.0f) return;
  float3 P = ts_view_position(x, y, depth, camera.x, camera.y, width, height);
  float4 normal = ts_decode_normal(i, gb_normal);
  float4 diffuse = ts_decode_diffuse(i, gb_diffuse);
  o[0] = P.x; o[1] = P.y; o[2] = P.z;
  o[3] = normal.x; o[4] = normal.y; o[5] = normal.z;
  o[6] = diffuse.x; o[7] = diffuse.y; o[8] = diffuse.z;
#if TS_SHADING == 1
  o[9] = ts_decode_roughness(i, normal, gb_specular);
#elif TS_HAS_SPECULAR
  float4 spec = ts_decode_specular(i, gb_specular);
  o[9] = spec.x; o[10] = spec.y; o[11] = spec.z;
  o[12] = spec.w;
#else
  o[12] = 1.0f; /* no specular plane: ks 0, shininess 1 */
#endif
#if TS_HAS_EMISSIVE
  float3 ke = ts_decode_emissive(i, gb_emissive);
  o[13] = ke.x; o[14] = ke.y; o[15] = ke.z;
#endif
  o[16] = 1.0f;
}
