/*
 * Shading in lanes (build option TS_LANES > 1; the host picks it on CPU devices).
 *
 * Why: a CPU OpenCL compiler (PoCL) runs a work-group's work-items in a loop and vectorises that
 * loop only when a work-item's code is straight-line. A per-pixel loop over a light list is not,
 * so every light evaluation runs in scalar code. In lanes, the work-group first decodes its pixels
 * one per work-item, as always, and stores the shading terms plane by plane in local memory; then
 * one work-item per TS_LANES pixels loads them as vectors and runs the light loop once for all of
 * them with the same shading function (kernels/shading.h with TS_LANE = floatN), the way ISPC's
 * deferred example shades a tile. The sums go back through local memory to their pixels' items.
 * Each lane computes exactly what the per-pixel kernel computes for its pixel; only lights that
 * reach no lane of a vector are skipped early.
 *
 * Layout of the local buffer: TS_LANE_PLANES planes of `slots` floats (slots = the work-group
 * size rounded up to whole vectors; tiled_single.cl uses its tile's pixels and 3 more planes);
 * plane f of pixel slot i is at soa[f * slots + i]. Slots without a lit pixel (background, off
 * screen, padding) hold a surface that no light reaches. Only the terms the scene's features use
 * have planes (a diffuse-only scene stores P, N and kd: 9 planes instead of 17); the host sizes
 * the buffer from the same rule (TechniqueConfig::lanePlanes in src/techniques/registry.cpp,
 * checked at build time through TS_HOST_LANE_PLANES).
 *
 * The includer includes gbuffer.h first (with TS_LANES > 1).
 */
#ifndef TS_LANES_H
#define TS_LANES_H

/* Plane indices: P, N always; V, gloss and ks with a specular term; the Smith view term with
 * metallic-roughness; kd always. */
#define TS_LP_P 0
#define TS_LP_N 3
#if TS_HAS_SPECULAR
#define TS_LP_V 6
#define TS_LP_GLOSS 9
#define TS_LP_KD 10
#define TS_LP_KS 13
#if TS_SHADING == 1
#define TS_LP_VIEW_TERM 16
#define TS_LANE_PLANES 17
#else
#define TS_LANE_PLANES 16
#endif
#else
#define TS_LP_KD 6
#define TS_LANE_PLANES 9
#endif
#ifdef TS_HOST_LANE_PLANES
/* The host's count must be ours (a negative array size stops the build otherwise). */
typedef char ts_lane_planes_match_the_host[TS_LANE_PLANES == TS_HOST_LANE_PLANES ? 1 : -1];
#endif

#define TS_LANE_VLOAD_(n) vload##n
#define TS_LANE_VLOAD(n) TS_LANE_VLOAD_(n)
#define TS_LANE_VSTORE_(n) vstore##n
#define TS_LANE_VSTORE(n) TS_LANE_VSTORE_(n)

/* Pixel slots of the work-group: its items rounded up to whole vectors. */
static inline int ts_lane_slots(void) {
  int group_size = (int)(get_local_size(0) * get_local_size(1));
  return (group_size + TS_LANES - 1) / TS_LANES * TS_LANES;
}

static inline int ts_lane_item(void) {
  return (int)(get_local_id(1) * get_local_size(0) + get_local_id(0));
}

/* Each vector of TS_LANES slots is a compact block of pixels (4x4 for 16 lanes, 4x2, 2x2, 2x1)
 * when the work-group's shape allows it, else a run of a row: a compact block's pixels are
 * closer together, so more vectors lie wholly outside a light's range and leave at its first
 * test (kernels/shading.h). The slot of this work-item's pixel: */
#if TS_LANES == 16 || TS_LANES == 8
#define TS_LANE_BLOCK_W 4
#elif TS_LANES == 4 || TS_LANES == 2
#define TS_LANE_BLOCK_W 2
#else
#define TS_LANE_BLOCK_W 1
#endif
#define TS_LANE_BLOCK_H (TS_LANES / TS_LANE_BLOCK_W)
static inline int ts_lane_pixel_slot(void) {
  int w = (int)get_local_size(0), h = (int)get_local_size(1);
  int x = (int)get_local_id(0), y = (int)get_local_id(1);
  if (w % TS_LANE_BLOCK_W != 0 || h % TS_LANE_BLOCK_H != 0) return y * w + x;
  int block = (y / TS_LANE_BLOCK_H) * (w / TS_LANE_BLOCK_W) + x / TS_LANE_BLOCK_W;
  return (block * TS_LANE_BLOCK_H + y % TS_LANE_BLOCK_H) * TS_LANE_BLOCK_W + x % TS_LANE_BLOCK_W;
}

/* The shading terms of TS_LANES pixels. */
typedef struct {
  ts_shading_point p;
  TS_LANE kdr, kdg, kdb, ksr, ksg, ksb;
} ts_lane_surface;

typedef struct {
  TS_LANE r, g, b;
} ts_lane_rgb;

static inline void ts_lanes_put3(__local float *soa, int slots, int plane, int i, float3 v) {
  soa[plane * slots + i] = v.x;
  soa[(plane + 1) * slots + i] = v.y;
  soa[(plane + 2) * slots + i] = v.z;
}

/* The depth of an unlit slot: d2 ~ 1e36 stays finite and beyond every range. */
#define TS_LANE_UNLIT_Z -1e18f

/* Stores slot i of `slots`: the surface s, or (s null) an unlit slot — far away with black
 * materials, so every light is out of its range and its sum stays 0. (A directional light
 * reaches every slot: the unlit slot's normal is 0, so its N.l is 0 and it gets nothing.) */
static inline void ts_lanes_put(__local float *soa, int slots, int i, const ts_surface *s) {
  const float3 zero = (float3)(0.0f);
  ts_lanes_put3(soa, slots, TS_LP_P, i, s ? s->P : (float3)(0.0f, 0.0f, TS_LANE_UNLIT_Z));
  ts_lanes_put3(soa, slots, TS_LP_N, i, s ? s->N : zero);
  ts_lanes_put3(soa, slots, TS_LP_KD, i, s ? s->kd : zero);
#if TS_HAS_SPECULAR
  ts_lanes_put3(soa, slots, TS_LP_V, i, s ? s->V : zero);
  ts_lanes_put3(soa, slots, TS_LP_KS, i, s ? s->ks : zero);
  soa[TS_LP_GLOSS * slots + i] = s ? s->gloss : 1.0f;
#if TS_SHADING == 1
  soa[TS_LP_VIEW_TERM * slots + i] = s ? s->view_term : 1.0f;
#endif
#endif
}

/* Step 1, every work-item: decodes pixel (x, y) into *s when `wanted` (and not background),
 * stores its slot (unlit otherwise) and the padding slots past the group; returns whether the
 * pixel is lit. A barrier must follow. */
static inline int ts_lanes_store_pixel(__local float *soa, int x, int y, int wanted,
                                       float4 camera, float4 ambient, TS_GBUFFER_PARAMS,
                                       ts_surface *s) {
  int group_size = (int)(get_local_size(0) * get_local_size(1)), item = ts_lane_item();
  int slots = ts_lane_slots();
  int lit = wanted && ts_load_surface(x, y, camera, ambient, TS_GBUFFER_ARGS, s);
  ts_lanes_put(soa, slots, ts_lane_pixel_slot(), lit ? s : 0);
  for (int i = group_size + item; i < slots; i += group_size) ts_lanes_put(soa, slots, i, 0);
  return lit;
}

/* Step 2 is run by the work-items this returns a first slot for (one per TS_LANES slots); the
 * others get -1 and wait at the next barrier. */
static inline int ts_lanes_first_slot(void) {
  int item = ts_lane_item();
  return item < ts_lane_slots() / TS_LANES ? item * TS_LANES : -1;
}

static inline TS_LANE ts_lanes_plane(__local const float *soa, int slots, int plane, int first) {
  return TS_LANE_VLOAD(TS_LANES)(0, soa + plane * slots + first);
}

/* Loads the TS_LANES slots from `first` (of `slots`). */
static inline ts_lane_surface ts_lanes_get(__local const float *soa, int slots, int first) {
  const TS_LANE zero = (TS_LANE)0.0f, one = (TS_LANE)1.0f;
  ts_lane_surface s;
  s.p.px = ts_lanes_plane(soa, slots, TS_LP_P, first);
  s.p.py = ts_lanes_plane(soa, slots, TS_LP_P + 1, first);
  s.p.pz = ts_lanes_plane(soa, slots, TS_LP_P + 2, first);
  s.p.nx = ts_lanes_plane(soa, slots, TS_LP_N, first);
  s.p.ny = ts_lanes_plane(soa, slots, TS_LP_N + 1, first);
  s.p.nz = ts_lanes_plane(soa, slots, TS_LP_N + 2, first);
  s.kdr = ts_lanes_plane(soa, slots, TS_LP_KD, first);
  s.kdg = ts_lanes_plane(soa, slots, TS_LP_KD + 1, first);
  s.kdb = ts_lanes_plane(soa, slots, TS_LP_KD + 2, first);
#if TS_HAS_SPECULAR
  s.p.vx = ts_lanes_plane(soa, slots, TS_LP_V, first);
  s.p.vy = ts_lanes_plane(soa, slots, TS_LP_V + 1, first);
  s.p.vz = ts_lanes_plane(soa, slots, TS_LP_V + 2, first);
  s.p.gloss = ts_lanes_plane(soa, slots, TS_LP_GLOSS, first);
  s.ksr = ts_lanes_plane(soa, slots, TS_LP_KS, first);
  s.ksg = ts_lanes_plane(soa, slots, TS_LP_KS + 1, first);
  s.ksb = ts_lanes_plane(soa, slots, TS_LP_KS + 2, first);
#else
  s.p.vx = s.p.vy = s.p.vz = zero;
  s.p.gloss = one;
  s.ksr = s.ksg = s.ksb = zero;
#endif
#if TS_HAS_SPECULAR && TS_SHADING == 1
  s.p.view_term = ts_lanes_plane(soa, slots, TS_LP_VIEW_TERM, first);
#else
  s.p.view_term = one;
#endif
  return s;
}

/* A per-lane mask of TS_LANES lanes: intN, a lane set where all its bits are (what a vector
 * comparison gives). */
#define TS_LANE_MASK_(n) int##n
#define TS_LANE_MASK_TYPE(n) TS_LANE_MASK_(n)
#define TS_LANE_MASK TS_LANE_MASK_TYPE(TS_LANES)

/* s with only the lanes set in `keep` left as they are; the others become unlit slots (the
 * values ts_lanes_put stores for one), so no light reaches them and lights that reach no kept
 * lane exit at the range test. For a loop over a light list that only some lanes use. */
static inline ts_lane_surface ts_lanes_keep(const ts_lane_surface *s, TS_LANE_MASK keep) {
  const TS_LANE zero = (TS_LANE)0.0f, one = (TS_LANE)1.0f;
  ts_lane_surface k = *s;
  k.p.px = select(zero, s->p.px, keep);
  k.p.py = select(zero, s->p.py, keep);
  k.p.pz = select((TS_LANE)TS_LANE_UNLIT_Z, s->p.pz, keep);
  k.p.nx = select(zero, s->p.nx, keep);
  k.p.ny = select(zero, s->p.ny, keep);
  k.p.nz = select(zero, s->p.nz, keep);
  k.p.vx = select(zero, s->p.vx, keep);
  k.p.vy = select(zero, s->p.vy, keep);
  k.p.vz = select(zero, s->p.vz, keep);
  k.p.gloss = select(one, s->p.gloss, keep);
  k.p.view_term = select(one, s->p.view_term, keep);
  k.kdr = select(zero, s->kdr, keep);
  k.kdg = select(zero, s->kdg, keep);
  k.kdb = select(zero, s->kdb, keep);
  k.ksr = select(zero, s->ksr, keep);
  k.ksg = select(zero, s->ksg, keep);
  k.ksb = select(zero, s->ksb, keep);
  return k;
}

#ifdef TS_HAS_SHADOWS
/* The shadow factors of the TS_LANES pixels for the light whose first face is `first` (>= 0),
 * towards the light at `light_pos` (punctual; `directional`: `light_pos` is the unit direction
 * to the light), pixel by pixel with the scalar kernels/shadows.h: a texel fetch per pixel does
 * not vectorise, and the per-pixel kernels call the same function. Lanes whose weights are all 0
 * are not sampled (their factor stays 1: it multiplies 0), so unlit slots never reach it. */
static inline TS_LANE ts_lanes_shadow(const ts_lane_surface *s, ts_light_weights_t w,
                                      __global const float4 *faces, __global const float *atlas,
                                      int first, float3 light_pos, int directional) {
  float px[TS_LANES], py[TS_LANES], pz[TS_LANES], nx[TS_LANES], ny[TS_LANES], nz[TS_LANES];
  float reach[TS_LANES], factor[TS_LANES];
  TS_LANE_VSTORE(TS_LANES)(s->p.px, 0, px);
  TS_LANE_VSTORE(TS_LANES)(s->p.py, 0, py);
  TS_LANE_VSTORE(TS_LANES)(s->p.pz, 0, pz);
  TS_LANE_VSTORE(TS_LANES)(s->p.nx, 0, nx);
  TS_LANE_VSTORE(TS_LANES)(s->p.ny, 0, ny);
  TS_LANE_VSTORE(TS_LANES)(s->p.nz, 0, nz);
  TS_LANE_VSTORE(TS_LANES)(fabs(w.wd) + fabs(w.ws) + fabs(w.wf), 0, reach);
  for (int k = 0; k < TS_LANES; ++k) {
    factor[k] = 1.0f;
    if (reach[k] == 0.0f) continue;
    float3 P = (float3)(px[k], py[k], pz[k]);
    float3 L = directional ? light_pos : normalize(light_pos - P);
    factor[k] = ts_shadow_factor(faces, atlas, first, P, (float3)(nx[k], ny[k], nz[k]), L);
  }
  return TS_LANE_VLOAD(TS_LANES)(0, factor);
}
#endif

/* sum += C (wd kd + ws ks + wf), lane by lane, as ts_weighted_color forms it. */
static inline void ts_lanes_add_weighted(ts_lane_rgb *sum, const ts_lane_surface *s,
                                         ts_light_weights_t w, float4 color) {
  sum->r += color.x * (w.wd * s->kdr + w.ws * s->ksr + w.wf);
  sum->g += color.y * (w.wd * s->kdg + w.ws * s->ksg + w.wf);
  sum->b += color.z * (w.wd * s->kdb + w.ws * s->ksb + w.wf);
}

#ifdef TS_HAS_SHADOWS
/* The same times the shadow factor f, in the per-pixel kernels' order (the contribution, then
 * the factor: kernels/gbuffer.h ts_shade_punctual), so each lane stays what they compute. */
static inline void ts_lanes_add_shadowed(ts_lane_rgb *sum, const ts_lane_surface *s,
                                         ts_light_weights_t w, float4 color, TS_LANE f) {
  sum->r += color.x * (w.wd * s->kdr + w.ws * s->ksr + w.wf) * f;
  sum->g += color.y * (w.wd * s->kdg + w.ws * s->ksg + w.wf) * f;
  sum->b += color.z * (w.wd * s->kdb + w.ws * s->ksb + w.wf) * f;
}
#endif

/* sum += point or spot light `light`'s contribution. */
static inline void ts_lanes_add_light(ts_lane_rgb *sum, const ts_lane_surface *s,
                                      TS_LIGHT_PARAMS, uint light) {
  float4 pr = light_pos_range[light], color = light_color[light];
  float4 spot = ts_light_spot(light_spot, light);
  /* Per-light constants once for all TS_LANES pixels. */
  float inv_r2 = 1.0f / (pr.w * pr.w);
  ts_light_weights_t w = ts_punctual_weights(
      &s->p, (TS_LANE)pr.x, (TS_LANE)pr.y, (TS_LANE)pr.z, (TS_LANE)pr.w, (TS_LANE)inv_r2,
      (TS_LANE)spot.x, (TS_LANE)spot.y, (TS_LANE)spot.z, (TS_LANE)spot.w, (TS_LANE)color.w,
      TS_MODEL, TS_SHADING, TS_HAS_SPECULAR, TS_HAS_SPOT);
#ifdef TS_HAS_SHADOWS
  int first = light_shadow[light];
  if (first >= 0) {
    TS_LANE f = ts_lanes_shadow(s, w, shadow_faces, shadow_atlas, first, pr.xyz, 0);
    ts_lanes_add_shadowed(sum, s, w, color, f);
    return;
  }
#endif
  ts_lanes_add_weighted(sum, s, w, color);
}

/* sum += every directional light's contribution (none in a build without them). */
static inline void ts_lanes_add_directionals(ts_lane_rgb *sum, const ts_lane_surface *s,
                                             TS_DIRECTIONAL_PARAMS) {
#if TS_HAS_DIRECTIONAL
  for (int k = 0; k < dir_light_count; ++k) {
    float4 d = dir_light_dir[k];
    ts_light_weights_t w = ts_directional_weights(&s->p, (TS_LANE)d.x, (TS_LANE)d.y,
                                                  (TS_LANE)d.z, TS_SHADING, TS_HAS_SPECULAR);
#ifdef TS_HAS_SHADOWS
    int first = dir_light_shadow[k];
    if (first >= 0) {
      TS_LANE f = ts_lanes_shadow(s, w, dir_shadow_faces, dir_shadow_atlas, first, d.xyz, 1);
      ts_lanes_add_shadowed(sum, s, w, dir_light_color[k], f);
      continue;
    }
#endif
    ts_lanes_add_weighted(sum, s, w, dir_light_color[k]);
  }
#endif
}

/* How many directional lights the lanes loop adds (0 in a build without them). */
static inline int ts_directional_count(int dir_light_count) {
#if TS_HAS_DIRECTIONAL
  return dir_light_count;
#else
  return 0;
#endif
}

/* Stores (loads) the r, g, b sums of the TS_LANES slots from `first` in planes `plane` to
 * plane + 2. The one-pass kernels store them over planes 0..2 (the positions, no longer needed);
 * a barrier must follow before other work-items read them. */
static inline void ts_lanes_put_rgb(__local float *soa, int slots, int plane, int first,
                                    const ts_lane_rgb *sum) {
  TS_LANE_VSTORE(TS_LANES)(sum->r, 0, soa + plane * slots + first);
  TS_LANE_VSTORE(TS_LANES)(sum->g, 0, soa + (plane + 1) * slots + first);
  TS_LANE_VSTORE(TS_LANES)(sum->b, 0, soa + (plane + 2) * slots + first);
}
static inline ts_lane_rgb ts_lanes_get_rgb(__local const float *soa, int slots, int plane,
                                           int first) {
  ts_lane_rgb sum;
  sum.r = ts_lanes_plane(soa, slots, plane, first);
  sum.g = ts_lanes_plane(soa, slots, plane + 1, first);
  sum.b = ts_lanes_plane(soa, slots, plane + 2, first);
  return sum;
}

/* Step 3, every work-item: the summed contributions of its pixel (planes 0..2). */
static inline float3 ts_lanes_pixel_sum(__local const float *soa) {
  int slots = ts_lane_slots(), i = ts_lane_pixel_slot();
  return (float3)(soa[i], soa[slots + i], soa[2 * slots + i]);
}

/* Step 3's colour of a pixel: its summed contributions (when its group ran step 2: `summed`) plus
 * its base term; black where the pixel is not lit (background). */
static inline float3 ts_lanes_pixel_colour(__local const float *soa, int lit, int summed,
                                           const ts_surface *s) {
  if (!lit) return (float3)(0.0f);
  return (summed ? ts_lanes_pixel_sum(soa) : (float3)(0.0f)) + s->base;
}

#endif
