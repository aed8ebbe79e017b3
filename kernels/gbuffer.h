/*
 * G-buffer access for every technique's kernels: one function decodes a pixel into the values the
 * shading function takes. The host mirror is src/raster/gbuffer_layout.cpp (decodeSurface); a test
 * (GBufferDecode in tests/pipeline_test.cpp) checks the two agree through the `decode_gbuffer`
 * kernel (kernels/dump.cl): colours exactly, positions and normals to float rounding.
 *
 * Planes (one element per pixel, row-major, row 0 = top of the screen):
 *   depth     float         linear view depth -z_view; 0 = background (no geometry)
 *   normal    view-space normal (renormalized after decoding)
 *   diffuse   kd rgb
 *   specular  ks rgb + shininess
 *   emissive  ke rgb
 * Layouts (build option): fp32 (float4 planes, default), TS_GBUFFER_FP16 (half4 planes read with
 * vload_half4), TS_GBUFFER_PACKED (octahedral normals, unorm8 colours; below). Depth stays float32
 * in every layout, as in the paper.
 */
#ifndef TS_GBUFFER_H
#define TS_GBUFFER_H

#define TS_REAL float
#define TS_REAL3 float3
#define TS_MAKE3(x, y, z) ((float3)((x), (y), (z)))
/* TS_LANES > 1 (build option, CPU devices): the light term works on vectors of TS_LANES pixels
 * (kernels/shading.h, kernels/lanes.h). */
#ifndef TS_LANES
#define TS_LANES 1
#endif
#if TS_LANES > 1
#define TS_LANE_VECTOR(n) float##n
#define TS_LANE_TYPE(n) TS_LANE_VECTOR(n)
#define TS_LANE TS_LANE_TYPE(TS_LANES)
#define TS_ANY(c) any(c)
#else
#define TS_LANE float
#define TS_ANY(c) (c)
#endif
#ifdef TS_NATIVE_MATH
/* Shading arithmetic knob: the native_ functions (implementation-defined accuracy) inside the
 * shading function only; culling below keeps the precise ones so it stays conservative. */
#define TS_SQRT native_sqrt
#define TS_POW native_powr
#else
/* The specular power x^s has x = max(N.h, 0) in [0, 1] and s >= 1. OpenCL's pow also handles
 * negative bases and integer exponents, and on PoCL that generality cost ~3x the rest of a light
 * evaluation. exp2(s*log2(x)) is exact at x = 0 (log2 0 = -inf) and its relative error,
 * ~(0.7*|s*log2 x| * 3.5 + 3) ulp, stays below 4e-6 wherever x^s >= 2^-24 — the same order as
 * pow's own 16-ulp allowance (docs/accuracy.md). */
static inline TS_LANE ts_pow_unit(TS_LANE x, TS_LANE s) {
  return s == (TS_LANE)0 ? (TS_LANE)1 : exp2(s * log2(x));
}
#define TS_POW ts_pow_unit
#endif
#include "shading.h"
#define TS_REAL4 float4
#define TS_MAKE4(x, y, z, w) ((float4)((x), (y), (z), (w)))
#include "culling.h"

/* Per-plane element types and decoders of the three layouts. */
#if defined(TS_GBUFFER_PACKED)
/* packed (24 B/pixel): normal = octahedral, 2 x snorm16 in one uint; diffuse = unorm8 RGBA;
 * specular = unorm8 RGB + shininess byte b, s = 2^(11 b/255) (1..2048); emissive = half4 (HDR). */
typedef uint ts_gb_normal;
typedef uint ts_gb_diffuse;
typedef uint ts_gb_specular;
typedef half ts_gb_emissive;
static inline float3 ts_unorm8x3(uint v) {
  return (float3)((float)(v & 255u), (float)((v >> 8) & 255u), (float)((v >> 16) & 255u)) /
         255.0f;
}
static inline float3 ts_decode_normal(int i, __global const ts_gb_normal *p) {
  uint v = p[i];
  float ex = fmax((float)(short)(v & 0xffffu) / 32767.0f, -1.0f);
  float ey = fmax((float)(short)(v >> 16) / 32767.0f, -1.0f);
  float3 n = (float3)(ex, ey, 1.0f - fabs(ex) - fabs(ey));
  if (n.z < 0.0f) {
    float nx = (1.0f - fabs(ey)) * (ex >= 0.0f ? 1.0f : -1.0f);
    float ny = (1.0f - fabs(ex)) * (ey >= 0.0f ? 1.0f : -1.0f);
    n.x = nx;
    n.y = ny;
  }
  return normalize(n);
}
static inline float3 ts_decode_diffuse(int i, __global const ts_gb_diffuse *p) {
  return ts_unorm8x3(p[i]);
}
static inline float4 ts_decode_specular(int i, __global const ts_gb_specular *p) {
  uint v = p[i];
  return (float4)(ts_unorm8x3(v), exp2((float)(v >> 24) * (11.0f / 255.0f)));
}
static inline float3 ts_decode_emissive(int i, __global const ts_gb_emissive *p) {
  return vload_half4(i, p).xyz;
}
#else
#if defined(TS_GBUFFER_FP16)
/* fp16 (36 B/pixel): every plane half4, read with vload_half4 (exact conversion). */
typedef half ts_gb_elem;
#define TS_LOAD4(i, p) vload_half4((i), (p))
#else
/* fp32 (68 B/pixel): every plane float4. */
typedef float ts_gb_elem;
#define TS_LOAD4(i, p) vload4((i), (p))
#endif
typedef ts_gb_elem ts_gb_normal;
typedef ts_gb_elem ts_gb_diffuse;
typedef ts_gb_elem ts_gb_specular;
typedef ts_gb_elem ts_gb_emissive;
static inline float3 ts_decode_normal(int i, __global const ts_gb_normal *p) {
  return normalize(TS_LOAD4(i, p).xyz);
}
static inline float3 ts_decode_diffuse(int i, __global const ts_gb_diffuse *p) {
  return TS_LOAD4(i, p).xyz;
}
static inline float4 ts_decode_specular(int i, __global const ts_gb_specular *p) {
  return TS_LOAD4(i, p);
}
static inline float3 ts_decode_emissive(int i, __global const ts_gb_emissive *p) {
  return TS_LOAD4(i, p).xyz;
}
#endif

/* Kernel parameters and arguments for the G-buffer planes; keeps every signature in step. */
#define TS_GBUFFER_PARAMS                                                                        \
  __global const float *gb_depth, __global const ts_gb_normal *gb_normal,                        \
      __global const ts_gb_diffuse *gb_diffuse, __global const ts_gb_specular *gb_specular,      \
      __global const ts_gb_emissive *gb_emissive
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
  s->N = ts_decode_normal(i, gb_normal);
  s->kd = ts_decode_diffuse(i, gb_diffuse);
  float4 spec = ts_decode_specular(i, gb_specular);
  s->ks = spec.xyz;
  s->shininess = spec.w;
  s->ke = ts_decode_emissive(i, gb_emissive);
  return 1;
}

#if TS_LANES == 1
/* Lights: view-space position + range in one float4, colour (intensity included) in another. */
static inline float3 ts_shade_light(const ts_surface *s, float4 pos_range, float4 color, int model) {
  return ts_point_light(s->P, s->N, s->V, s->kd, s->ks, s->shininess, pos_range.xyz, color.xyz,
                        pos_range.w, model);
}
#endif

#endif
