/*
 * The one shading function of tileshade, shared by every technique's kernels, the CPU reference
 * and the OpenGL forward shaders. It is written in the common subset of OpenCL C, C++ and GLSL
 * (with the few macros below, which shaders/opencl_as_glsl.h redefines for GLSL) so the three
 * cannot drift.
 *
 * The includer defines the scalar and vector types first:
 *   TS_REAL          scalar type            (float in kernels; double in the reference)
 *   TS_REAL3/4       3-/4-vectors of it     (float3/float4; glm::dvec3/dvec4)
 *   TS_MAKE3(x,y,z)  builds a TS_REAL3
 * and makes dot, sqrt, pow, max, min, clamp visible for those types (OpenCL has them built in;
 * src/reference/shading_cpu.h provides them for C++). TS_LIT(x) writes a literal of TS_REAL (a
 * float literal in kernels, so devices without fp64 see no double).
 *
 * Everything is in view space: camera at the origin looking down -Z. The model, its hard cases
 * and the reasons for each choice are in docs/shading.md. In short, for a light with colour C
 * (intensity included) reaching surface point P from unit direction l:
 *
 *   contribution = C * falloff * (wd*kd + ws*ks + wf)            (rgb: kd, ks per pixel)
 *
 * falloff (punctual lights; 1 for directional ones):
 *   window(d)  = clamp(1 - (d/r)^4, 0, 1)^2         windowed model; 1 in the physical model
 *   angular    = clamp((dot(-l, axis) - cos_outer) * angle_scale, 0, 1)^2    spot lights only
 *   falloff    = window * angular / max(d^2, dmin^2)
 * weights, with ndl = max(dot(N, l), 0) and h = normalize(l + V):
 *   Blinn-Phong         wd = ndl   ws = ndl * max(dot(N,h),0)^s   wf = 0
 *                       kd, ks: the material's
 *   metallic-roughness  wd = ndl (1-Fc)   ws = ndl (1-Fc) S   wf = ndl Fc S       (glTF spec)
 *                       Fc = (1 - dot(V,h))^5, S = pi * D_GGX * V_Smith (separable Smith-GGX),
 *                       kd = (1-F0) c_diff, ks = F0 (ts_metallic_roughness_terms)
 * Both are continuous everywhere: every term carries ndl, so nothing jumps where N.l = 0.
 *   pixel = ke + a*c_diff + sum over lights;  background = 0
 *
 * Build-time choices (kernels pass them as constants to the runtime parameters below, so the
 * compiler removes what a scene does not need; the reference passes the same values at run time):
 *   model     TS_MODEL_WINDOWED | TS_MODEL_PHYSICAL (range cut or not)
 *   shading   TS_SHADING_BLINN_PHONG | TS_SHADING_METALLIC_ROUGHNESS
 *   specular  0: Lambert only (ws = wf = 0; no V, h or material exponent needed)
 *   spot      0: every punctual light is a point light (the angular term is never computed)
 */
#ifndef TS_REAL
#error "define TS_REAL, TS_REAL3, TS_REAL4 and TS_MAKE3 before including shading.h"
#endif
/* The constructs GLSL spells differently (shaders/opencl_as_glsl.h gives its spellings): a cast,
 * a struct type, a read-only struct parameter and an output parameter (pointers in C, `in` and
 * `out` in GLSL) and their dereference and address. */
#ifndef TS_CAST
#define TS_CAST(type, x) ((type)(x))
#define TS_STRUCT_BEGIN(name) typedef struct
#define TS_STRUCT_END(name) name
#define TS_IN(type, name) const type *name
#define TS_OUT(type, name) type *name
#define TS_DEREF(p) (*(p))
#define TS_ADDR(x) (&(x))
#endif
#ifndef TS_LIT
#define TS_LIT(x) TS_CAST(TS_REAL, x)
#endif

/* dmin: the distance (scene units) below which the inverse-square falloff stops growing, so a
 * light touching a surface gives a finite value. One documented constant for every technique. */
#define TS_DMIN 0.1
#define TS_INV_DMIN2 100.0 /* 1 / TS_DMIN^2 */
/* The smallest metallic-roughness roughness: GGX with roughness 0 is a delta (D infinite at
 * N = h, 0/0 elsewhere); 0.045 (alpha = 0.002) is the value fp32 renderers use (Filament). */
#define TS_MIN_ROUGHNESS 0.045

/* The square root and power used by the shading function; kernels/gbuffer.h swaps in the
 * native_ variants for the "native" arithmetic knob. */
#ifndef TS_SQRT
#define TS_SQRT sqrt
#endif
#ifndef TS_RSQRT
#define TS_RSQRT rsqrt
#endif
#ifndef TS_POW
#define TS_POW pow
#endif

/* Cost of one contributing evaluation, for the device-limit estimate of the benchmark, in
 * floating-point operations (sqrt, divide and pow counted as one each). */
#define TS_SHADE_FLOPS_BLINN_PHONG 60
#define TS_SHADE_FLOPS_METALLIC_ROUGHNESS 96
#define TS_SHADE_FLOPS TS_SHADE_FLOPS_BLINN_PHONG

/* Range models. */
#define TS_MODEL_WINDOWED 0
#define TS_MODEL_PHYSICAL 1
/* Shading models (SceneFeatures::model). */
#define TS_SHADING_BLINN_PHONG 0
#define TS_SHADING_METALLIC_ROUGHNESS 1

/* View-space position of pixel (x,y) at linear depth `depth` (= -z_view > 0). Pixel centres sit at
 * +0.5; image row 0 is the top of the screen. tan_x/tan_y: tangents of the half field of view. */
static inline TS_REAL3 ts_view_position(int x, int y, TS_REAL depth, TS_REAL tan_x, TS_REAL tan_y,
                                        int width, int height) {
  TS_REAL ndc_x =
      (TS_LIT(2.0) * (TS_CAST(TS_REAL, x) + TS_LIT(0.5))) / TS_CAST(TS_REAL, width) - TS_LIT(1.0);
  TS_REAL ndc_y =
      TS_LIT(1.0) - (TS_LIT(2.0) * (TS_CAST(TS_REAL, y) + TS_LIT(0.5))) / TS_CAST(TS_REAL, height);
  return TS_MAKE3(ndc_x * tan_x * depth, ndc_y * tan_y * depth, -depth);
}

/* ---- Per-pixel material terms ------------------------------------------------------------ */

/* The terms of a metallic-roughness surface (glTF 2.0, Appendix B) that the light weights use:
 * c_diff = base (1 - metallic) (also what the ambient term lights), F0 = mix(0.04, base,
 * metallic), kd = (1 - F0) c_diff (the diffuse colour the Fresnel-weighted lights see) and
 * alpha = max(roughness, TS_MIN_ROUGHNESS)^2. */
static inline void ts_metallic_roughness_terms(TS_REAL3 base, TS_REAL metallic, TS_REAL roughness,
                                               TS_OUT(TS_REAL3, c_diff), TS_OUT(TS_REAL3, kd),
                                               TS_OUT(TS_REAL3, f0), TS_OUT(TS_REAL, alpha)) {
  TS_REAL m = clamp(metallic, TS_LIT(0.0), TS_LIT(1.0));
  TS_DEREF(c_diff) = base * (TS_LIT(1.0) - m);
  TS_DEREF(f0) = TS_MAKE3(TS_LIT(0.04), TS_LIT(0.04), TS_LIT(0.04)) * (TS_LIT(1.0) - m) + base * m;
  TS_DEREF(kd) = (TS_MAKE3(TS_LIT(1.0), TS_LIT(1.0), TS_LIT(1.0)) - TS_DEREF(f0)) * TS_DEREF(c_diff);
  TS_REAL r = clamp(roughness, TS_LIT(TS_MIN_ROUGHNESS), TS_LIT(1.0));
  TS_DEREF(alpha) = r * r;
}

/* The view factor of the separable Smith-GGX visibility (the glTF specification's form), per pixel:
 * N.V + sqrt(alpha^2 + (1 - alpha^2) (N.V)^2), with N.V clamped to [0, 1]. */
static inline TS_REAL ts_smith_view_term(TS_REAL3 N, TS_REAL3 V, TS_REAL alpha) {
  TS_REAL nv = clamp(dot(N, V), TS_LIT(0.0), TS_LIT(1.0));
  TS_REAL a2 = alpha * alpha;
  return nv + TS_SQRT(a2 + (TS_LIT(1.0) - a2) * nv * nv);
}

/* The light-independent part of a pixel: emission plus the global ambient term a*c_diff. */
static inline TS_REAL3 ts_surface_base(TS_REAL3 ke, TS_REAL3 c_diff, TS_REAL3 ambient) {
  return ke + ambient * c_diff;
}

/* ---- Lanes ------------------------------------------------------------------------------
 * The light terms below are written once for a "lane" type TS_LANE: by default the scalar TS_REAL
 * (one pixel: float in kernels, double in the reference), or an OpenCL vector of TS_LANES floats
 * that shades that many pixels against the same light at once (kernels/lanes.h; CPU devices,
 * where a compiler does not vectorise a per-pixel light loop by itself). The code therefore
 * branches only on "any lane": TS_ANY is the condition itself for a scalar and any() for a vector,
 * and per-lane choices are TS_SELECT (OpenCL's ?: works per component on vectors). For a scalar
 * the early exits are ordinary branches: no cost for the GPU or the reference. */
#ifndef TS_LANE
#define TS_LANE TS_REAL
#define TS_ANY(c) (c)
#endif
#define TS_SELECT(c, a, b) ((c) ? (a) : (b))

/* The surface terms the light weights need, one TS_LANE per component. */
TS_STRUCT_BEGIN(ts_shading_point) {
  TS_LANE px, py, pz; /* view-space position P */
  TS_LANE nx, ny, nz; /* unit normal N */
  TS_LANE vx, vy, vz; /* unit view vector V = normalize(-P) (specular only) */
  TS_LANE gloss;      /* Blinn-Phong: shininess s; metallic-roughness: alpha (specular only) */
  TS_LANE view_term;  /* metallic-roughness: ts_smith_view_term (specular only) */
} TS_STRUCT_END(ts_shading_point);

/* The three weights of a light (see the top of this file): contribution = C (wd kd + ws ks + wf). */
TS_STRUCT_BEGIN(ts_light_weights_t) {
  TS_LANE wd, ws, wf;
} TS_STRUCT_END(ts_light_weights_t);

/* The weights of a light from unit direction (ux, uy, uz) with `falloff` already known (finite,
 * >= 0). A lane whose direction is NaN (the light on the point) compares false in every select
 * below and gets 0; selects, not max(), because max() is undefined for NaN in OpenCL. */
static inline ts_light_weights_t ts_brdf_weights(TS_IN(ts_shading_point, p), TS_LANE ux, TS_LANE uy,
                                                 TS_LANE uz, TS_LANE falloff, int shading,
                                                 int specular) {
  const TS_LANE zero = TS_CAST(TS_LANE, TS_LIT(0.0)), one = TS_CAST(TS_LANE, TS_LIT(1.0));
  ts_light_weights_t w = {zero, zero, zero};
  TS_LANE n_dot_l = TS_DEREF(p).nx * ux + TS_DEREF(p).ny * uy + TS_DEREF(p).nz * uz;
  TS_LANE ndl = TS_SELECT(n_dot_l > zero, n_dot_l, zero);
  TS_LANE lit = falloff * ndl;
  if (!TS_ANY(lit > zero)) return w;
  w.wd = lit;
  if (specular == 0) return w;
  /* h = (l + V) / |l + V|, as a reciprocal square root; l = -V (no half vector) gives h = 0: no
   * specular term (and no Fresnel weight) for that lane. */
  TS_LANE hx = ux + TS_DEREF(p).vx, hy = uy + TS_DEREF(p).vy, hz = uz + TS_DEREF(p).vz;
  TS_LANE hlen2 = hx * hx + hy * hy + hz * hz;
  TS_LANE inv_h = TS_SELECT(hlen2 > zero, TS_RSQRT(hlen2), zero);
  TS_LANE ndh = max((TS_DEREF(p).nx * hx + TS_DEREF(p).ny * hy + TS_DEREF(p).nz * hz) * inv_h, zero);
  if (shading == TS_SHADING_BLINN_PHONG) {
    w.ws = lit * TS_POW(ndh, TS_DEREF(p).gloss);
    return w;
  }
  /* GGX's pi*D: alpha^2 / ((N.h)^2 (alpha^2 - 1) + 1)^2 with 1 - (N.h)^2 = |N x h|^2, which keeps
   * its precision where N.h -> 1 (the peak, for small alpha) instead of cancelling; 0 for
   * microfacets facing away (N.h <= 0), where the denominator can vanish. */
  TS_LANE cx = TS_DEREF(p).ny * hz - TS_DEREF(p).nz * hy, cy = TS_DEREF(p).nz * hx - TS_DEREF(p).nx * hz, cz = TS_DEREF(p).nx * hy - TS_DEREF(p).ny * hx;
  TS_LANE a2 = TS_DEREF(p).gloss * TS_DEREF(p).gloss;
  TS_LANE den = (cx * cx + cy * cy + cz * cz) * (inv_h * inv_h) + ndh * ndh * a2;
  TS_LANE d_pi = TS_SELECT(ndh > zero, a2 / (den * den), zero);
  /* Separable Smith-GGX visibility with 4 N.l N.v folded in: 1 / (light term * view term). */
  TS_LANE light_term = ndl + TS_SQRT(a2 + (one - a2) * ndl * ndl);
  TS_LANE s = d_pi / (light_term * TS_DEREF(p).view_term);
  TS_LANE vdh = clamp((TS_DEREF(p).vx * hx + TS_DEREF(p).vy * hy + TS_DEREF(p).vz * hz) * inv_h, zero, one);
  TS_LANE f1 = one - vdh, f2 = f1 * f1;
  TS_LANE fc = TS_SELECT(hlen2 > zero, f2 * f2 * f1, zero); /* Schlick: F = F0 + (1 - F0) fc */
  w.wd = lit * (one - fc);
  w.ws = w.wd * s;
  w.wf = lit * fc * s;
  return w;
}

/* The weights of a point or spot light at (lx, ly, lz) with range r and inv_r2 = 1/r^2 (a
 * per-light constant: the lane kernels compute it once per light for all their lanes). A spot
 * light shines along the unit axis (ax, ay, az) within the cone whose half-angle has cosine
 * cos_outer, fading in with angle_scale = 1/(cos inner - cos outer); a point light has axis 0 and
 * cos_outer -1, which makes the angular term exactly 1. Lanes outside the range or the cone, or
 * with the light exactly on the point (no direction: it lights nothing, instead of NaN), get 0. */
static inline ts_light_weights_t ts_punctual_weights(TS_IN(ts_shading_point, p), TS_LANE lx,
                                                     TS_LANE ly, TS_LANE lz, TS_LANE r,
                                                     TS_LANE inv_r2, TS_LANE ax, TS_LANE ay,
                                                     TS_LANE az, TS_LANE cos_outer,
                                                     TS_LANE angle_scale, int model, int shading,
                                                     int specular, int spot) {
  const TS_LANE zero = TS_CAST(TS_LANE, TS_LIT(0.0)), one = TS_CAST(TS_LANE, TS_LIT(1.0));
  ts_light_weights_t none = {zero, zero, zero};
  TS_LANE vx = lx - TS_DEREF(p).px, vy = ly - TS_DEREF(p).py, vz = lz - TS_DEREF(p).pz;
  TS_LANE d2 = vx * vx + vy * vy + vz * vz;
  TS_LANE window = one;
  if (model == TS_MODEL_WINDOWED) {
    TS_LANE r2 = r * r;
    if (!TS_ANY(d2 < r2)) return none; /* the common exit: no lane in range */
    TS_LANE q = d2 * inv_r2;           /* (d/r)^2, so (d/r)^4 = q*q without a sqrt */
    TS_LANE w = max(one - q * q, zero);
    window = TS_SELECT(d2 < r2, w * w, zero); /* the cut itself is exact: d2 < r*r */
  }
  /* One reciprocal square root gives the direction and the inverse square; where d2 = 0 it is
   * infinite and l is NaN, which the selects below and in ts_brdf_weights turn into 0. */
  TS_LANE inv_d = TS_RSQRT(d2);
  TS_LANE ux = vx * inv_d, uy = vy * inv_d, uz = vz * inv_d;
  TS_LANE inv_dmin2 = TS_CAST(TS_LANE, TS_LIT(TS_INV_DMIN2));
  TS_LANE falloff = window * min(inv_d * inv_d, inv_dmin2); /* window / max(d2, dmin^2) */
  if (spot != 0) {
    TS_LANE cd = -(ax * ux + ay * uy + az * uz); /* cosine between the axis and the light ray */
    TS_LANE t = clamp((cd - cos_outer) * angle_scale, zero, one);
    falloff = TS_SELECT(d2 > zero, falloff * t * t, zero);
  }
  return ts_brdf_weights(p, ux, uy, uz, falloff, shading, specular);
}

/* The weights of a directional light arriving from the unit direction (lx, ly, lz) (towards the
 * light): no range, no falloff. */
static inline ts_light_weights_t ts_directional_weights(TS_IN(ts_shading_point, p), TS_LANE lx,
                                                        TS_LANE ly, TS_LANE lz, int shading,
                                                        int specular) {
  return ts_brdf_weights(p, lx, ly, lz, TS_CAST(TS_LANE, TS_LIT(1.0)), shading, specular);
}

#if !defined(TS_LANES) || TS_LANES == 1
/* ---- One pixel ---------------------------------------------------------------------------
 * The vector forms every per-pixel kernel and the reference call. */

/* The shading point of a surface: P, N, V and, when the specular term is on, its gloss and
 * (metallic-roughness) the per-pixel Smith view term. */
static inline ts_shading_point ts_make_shading_point(TS_REAL3 P, TS_REAL3 N, TS_REAL3 V,
                                                     TS_REAL gloss, int shading) {
  ts_shading_point p = {P.x, P.y, P.z, N.x, N.y, N.z, V.x, V.y, V.z, gloss, TS_LIT(0.0)};
  if (shading == TS_SHADING_METALLIC_ROUGHNESS) p.view_term = ts_smith_view_term(N, V, gloss);
  return p;
}

static inline TS_REAL3 ts_weighted_color(ts_light_weights_t w, TS_REAL3 C, TS_REAL3 kd,
                                         TS_REAL3 ks) {
  return C * (w.wd * kd + w.ws * ks + TS_MAKE3(w.wf, w.wf, w.wf));
}

/* Contribution of one point or spot light (kernels/shading.h "Lights" layout: pos_range =
 * position + range, color = rgb + spot angle scale, spot = axis + cos outer). */
static inline TS_REAL3 ts_punctual_light(TS_IN(ts_shading_point, p), TS_REAL3 kd, TS_REAL3 ks,
                                         TS_REAL4 pos_range, TS_REAL4 color, TS_REAL4 spot,
                                         int model, int shading, int specular, int spot_on) {
  ts_light_weights_t w = ts_punctual_weights(
      p, pos_range.x, pos_range.y, pos_range.z, pos_range.w,
      TS_LIT(1.0) / (pos_range.w * pos_range.w), spot.x, spot.y, spot.z, spot.w, color.w, model,
      shading, specular, spot_on);
  return ts_weighted_color(w, TS_MAKE3(color.x, color.y, color.z), kd, ks);
}

/* Contribution of one directional light (dir: unit vector towards the light). */
static inline TS_REAL3 ts_directional_light(TS_IN(ts_shading_point, p), TS_REAL3 kd, TS_REAL3 ks,
                                            TS_REAL3 dir, TS_REAL3 color, int shading,
                                            int specular) {
  ts_light_weights_t w = ts_directional_weights(p, dir.x, dir.y, dir.z, shading, specular);
  return ts_weighted_color(w, color, kd, ks);
}

/* A Blinn-Phong point light at Lp (colour C, range r) on the surface P, N, V = normalize(-P),
 * kd, ks, shininess s: the papers' case, for tests and examples. */
static inline TS_REAL3 ts_point_light(TS_REAL3 P, TS_REAL3 N, TS_REAL3 V, TS_REAL3 kd, TS_REAL3 ks,
                                      TS_REAL s, TS_REAL3 Lp, TS_REAL3 C, TS_REAL r, int model) {
  ts_shading_point p = ts_make_shading_point(P, N, V, s, TS_SHADING_BLINN_PHONG);
  ts_light_weights_t w = ts_punctual_weights(TS_ADDR(p), Lp.x, Lp.y, Lp.z, r, TS_LIT(1.0) / (r * r),
                                             TS_LIT(0.0), TS_LIT(0.0), TS_LIT(0.0), TS_LIT(-1.0),
                                             TS_LIT(1.0), model, TS_SHADING_BLINN_PHONG, 1, 0);
  return ts_weighted_color(w, C, kd, ks);
}
#endif
