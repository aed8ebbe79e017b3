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
 * screen, padding) hold a surface that no light reaches.
 *
 * The includer includes gbuffer.h first (with TS_LANES > 1).
 */
#ifndef TS_LANES_H
#define TS_LANES_H

/* P, N, V, kd, ks (3 each) and shininess. */
#define TS_LANE_PLANES 16

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

/* The shading terms of TS_LANES pixels. */
typedef struct {
  ts_shading_point p;
  TS_LANE kdr, kdg, kdb, ksr, ksg, ksb;
} ts_lane_surface;

typedef struct {
  TS_LANE r, g, b;
} ts_lane_rgb;

/* Stores slot i of `slots`: the surface s, or (s null) an unlit slot — far away with black
 * materials, so every light is out of its range and its sum stays 0. */
static inline void ts_lanes_put(__local float *soa, int slots, int i, const ts_surface *s) {
  float v[TS_LANE_PLANES];
  if (s) {
    v[0] = s->P.x, v[1] = s->P.y, v[2] = s->P.z;
    v[3] = s->N.x, v[4] = s->N.y, v[5] = s->N.z;
    v[6] = s->V.x, v[7] = s->V.y, v[8] = s->V.z;
    v[9] = s->shininess;
    v[10] = s->kd.x, v[11] = s->kd.y, v[12] = s->kd.z;
    v[13] = s->ks.x, v[14] = s->ks.y, v[15] = s->ks.z;
  } else {
    for (int f = 0; f < TS_LANE_PLANES; ++f) v[f] = 0.0f;
    v[2] = -1e18f; /* d2 ~ 1e36 stays finite and beyond every range */
    v[9] = 1.0f;
  }
  for (int f = 0; f < TS_LANE_PLANES; ++f) soa[f * slots + i] = v[f];
}

/* Step 1, every work-item: decodes pixel (x, y) into *s when `wanted` (and not background),
 * stores its slot (unlit otherwise) and the padding slots past the group; returns whether the
 * pixel is lit. A barrier must follow. */
static inline int ts_lanes_store_pixel(__local float *soa, int x, int y, int wanted,
                                       float4 camera, TS_GBUFFER_PARAMS, ts_surface *s) {
  int group_size = (int)(get_local_size(0) * get_local_size(1)), item = ts_lane_item();
  int slots = ts_lane_slots();
  int lit = wanted && ts_load_surface(x, y, camera, TS_GBUFFER_ARGS, s);
  ts_lanes_put(soa, slots, item, lit ? s : 0);
  for (int i = group_size + item; i < slots; i += group_size) ts_lanes_put(soa, slots, i, 0);
  return lit;
}

/* Step 2 is run by the work-items this returns a first slot for (one per TS_LANES slots); the
 * others get -1 and wait at the next barrier. */
static inline int ts_lanes_first_slot(void) {
  int item = ts_lane_item();
  return item < ts_lane_slots() / TS_LANES ? item * TS_LANES : -1;
}

/* Loads the TS_LANES slots from `first` (of `slots`). */
static inline ts_lane_surface ts_lanes_get(__local const float *soa, int slots, int first) {
  TS_LANE v[TS_LANE_PLANES];
  for (int f = 0; f < TS_LANE_PLANES; ++f) v[f] = TS_LANE_VLOAD(TS_LANES)(0, soa + f * slots + first);
  ts_lane_surface s;
  s.p.px = v[0], s.p.py = v[1], s.p.pz = v[2];
  s.p.nx = v[3], s.p.ny = v[4], s.p.nz = v[5];
  s.p.vx = v[6], s.p.vy = v[7], s.p.vz = v[8];
  s.p.shininess = v[9];
  s.kdr = v[10], s.kdg = v[11], s.kdb = v[12];
  s.ksr = v[13], s.ksg = v[14], s.ksb = v[15];
  return s;
}

/* sum += the light's contribution, lane by lane: C*diffuse*kd + C*specular*ks as ts_point_light
 * forms it. */
static inline void ts_lanes_add_light(ts_lane_rgb *sum, const ts_lane_surface *s, float4 pos_range,
                                      float4 color, int model) {
  TS_LANE specular;
  TS_LANE diffuse = ts_light_weights(&s->p, (TS_LANE)pos_range.x, (TS_LANE)pos_range.y,
                                     (TS_LANE)pos_range.z, (TS_LANE)pos_range.w, model, &specular);
  sum->r += color.x * diffuse * s->kdr + color.x * specular * s->ksr;
  sum->g += color.y * diffuse * s->kdg + color.y * specular * s->ksg;
  sum->b += color.z * diffuse * s->kdb + color.z * specular * s->ksb;
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
  sum.r = TS_LANE_VLOAD(TS_LANES)(0, soa + plane * slots + first);
  sum.g = TS_LANE_VLOAD(TS_LANES)(0, soa + (plane + 1) * slots + first);
  sum.b = TS_LANE_VLOAD(TS_LANES)(0, soa + (plane + 2) * slots + first);
  return sum;
}

/* Step 3, every work-item: the summed contributions of its pixel (planes 0..2). */
static inline float3 ts_lanes_pixel_sum(__local const float *soa) {
  int slots = ts_lane_slots(), i = ts_lane_item();
  return (float3)(soa[i], soa[slots + i], soa[2 * slots + i]);
}

#endif
