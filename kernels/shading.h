/*
 * The one shading function of tileshade, shared by every technique's kernels and by the CPU
 * reference. It is written in the common subset of OpenCL C and C++ so the two cannot drift.
 *
 * The includer defines the scalar and vector types first:
 *   TS_REAL          scalar type            (float in kernels; double in the reference)
 *   TS_REAL3         3-vector of TS_REAL    (float3; glm::dvec3)
 *   TS_MAKE3(x,y,z)  builds a TS_REAL3
 * and makes dot, sqrt, pow, max, clamp visible for those types (OpenCL has them built in;
 * src/reference/shading_cpu.h provides them for C++).
 *
 * Shading model (view space, camera at the origin looking down -Z):
 *   v = Lp - P;  d2 = dot(v,v);  no contribution if d2 >= r*r (windowed model)
 *   d = sqrt(d2);  l = v/d
 *   window  = clamp(1 - (d/r)^4, 0, 1)^2
 *   falloff = window / max(d2, dmin*dmin)
 *   ndl  = max(dot(N,l), 0)
 *   h    = normalize(l + V)    V = normalize(-P); zero-length h gives spec = 0
 *   spec = ndl > 0 ? pow(max(dot(N,h),0), s) : 0
 *   out  = C * falloff * (kd*ndl + ks*spec)
 *   pixel = ke + a*kd + sum(out);  background = 0
 * The "physical" model drops the window and the range cut: falloff = 1 / max(d2, dmin*dmin).
 *
 * Cost (for the device-limit estimate in the benchmark): a contributing evaluation is about
 * TS_SHADE_FLOPS floating-point operations (sqrt, divide and pow counted as one each).
 */
#ifndef TS_REAL
#error "define TS_REAL, TS_REAL3 and TS_MAKE3 before including shading.h"
#endif

/* dmin: the distance (scene units) below which the inverse-square falloff stops growing, so a
 * light touching a surface gives a finite value. One documented constant for every technique. */
#ifndef TS_DMIN
#define TS_DMIN 0.1
#endif

/* The square root and power used by the shading function; kernels/gbuffer.h swaps in the
 * native_ variants for the "native" arithmetic knob. */
#ifndef TS_SQRT
#define TS_SQRT sqrt
#endif
#ifndef TS_POW
#define TS_POW pow
#endif

#ifndef TS_SHADE_FLOPS
#define TS_SHADE_FLOPS 60
#endif

/* Shading models. */
#define TS_MODEL_WINDOWED 0
#define TS_MODEL_PHYSICAL 1

/* View-space position of pixel (x,y) at linear depth `depth` (= -z_view > 0). Pixel centres sit at
 * +0.5; image row 0 is the top of the screen. tan_x/tan_y: tangents of the half field of view. */
static inline TS_REAL3 ts_view_position(int x, int y, TS_REAL depth, TS_REAL tan_x, TS_REAL tan_y,
                                        int width, int height) {
  TS_REAL ndc_x = ((TS_REAL)2 * ((TS_REAL)x + (TS_REAL)0.5)) / (TS_REAL)width - (TS_REAL)1;
  TS_REAL ndc_y = (TS_REAL)1 - ((TS_REAL)2 * ((TS_REAL)y + (TS_REAL)0.5)) / (TS_REAL)height;
  return TS_MAKE3(ndc_x * tan_x * depth, ndc_y * tan_y * depth, -depth);
}

/* Contribution of one point light at Lp (colour C, range r) to the surface point P with unit normal
 * N, unit view vector V = normalize(-P), diffuse kd, specular ks and shininess s. */
static inline TS_REAL3 ts_point_light(TS_REAL3 P, TS_REAL3 N, TS_REAL3 V, TS_REAL3 kd, TS_REAL3 ks,
                                      TS_REAL s, TS_REAL3 Lp, TS_REAL3 C, TS_REAL r, int model) {
  TS_REAL3 zero = TS_MAKE3((TS_REAL)0, (TS_REAL)0, (TS_REAL)0);
  TS_REAL3 v = Lp - P;
  TS_REAL d2 = dot(v, v);
  TS_REAL window = (TS_REAL)1;
  if (model == TS_MODEL_WINDOWED) {
    TS_REAL r2 = r * r;
    if (d2 >= r2) return zero;
    TS_REAL q = d2 / r2; /* (d/r)^2, so (d/r)^4 = q*q without a sqrt */
    TS_REAL w = clamp((TS_REAL)1 - q * q, (TS_REAL)0, (TS_REAL)1);
    window = w * w;
  }
  /* A light exactly on the point has no direction: it lights nothing (instead of NaN). */
  if (d2 <= (TS_REAL)0) return zero;
  TS_REAL d = TS_SQRT(d2);
  TS_REAL3 l = v / d;
  TS_REAL dmin = (TS_REAL)TS_DMIN;
  TS_REAL falloff = window / max(d2, dmin * dmin);
  TS_REAL ndl = max(dot(N, l), (TS_REAL)0);
  TS_REAL spec = (TS_REAL)0;
  if (ndl > (TS_REAL)0) {
    TS_REAL3 hv = l + V;
    TS_REAL hlen2 = dot(hv, hv);
    if (hlen2 > (TS_REAL)0) {
      TS_REAL ndh = max(dot(N, hv / TS_SQRT(hlen2)), (TS_REAL)0);
      spec = TS_POW(ndh, s);
    }
  }
  return C * (falloff * ndl) * kd + C * (falloff * spec) * ks;
}

/* The light-independent part of a pixel: emission plus the global ambient term a*kd. */
static inline TS_REAL3 ts_surface_base(TS_REAL3 ke, TS_REAL3 kd, TS_REAL3 ambient) {
  return ke + ambient * kd;
}
