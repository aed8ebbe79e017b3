/*
 * The one shading function of tileshade, shared by every technique's kernels and by the CPU
 * reference. It is written in the common subset of OpenCL C and C++ so the two cannot drift.
 *
 * The includer defines the scalar and vector types first:
 *   TS_REAL          scalar type            (float in kernels; double in the reference)
 *   TS_REAL3         3-vector of TS_REAL    (float3; glm::dvec3)
 *   TS_MAKE3(x,y,z)  builds a TS_REAL3
 * and makes dot, sqrt, pow, max, clamp visible for those types (OpenCL has them built in;
 * src/reference/shading_cpu.h provides them for C++). Floating-point constants are written
 * TS_LIT(0.5) (below): float in OpenCL C, TS_REAL in C++.
 *
 * Shading model (view space, camera at the origin looking down -Z):
 *   v = Lp - P;  d2 = dot(v,v);  no contribution if d2 >= r*r (windowed model)
 *   d = sqrt(d2);  l = v/d
 *   window  = clamp(1 - (d/r)^4, 0, 1)^2
 *   falloff = window / max(d2, dmin*dmin)
 *   ndl  = max(dot(N,l), 0)
 *   h    = normalize(l + V)    V = normalize(-P); zero-length h gives spec = 0
 *   spec = pow(max(dot(N,h),0), s)
 *   out  = C * falloff * ndl * (kd + ks*spec)     continuous at ndl = 0 (docs/shading.md)
 *   pixel = ke + a*kd + sum(out);  background = 0
 * The "physical" model drops the window and the range cut: falloff = 1 / max(d2, dmin*dmin).
 *
 * Cost (for the device-limit estimate in the benchmark): a contributing evaluation is about
 * TS_SHADE_FLOPS floating-point operations (sqrt, divide and pow counted as one each).
 */
#ifndef TS_REAL
#error "define TS_REAL, TS_REAL3 and TS_MAKE3 before including shading.h"
#endif

/* TS_LIT(x): the floating-point constant x (written with a decimal point or an exponent) as the
 * shading type: x##f in OpenCL C, so no double constant reaches a device without fp64 (clang
 * warns and some compilers refuse), and (TS_REAL)(x) in C++, so the double reference keeps the
 * exact double value. An includer may define its own. */
#ifndef TS_LIT
#if defined(__OPENCL_C_VERSION__) || defined(__OPENCL_VERSION__)
#define TS_LIT(x) TS_LIT_F_(x)
#define TS_LIT_F_(x) x##f
#else
#define TS_LIT(x) ((TS_REAL)(x))
#endif
#endif

/* dmin: the distance (scene units) below which the inverse-square falloff stops growing, so a
 * light touching a surface gives a finite value. One documented constant for every technique
 * (a plain number for the host; shading code reads it as TS_LIT(TS_DMIN)). */
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
  TS_REAL ndc_x = ((TS_REAL)2 * ((TS_REAL)x + TS_LIT(0.5))) / (TS_REAL)width - (TS_REAL)1;
  TS_REAL ndc_y = (TS_REAL)1 - ((TS_REAL)2 * ((TS_REAL)y + TS_LIT(0.5))) / (TS_REAL)height;
  return TS_MAKE3(ndc_x * tan_x * depth, ndc_y * tan_y * depth, -depth);
}

/* ---- Lanes ------------------------------------------------------------------------------
 * The light term below is written once for a "lane" type TS_LANE: by default the scalar TS_REAL
 * (one pixel: float in kernels, double in the reference), or an OpenCL vector of TS_LANES floats
 * that shades that many pixels against the same light at once (kernels/lanes.h; CPU devices,
 * where a compiler does not vectorise a per-pixel light loop by itself). The code therefore
 * branches only on "any lane": TS_ANY is the condition itself for a scalar and any() for a vector,
 * and per-lane choices are TS_SELECT (OpenCL's ?: works per component on vectors). For a scalar
 * the early exits are ordinary branches, as before: no cost for the GPU or the reference. */
#ifndef TS_LANE
#define TS_LANE TS_REAL
#define TS_ANY(c) (c)
#endif
#define TS_SELECT(c, a, b) ((c) ? (a) : (b))

/* The surface terms the light weights need, one TS_LANE per component. */
typedef struct {
  TS_LANE px, py, pz; /* view-space position P */
  TS_LANE nx, ny, nz; /* unit normal N */
  TS_LANE vx, vy, vz; /* unit view vector V = normalize(-P) */
  TS_LANE shininess;
} ts_shading_point;

/* The two weights of one point light at (lx, ly, lz) with range r on surface point p: returns the
 * diffuse weight falloff*ndl and stores the specular weight falloff*ndl*spec, so the contribution
 * is C*diffuse*kd + C*specular*ks. Lanes outside the range, or with the light exactly on the point
 * (no direction: it lights nothing, instead of NaN), get 0 for both. The specular weight carries
 * ndl like the diffuse one, so both fall to 0 as the light reaches the surface's plane: no jump at
 * ndl = 0, where float and double may disagree on the sign (issue #12). */
static inline TS_LANE ts_light_weights(const ts_shading_point *p, TS_LANE lx, TS_LANE ly,
                                       TS_LANE lz, TS_LANE r, int model, TS_LANE *specular) {
  const TS_LANE zero = (TS_LANE)0, one = (TS_LANE)1;
  TS_LANE vx = lx - p->px, vy = ly - p->py, vz = lz - p->pz;
  TS_LANE d2 = vx * vx + vy * vy + vz * vz;
  TS_LANE window = one;
  if (model == TS_MODEL_WINDOWED) {
    TS_LANE r2 = r * r;
    if (!TS_ANY(d2 < r2)) { /* the common exit: no lane in range */
      *specular = zero;
      return zero;
    }
    TS_LANE q = d2 / r2; /* (d/r)^2, so (d/r)^4 = q*q without a sqrt */
    TS_LANE w = clamp(one - q * q, zero, one);
    window = TS_SELECT(d2 < r2, w * w, zero);
  }
  *specular = zero;
  if (!TS_ANY(d2 > zero)) return zero;
  TS_LANE d = TS_SQRT(d2);
  TS_LANE ux = vx / d, uy = vy / d, uz = vz / d; /* l = v/d */
  TS_LANE dmin = (TS_LANE)TS_LIT(TS_DMIN);
  TS_LANE falloff = window / max(d2, dmin * dmin);
  /* A lane with d2 = 0 has l = NaN (OpenCL leaves max(NaN, 0) undefined): ndl > 0 is false for
   * it and the last line returns 0 for it. */
  TS_LANE ndl = max(p->nx * ux + p->ny * uy + p->nz * uz, zero);
  if (TS_ANY(ndl > zero)) {
    TS_LANE hx = ux + p->vx, hy = uy + p->vy, hz = uz + p->vz; /* h = l + V, normalised below */
    TS_LANE hlen2 = hx * hx + hy * hy + hz * hz;
    if (TS_ANY(hlen2 > zero)) {
      TS_LANE hlen = TS_SQRT(hlen2);
      TS_LANE ndh = max((p->nx * hx + p->ny * hy + p->nz * hz) / hlen, zero);
      TS_LANE spec = TS_POW(ndh, p->shininess);
      *specular = TS_SELECT(ndl > zero && hlen2 > zero, falloff * ndl * spec, zero);
    }
  }
  return TS_SELECT(d2 > zero, falloff * ndl, zero);
}

#if !defined(TS_LANES) || TS_LANES == 1
/* Contribution of one point light at Lp (colour C, range r) to the surface point P with unit normal
 * N, unit view vector V = normalize(-P), diffuse kd, specular ks and shininess s: the vector form
 * of ts_light_weights that every per-pixel kernel and the reference call. */
static inline TS_REAL3 ts_point_light(TS_REAL3 P, TS_REAL3 N, TS_REAL3 V, TS_REAL3 kd, TS_REAL3 ks,
                                      TS_REAL s, TS_REAL3 Lp, TS_REAL3 C, TS_REAL r, int model) {
  ts_shading_point p = {P.x, P.y, P.z, N.x, N.y, N.z, V.x, V.y, V.z, s};
  TS_REAL specular;
  TS_REAL diffuse = ts_light_weights(&p, Lp.x, Lp.y, Lp.z, r, model, &specular);
  return C * diffuse * kd + C * specular * ks;
}
#endif

/* The light-independent part of a pixel: emission plus the global ambient term a*kd. */
static inline TS_REAL3 ts_surface_base(TS_REAL3 ke, TS_REAL3 kd, TS_REAL3 ambient) {
  return ke + ambient * kd;
}
