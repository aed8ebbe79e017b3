/*
 * G-buffer access for every technique's kernels: one function decodes a pixel into the values the
 * shading function takes. The host mirror is src/raster/gbuffer_layout.cpp (decodeSurface); a test
 * checks the two agree bit for bit through the `decode_gbuffer` kernel (kernels/dump.cl).
 *
 * Planes (one element per pixel, row-major, row 0 = top of the screen):
 *   depth     float         linear view depth -z_view; 0 = background (no geometry)
 *   normal    GB4           view-space normal xyz (renormalized after decoding), w unused
 *   diffuse   GB4           kd rgb, a unused
 *   specular  GB4           ks rgb, shininess in w
 *   emissive  GB4           ke rgb, a unused
 * GB4 is float4 (layout fp32, 16 B/plane) or half4 read with vload_half4 (TS_GBUFFER_FP16, 8 B).
 * Depth stays float32 in both layouts, as in the paper.
 */
#ifndef TS_GBUFFER_H
#define TS_GBUFFER_H

#define TS_REAL float
#define TS_REAL3 float3
#define TS_MAKE3(x, y, z) ((float3)((x), (y), (z)))
#include "shading.h"
#define TS_REAL4 float4
#define TS_MAKE4(x, y, z, w) ((float4)((x), (y), (z), (w)))
#include "culling.h"

#ifdef TS_GBUFFER_FP16
typedef half ts_gb_elem;
#define TS_LOAD4(i, p) vload_half4((i), (p))
#else
typedef float ts_gb_elem;
#define TS_LOAD4(i, p) vload4((i), (p))
#endif

/* Kernel parameters and arguments for the G-buffer planes; keeps every signature in step. */
#define TS_GBUFFER_PARAMS                                                                        \
  __global const float *gb_depth, __global const ts_gb_elem *gb_normal,                          \
      __global const ts_gb_elem *gb_diffuse, __global const ts_gb_elem *gb_specular,             \
      __global const ts_gb_elem *gb_emissive
#define TS_GBUFFER_ARGS gb_depth, gb_normal, gb_diffuse, gb_specular, gb_emissive

/* Camera: (tan of half fov x, tan of half fov y, width, height). */
typedef struct {
  float3 P, N, V, kd, ks, ke;
  float shininess;
} ts_surface;

/* Reads the depth only: background test and depth-range work need no more. */
static inline float ts_load_depth(int x, int y, int width, __global const float *gb_depth) {
  return gb_depth[y * width + x];
}

/* Decodes pixel (x,y); returns 0 for background (surface left untouched). */
static inline int ts_load_surface(int x, int y, float4 camera, TS_GBUFFER_PARAMS, ts_surface *s) {
  int width = (int)camera.z;
  int i = y * width + x;
  float depth = gb_depth[i];
  if (depth <= 0.0f) return 0;
  s->P = ts_view_position(x, y, depth, camera.x, camera.y, width, (int)camera.w);
  s->V = normalize(-s->P);
  s->N = normalize(TS_LOAD4(i, gb_normal).xyz);
  s->kd = TS_LOAD4(i, gb_diffuse).xyz;
  float4 spec = TS_LOAD4(i, gb_specular);
  s->ks = spec.xyz;
  s->shininess = spec.w;
  s->ke = TS_LOAD4(i, gb_emissive).xyz;
  return 1;
}

/* Lights: view-space position + range in one float4, colour (intensity included) in another. */
static inline float3 ts_shade_light(const ts_surface *s, float4 pos_range, float4 color, int model) {
  return ts_point_light(s->P, s->N, s->V, s->kd, s->ks, s->shininess, pos_range.xyz, color.xyz,
                        pos_range.w, model);
}

#endif
