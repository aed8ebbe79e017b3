/*
 * G-buffer access and the shading entry points of every technique's kernels: one function decodes
 * a pixel into the values the shading function takes (ts_load_surface), one shades a light
 * (ts_shade_punctual, ts_shade_directionals). The per-element decoders are in
 * kernels/gbuffer_codecs.h, which the host decodes with too (src/gbuffer/gbuffer_layout.cpp:
 * decodeSurface, decodeStored); tests check the two agree through the `decode_gbuffer` kernel
 * (kernels/dump.cl): GBufferDecode (tests/gbuffer/gbuffer_decode_test.cpp),
 * MetallicRoughnessDecode and AccuracyKnobs.PackedDecodeMatchesTheHostForEveryCode.
 *
 * Planes (one element per pixel, row-major, row 0 = top of the screen), present only when the
 * scene needs them (SceneFeatures; the layout table is in docs/accuracy.md, "G-buffer precision"):
 *   depth     float         linear view depth -z_view; 0 = background (no geometry). Always.
 *   normal    view-space normal (renormalised after decoding); fp32/fp16 metallic-roughness:
 *             roughness in w. Always.
 *   diffuse   Blinn-Phong kd rgb; metallic-roughness base colour rgb + metallic. Always.
 *   specular  Blinn-Phong ks rgb + shininess (TS_HAS_SPECULAR); packed metallic-roughness:
 *             roughness (unorm8). Otherwise absent.
 *   emissive  ke rgb (TS_HAS_EMISSIVE). Otherwise absent.
 * An absent plane is still a kernel argument (a one-element buffer) and is never read.
 * Precisions (build option): fp32 (float4 elements, default), TS_GBUFFER_FP16 (half4, read with
 * vload_half4), TS_GBUFFER_PACKED (octahedral normals, unorm8 colours; below). Depth stays
 * float32 in every layout, as in the paper.
 *
 * Scene features (SceneFeatures::kernelDefines): TS_SHADING, TS_HAS_SPECULAR, TS_HAS_EMISSIVE,
 * TS_HAS_SPOT, TS_HAS_DIRECTIONAL (all default to the general pipeline) and TS_HAS_SHADOWS
 * (defined only when a light casts a shadow; kernels/shadows.h).
 */
#ifndef TS_GBUFFER_H
#define TS_GBUFFER_H

#define TS_REAL float
#define TS_REAL3 float3
#define TS_REAL4 float4
#define TS_MAKE3(x, y, z) ((float3)((x), (y), (z)))
#define TS_MAKE4(x, y, z, w) ((float4)((x), (y), (z), (w)))
/* Literals are float literals here: no double reaches a device without fp64. */
#define TS_LIT_(x) x##f
#define TS_LIT(x) TS_LIT_(x)

#ifndef TS_SHADING
#define TS_SHADING 0 /* TS_SHADING_BLINN_PHONG */
#endif
#ifndef TS_HAS_SPECULAR
#define TS_HAS_SPECULAR 1
#endif
#ifndef TS_HAS_EMISSIVE
#define TS_HAS_EMISSIVE 1
#endif
#ifndef TS_HAS_SPOT
#define TS_HAS_SPOT 1
#endif
#ifndef TS_HAS_DIRECTIONAL
#define TS_HAS_DIRECTIONAL 1
#endif
#ifndef TS_MODEL
#define TS_MODEL 0 /* TS_MODEL_WINDOWED */
#endif
#ifndef TS_SPOT_CULL
#define TS_SPOT_CULL 0 /* TS_SPOT_CULL_CONE */
#endif
#ifndef TS_DEPTH_SPLIT
#define TS_DEPTH_SPLIT 0 /* tiles: one depth range (kernels/tiled.cl) */
#endif
/* The metallic-roughness model always has its specular term (F0 >= 0.04). */
#if TS_SHADING == 1
#undef TS_HAS_SPECULAR
#define TS_HAS_SPECULAR 1
#endif

/* TS_LANES > 1 (build option, CPU devices): the light terms work on vectors of TS_LANES pixels
 * (kernels/shading.h, kernels/lanes.h). */
#ifndef TS_LANES
#define TS_LANES 1
#endif
#if TS_LANES > 1
#define TS_LANE_VECTOR(n) float##n
#define TS_LANE_TYPE(n) TS_LANE_VECTOR(n)
#define TS_LANE TS_LANE_TYPE(TS_LANES)
#define TS_MASK_VECTOR(n) int##n
#define TS_MASK_TYPE(n) TS_MASK_VECTOR(n)
/* "Any lane". PoCL's any() tests the components one by one with a branch each: about 40
 * instructions for 16 lanes, several times per light evaluation. On PoCL (the host defines
 * TS_POCL) clang's vector reduction becomes one mask test (kortest); elsewhere (Oclgrind cannot
 * execute LLVM's vector reductions) the components are ORed, no branch, and the sign bit of the
 * result is the answer. */
#if defined(TS_POCL) && defined(__has_builtin)
#if __has_builtin(__builtin_reduce_or)
#define TS_HAVE_REDUCE_OR 1
#endif
#endif
#ifdef TS_HAVE_REDUCE_OR
static inline int ts_any_lanes(TS_MASK_TYPE(TS_LANES) m) { return __builtin_reduce_or(m) != 0; }
#else
static inline int ts_any_lanes(TS_MASK_TYPE(TS_LANES) m) {
  int any = m.s0 | m.s1;
#if TS_LANES >= 4
  any |= m.s2 | m.s3;
#endif
#if TS_LANES >= 8
  any |= m.s4 | m.s5 | m.s6 | m.s7;
#endif
#if TS_LANES == 16
  any |= m.s8 | m.s9 | m.sa | m.sb | m.sc | m.sd | m.se | m.sf;
#endif
  return any < 0;
}
#endif
#define TS_ANY(c) ts_any_lanes(c)
#else
#define TS_LANE float
#define TS_ANY(c) (c)
#endif
#ifdef TS_NATIVE_MATH
/* Shading arithmetic knob: the native_ functions (implementation-defined accuracy) inside the
 * shading function only; culling below keeps the precise ones so it stays conservative. The
 * specular power is ts_pow_unit below with native_exp2, not native_powr: PoCL's native_powr is its
 * full-precision powr, an out-of-line call of ~500 instructions (an extended-precision log and
 * exp) with the live vector registers spilled around each of its three call sites, which made
 * `--math native` 2.7x slower than precise (issue #19). */
#define TS_SQRT native_sqrt
#define TS_RSQRT native_rsqrt
#define TS_EXP2 native_exp2
#else
#define TS_EXP2 exp2
#endif
/* The specular power x^s has x = max(N.h, 0) in [0, 1] and s >= 1. OpenCL's pow also handles
 * negative bases and integer exponents, and on PoCL that generality cost ~3x the rest of a light
 * evaluation, so the kernels compute exp2(s*log2(x)). And PoCL's log2 is an out-of-line call:
 * every live vector register (the lanes' surfaces and sums, ~20 of them) was saved and restored
 * around it, once per light evaluation. ts_log2_positive below is inline: the exponent from the
 * bits, the mantissa m in [sqrt(1/2), sqrt(2)) and log2(m) = f*q(f), f = m - 1, with q a degree-8
 * polynomial (weighted least-squares fit; 2.3 ulp of relative error measured over the interval,
 * the same order as log2's own 3-ulp allowance). The result x^s is exact at x = 0 and within
 * ~(0.7*|s*log2 x|*3.5 + 3) ulp elsewhere, below 4e-6 relative wherever x^s >= 2^-24
 * (docs/accuracy.md); x below FLT_MIN gives 0. */
#if TS_LANES > 1
#define TS_AS_INT_(n) as_int##n
#define TS_AS_INT(n) TS_AS_INT_(n)
#define TS_AS_LANE_(n) as_float##n
#define TS_AS_LANE(n) TS_AS_LANE_(n)
#define TS_INT_TO_LANE_(n) convert_float##n
#define TS_INT_TO_LANE(n) TS_INT_TO_LANE_(n)
#define TS_LANE_AS_INT TS_AS_INT(TS_LANES)
#define TS_INT_AS_LANE TS_AS_LANE(TS_LANES)
#define TS_LANE_FROM_INT TS_INT_TO_LANE(TS_LANES)
#define TS_LANE_INT TS_MASK_TYPE(TS_LANES)
#else
#define TS_LANE_AS_INT as_int
#define TS_INT_AS_LANE as_float
#define TS_LANE_FROM_INT convert_float
#define TS_LANE_INT int
#endif
static inline TS_LANE ts_log2_positive(TS_LANE x) {
  TS_LANE_INT bits = TS_LANE_AS_INT(x);
  TS_LANE_INT e = (bits >> 23) - 127;
  TS_LANE m = TS_INT_AS_LANE((bits & 0x007fffff) | 0x3f800000); /* [1, 2) */
  TS_LANE_INT big = m > 1.41421356f; /* scalar: 1 or 0; vector: -1 or 0 per lane */
  m = big ? m * 0.5f : m;
  e += big ? (TS_LANE_INT)1 : (TS_LANE_INT)0;
  TS_LANE f = m - 1.0f; /* exact */
  TS_LANE q = 0.125840425f;
  q = q * f - 0.20727697f;
  q = q * f + 0.215717539f;
  q = q * f - 0.238943845f;
  q = q * f + 0.287915945f;
  q = q * f - 0.360703707f;
  q = q * f + 0.480910659f;
  q = q * f - 0.721347332f;
  q = q * f + 1.44269502f;
  return TS_LANE_FROM_INT(e) + f * q;
}
static inline TS_LANE ts_pow_unit(TS_LANE x, TS_LANE s) {
  TS_LANE p = TS_EXP2(s * ts_log2_positive(x));
  p = x >= FLT_MIN ? p : (TS_LANE)0.0f;
  return s == (TS_LANE)0.0f ? (TS_LANE)1.0f : p;
}
#define TS_POW ts_pow_unit
#include "shading.h"
#include "culling.h"
#define TS_FLOAT3 float3
#define TS_MAKE_FLOAT3(x, y, z) ((float3)((x), (y), (z)))
#include "gbuffer_codecs.h"

/* ---- Per-plane element types and decoders of the three precisions ---------------------- */
#if defined(TS_GBUFFER_PACKED)
/* packed: normal = octahedral, 2 x snorm16 in one uint; diffuse = unorm8 RGBA (metallic-roughness:
 * base colour + metallic); specular = unorm8 RGB + shininess byte b, s = 2^(11 b/255) (1..2048),
 * or (metallic-roughness) unorm8 roughness; emissive = half4 (HDR). */
typedef uint ts_gb_normal;
typedef uint ts_gb_diffuse;
#if TS_SHADING == 1
typedef uchar ts_gb_specular;
#else
typedef uint ts_gb_specular;
#endif
typedef half ts_gb_emissive;
static inline float4 ts_decode_normal(int i, __global const ts_gb_normal *p) {
  return (float4)(normalize(ts_decode_octahedral(p[i])), 0.0f);
}
static inline float4 ts_decode_diffuse(int i, __global const ts_gb_diffuse *p) {
  uint v = p[i];
  return (float4)(ts_decode_unorm8x3(v), ts_decode_unorm8(v >> 24));
}
#if TS_SHADING == 1
static inline float4 ts_decode_specular(int i, __global const ts_gb_specular *p) {
  return (float4)(ts_decode_roughness_byte(p[i]), 0.0f, 0.0f, 0.0f);
}
#else
static inline float4 ts_decode_specular(int i, __global const ts_gb_specular *p) {
  uint v = p[i];
  return (float4)(ts_decode_unorm8x3(v), ts_decode_shininess(v >> 24));
}
#endif
static inline float3 ts_decode_emissive(int i, __global const ts_gb_emissive *p) {
  return vload_half4(i, p).xyz;
}
/* Roughness (metallic-roughness): in the specular plane. */
static inline float ts_decode_roughness(int i, float4 normal, __global const ts_gb_specular *p) {
  return ts_decode_specular(i, p).x;
}
#else
#if defined(TS_GBUFFER_FP16)
/* fp16: every plane half4, read with vload_half4 (exact conversion). */
typedef half ts_gb_elem;
#define TS_LOAD4(i, p) vload_half4((i), (p))
#else
/* fp32: every plane float4. */
typedef float ts_gb_elem;
#define TS_LOAD4(i, p) vload4((i), (p))
#endif
typedef ts_gb_elem ts_gb_normal;
typedef ts_gb_elem ts_gb_diffuse;
typedef ts_gb_elem ts_gb_specular;
typedef ts_gb_elem ts_gb_emissive;
static inline float4 ts_decode_normal(int i, __global const ts_gb_normal *p) {
  float4 n = TS_LOAD4(i, p);
  return (float4)(normalize(n.xyz), n.w);
}
static inline float4 ts_decode_diffuse(int i, __global const ts_gb_diffuse *p) {
  return TS_LOAD4(i, p);
}
static inline float4 ts_decode_specular(int i, __global const ts_gb_specular *p) {
  return TS_LOAD4(i, p);
}
static inline float3 ts_decode_emissive(int i, __global const ts_gb_emissive *p) {
  return TS_LOAD4(i, p).xyz;
}
/* Roughness (metallic-roughness): in the normal's w. */
static inline float ts_decode_roughness(int i, float4 normal, __global const ts_gb_specular *p) {
  return normal.w;
}
#endif

/* Kernel parameters and arguments for the G-buffer planes; keeps every signature in step. */
#define TS_GBUFFER_PARAMS                                                                        \
  __global const float *gb_depth, __global const ts_gb_normal *gb_normal,                        \
      __global const ts_gb_diffuse *gb_diffuse, __global const ts_gb_specular *gb_specular,      \
      __global const ts_gb_emissive *gb_emissive
#define TS_GBUFFER_ARGS gb_depth, gb_normal, gb_diffuse, gb_specular, gb_emissive

/* Kernel parameters and arguments for the lights (ts::ViewLights): point and spot lights (the
 * culled ones; kernels/shading.h "Lights") and the directional lights (never culled). */
#ifndef TS_HAS_SHADOWS
#define TS_LIGHT_PARAMS                                                                          \
  __global const float4 *light_pos_range, __global const float4 *light_color,                    \
      __global const float4 *light_spot
#define TS_LIGHT_ARGS light_pos_range, light_color, light_spot
#define TS_DIRECTIONAL_PARAMS                                                                    \
  __global const float4 *dir_light_dir, __global const float4 *dir_light_color,                  \
      int dir_light_count
#define TS_DIRECTIONAL_ARGS dir_light_dir, dir_light_color, dir_light_count
/* The same with another count (`n` of them: 0 = none). */
#define TS_DIRECTIONAL_ARGS_COUNT(n) dir_light_dir, dir_light_color, (n)
#else
/* With shadows (TS_HAS_SHADOWS, the `shadows` feature) each group also has, per light, its first
 * shadow face (-1: none) and the face table and atlas (kernels/shadows.h); the two groups get the
 * same two buffers under their own names, so a kernel may take either group or both. */
#define TS_LIGHT_PARAMS                                                                          \
  __global const float4 *light_pos_range, __global const float4 *light_color,                    \
      __global const float4 *light_spot, __global const int *light_shadow,                       \
      __global const float4 *shadow_faces, __global const float *shadow_atlas
#define TS_LIGHT_ARGS                                                                            \
  light_pos_range, light_color, light_spot, light_shadow, shadow_faces, shadow_atlas
#define TS_DIRECTIONAL_PARAMS                                                                    \
  __global const float4 *dir_light_dir, __global const float4 *dir_light_color,                  \
      int dir_light_count, __global const int *dir_light_shadow,                                 \
      __global const float4 *dir_shadow_faces, __global const float *dir_shadow_atlas
#define TS_DIRECTIONAL_ARGS                                                                      \
  dir_light_dir, dir_light_color, dir_light_count, dir_light_shadow, dir_shadow_faces,           \
      dir_shadow_atlas
#define TS_DIRECTIONAL_ARGS_COUNT(n)                                                             \
  dir_light_dir, dir_light_color, (n), dir_light_shadow, dir_shadow_faces, dir_shadow_atlas
#include "shadows.h"
#endif

/* A decoded pixel: what the light terms need (kernels/shading.h) and its light-independent base.
 *   kd, ks   the colours the weights wd, ws multiply (Blinn-Phong: the material's; metallic-
 *            roughness: (1 - F0) c_diff and F0)
 *   gloss    Blinn-Phong shininess, metallic-roughness alpha; view_term: its Smith view term
 *   base     emission + ambient * c_diff */
typedef struct {
  float3 P, N, V, kd, ks, base;
  float gloss, view_term;
} ts_surface;

/* Reads the depth only: background test and depth-range work need no more. */
static inline float ts_load_depth(int x, int y, int width, __global const float *gb_depth) {
  return gb_depth[y * width + x];
}

/* Decodes pixel (x,y); returns 0 for background (surface left untouched). camera = (tan x,
 * tan y, width, height). */
static inline int ts_load_surface(int x, int y, float4 camera, float4 ambient, TS_GBUFFER_PARAMS,
                                  ts_surface *s) {
  int width = (int)camera.z;
  int i = y * width + x;
  float depth = gb_depth[i];
  if (depth <= 0.0f) return 0;
  s->P = ts_view_position(x, y, depth, camera.x, camera.y, width, (int)camera.w);
  s->V = normalize(-s->P);
  float4 normal = ts_decode_normal(i, gb_normal);
  s->N = normal.xyz;
  float4 diffuse = ts_decode_diffuse(i, gb_diffuse);
  float3 c_diff;
#if TS_SHADING == 1
  ts_metallic_roughness_terms(diffuse.xyz, diffuse.w, ts_decode_roughness(i, normal, gb_specular),
                              &c_diff, &s->kd, &s->ks, &s->gloss);
  s->view_term = ts_smith_view_term(s->N, s->V, s->gloss);
#else
  c_diff = s->kd = diffuse.xyz;
#if TS_HAS_SPECULAR
  float4 spec = ts_decode_specular(i, gb_specular);
  s->ks = spec.xyz;
  s->gloss = spec.w;
#else
  s->ks = (float3)(0.0f);
  s->gloss = 1.0f;
#endif
  s->view_term = 1.0f;
#endif
#if TS_HAS_EMISSIVE
  float3 ke = ts_decode_emissive(i, gb_emissive);
#else
  float3 ke = (float3)(0.0f);
#endif
  s->base = ts_surface_base(ke, c_diff, ambient.xyz);
  return 1;
}

/* The spot parameters of light `light` (a point light's when the build has no spot lights). */
static inline float4 ts_light_spot(__global const float4 *light_spot, uint light) {
#if TS_HAS_SPOT
  return light_spot[light];
#else
  return (float4)(0.0f, 0.0f, 0.0f, -1.0f);
#endif
}

/* The culling volume of light `light` (kernels/culling.h, TS_SPOT_CULL). */
static inline ts_light_volume ts_load_light_volume(__global const float4 *light_pos_range,
                                                   __global const float4 *light_spot, uint light) {
  return ts_make_light_volume(light_pos_range[light], ts_light_spot(light_spot, light),
                              TS_SPOT_CULL);
}

#if TS_LANES == 1
static inline ts_shading_point ts_surface_point(const ts_surface *s) {
  ts_shading_point p = {s->P.x, s->P.y, s->P.z, s->N.x, s->N.y, s->N.z,
                        s->V.x, s->V.y, s->V.z, s->gloss, s->view_term};
  return p;
}

/* The contribution of point or spot light `light` to the surface. */
static inline float3 ts_shade_punctual(const ts_surface *s, TS_LIGHT_PARAMS, uint light) {
  ts_shading_point p = ts_surface_point(s);
  float3 c = ts_punctual_light(&p, s->kd, s->ks, light_pos_range[light], light_color[light],
                               ts_light_spot(light_spot, light), TS_MODEL, TS_SHADING,
                               TS_HAS_SPECULAR, TS_HAS_SPOT);
#ifdef TS_HAS_SHADOWS
  /* Sampled only where the light reaches: outside its range c is exactly 0 already. */
  int first = light_shadow[light];
  if (first >= 0 && (c.x != 0.0f || c.y != 0.0f || c.z != 0.0f))
    c *= ts_shadow_factor(shadow_faces, shadow_atlas, first, s->P, s->N,
                          normalize(light_pos_range[light].xyz - s->P));
#endif
  return c;
}

/* The summed contributions of every directional light (none in a build without them). */
static inline float3 ts_shade_directionals(const ts_surface *s, TS_DIRECTIONAL_PARAMS) {
  float3 sum = (float3)(0.0f);
#if TS_HAS_DIRECTIONAL
  ts_shading_point p = ts_surface_point(s);
  for (int k = 0; k < dir_light_count; ++k) {
    float3 c = ts_directional_light(&p, s->kd, s->ks, dir_light_dir[k].xyz,
                                    dir_light_color[k].xyz, TS_SHADING, TS_HAS_SPECULAR);
#ifdef TS_HAS_SHADOWS
    int first = dir_light_shadow[k];
    if (first >= 0 && (c.x != 0.0f || c.y != 0.0f || c.z != 0.0f))
      c *= ts_shadow_factor(dir_shadow_faces, dir_shadow_atlas, first, s->P, s->N,
                            dir_light_dir[k].xyz);
#endif
    sum += c;
  }
#endif
  return sum;
}
#endif

#endif
