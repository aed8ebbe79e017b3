/*
 * Light-culling geometry shared by the binning kernels and by host tests, in the common subset of
 * OpenCL C and C++ (same conventions as shading.h; the includer also defines TS_REAL4/TS_MAKE4
 * and min).
 *
 * Conventions: view space, camera at the origin looking down -Z; "depth" w = -z > 0.
 * A sphere's screen bounds are returned as NDC slopes' images: (xmin, ymin, xmax, ymax) in NDC,
 * y up. An empty result has xmin > xmax.
 */
#ifndef TS_REAL4
#error "define TS_REAL4 and TS_MAKE4 before including culling.h"
#endif
#ifndef TS_LIT
#define TS_LIT(x) ((TS_REAL)(x))
#endif

/* Bounds, along one axis, of the projection of a circle (centre (a, w), radius r, in the plane of
 * that axis and the view direction) clipped to w >= znear. Outputs tangent-slope bounds a/w.
 * Returns 0 when nothing of the circle lies in front of the near plane. The silhouette rays from
 * the eye bound the whole circle; where a tangent point lies behind the near plane, the clipped
 * shape's extreme is an end of the chord on the near plane instead. */
static inline int ts_circle_slope_bounds(TS_REAL a, TS_REAL w, TS_REAL r, TS_REAL znear,
                                         TS_REAL *lo, TS_REAL *hi) {
  if (w + r < znear) return 0; /* wholly behind the near plane */
  TS_REAL big = TS_LIT(1e30);
  TS_REAL d2 = a * a + w * w;
  TS_REAL r2 = r * r;
  if (d2 <= r2) { /* the eye is inside the circle: every direction is covered */
    *lo = -big;
    *hi = big;
    return 1;
  }
  /* Tangent points from the origin: T = (d2 - r2)/d2 * C +- r*sqrt(d2 - r2)/d2 * perp(C). */
  TS_REAL t = sqrt(d2 - r2);
  TS_REAL ka = (d2 - r2) / d2, kb = r * t / d2;
  TS_REAL ta0 = ka * a + kb * w, tw0 = ka * w - kb * a; /* perp(C) = (w, -a) */
  TS_REAL ta1 = ka * a - kb * w, tw1 = ka * w + kb * a;
  /* Chord on the near plane (only meaningful when the circle crosses it). */
  TS_REAL h2 = r2 - (w - znear) * (w - znear);
  TS_REAL h = h2 > TS_LIT(0.0) ? sqrt(h2) : TS_LIT(0.0);
  TS_REAL chord_lo = (a - h) / znear, chord_hi = (a + h) / znear;
  TS_REAL s0 = tw0 >= znear ? ta0 / tw0 : (ta0 > TS_LIT(0.0) ? chord_hi : chord_lo);
  TS_REAL s1 = tw1 >= znear ? ta1 / tw1 : (ta1 > TS_LIT(0.0) ? chord_hi : chord_lo);
  /* A tangent point behind the near plane may sit on either side; the chord bounds both. */
  if (tw0 < znear || tw1 < znear) {
    *lo = min(min(s0, s1), chord_lo);
    *hi = max(max(s0, s1), chord_hi);
  } else {
    *lo = min(s0, s1);
    *hi = max(s0, s1);
  }
  return 1;
}

/* Conservative NDC bounds of a view-space sphere clipped to the near plane. */
static inline TS_REAL4 ts_sphere_ndc_bounds(TS_REAL3 c, TS_REAL r, TS_REAL znear, TS_REAL tan_x,
                                            TS_REAL tan_y) {
  TS_REAL4 empty = TS_MAKE4(TS_LIT(1.0), TS_LIT(1.0), TS_LIT(-1.0), TS_LIT(-1.0));
  TS_REAL xlo, xhi, ylo, yhi;
  TS_REAL w = -c.z;
  if (!ts_circle_slope_bounds(c.x, w, r, znear, &xlo, &xhi)) return empty;
  if (!ts_circle_slope_bounds(c.y, w, r, znear, &ylo, &yhi)) return empty;
  return TS_MAKE4(xlo / tan_x, ylo / tan_y, xhi / tan_x, yhi / tan_y);
}

/* Tile rectangle (x0, y0, x1, y1 inclusive; rows from the top) covered by NDC bounds on a
 * tiles_x x tiles_y grid of tile_w x tile_h pixels over a width x height image. Returns 0 if the
 * bounds miss the screen. */
static inline int ts_ndc_bounds_to_tiles(TS_REAL4 b, int width, int height, int tile_w,
                                         int tile_h, int *x0, int *y0, int *x1, int *y1) {
  if (b.x > b.z || b.y > b.w) return 0;
  if (b.z < TS_LIT(-1.0) || b.x > TS_LIT(1.0) || b.w < TS_LIT(-1.0) || b.y > TS_LIT(1.0)) return 0;
  TS_REAL px0 = (max(b.x, TS_LIT(-1.0)) + TS_LIT(1.0)) * TS_LIT(0.5) * (TS_REAL)width;
  TS_REAL px1 = (min(b.z, TS_LIT(1.0)) + TS_LIT(1.0)) * TS_LIT(0.5) * (TS_REAL)width;
  TS_REAL py0 = (TS_LIT(1.0) - min(b.w, TS_LIT(1.0))) * TS_LIT(0.5) * (TS_REAL)height;
  TS_REAL py1 = (TS_LIT(1.0) - max(b.y, TS_LIT(-1.0))) * TS_LIT(0.5) * (TS_REAL)height;
  int tiles_x = (width + tile_w - 1) / tile_w, tiles_y = (height + tile_h - 1) / tile_h;
  /* Pixel centres at +0.5: a pixel is touched when its centre lies within [p0, p1]. */
  *x0 = (int)floor(px0 / (TS_REAL)tile_w);
  *x1 = (int)floor(px1 / (TS_REAL)tile_w);
  *y0 = (int)floor(py0 / (TS_REAL)tile_h);
  *y1 = (int)floor(py1 / (TS_REAL)tile_h);
  *x0 = *x0 < 0 ? 0 : *x0;
  *y0 = *y0 < 0 ? 0 : *y0;
  *x1 = *x1 > tiles_x - 1 ? tiles_x - 1 : *x1;
  *y1 = *y1 > tiles_y - 1 ? tiles_y - 1 : *y1;
  return *x0 <= *x1 && *y0 <= *y1;
}

/* Depth-range test: does the sphere's depth extent [w - r, w + r] meet the tile's geometry depth
 * range [zmin, zmax]? An empty tile (zmin > zmax) meets nothing. */
static inline int ts_sphere_meets_depth_range(TS_REAL3 c, TS_REAL r, TS_REAL zmin, TS_REAL zmax) {
  TS_REAL w = -c.z;
  return zmin <= zmax && w + r >= zmin && w - r <= zmax;
}

/* ---- Per-tile tests (the culling knob; every one is conservative) ----------------------------
 * TS_CULL_RECT     the light's projected-sphere tile rectangle + the tile's depth range (default;
 *                  the rectangle is exact for the clipped sphere, so no extra per-tile test)
 * TS_CULL_FRUSTUM  additionally: sphere against the tile frustum's four side planes
 * TS_CULL_AABB     additionally: sphere against the view-space box bounding the tile frustum
 *                  between the tile's zmin and zmax
 * Side planes alone accept spheres near a frustum corner that miss the frustum; the box does
 * better for thin depth ranges and worse for deep ones: the benchmark measures both. */
#define TS_CULL_RECT 0
#define TS_CULL_FRUSTUM 1
#define TS_CULL_AABB 2

/* Slope bounds (x/w, y/w with w = -z) of the pixel rectangle [px0,px1) x [py0,py1) (rows down). */
static inline TS_REAL4 ts_tile_slopes(int px0, int py0, int px1, int py1, int width, int height,
                                      TS_REAL tan_x, TS_REAL tan_y) {
  TS_REAL sx0 = (TS_LIT(2.0) * (TS_REAL)px0 / (TS_REAL)width - TS_LIT(1.0)) * tan_x;
  TS_REAL sx1 = (TS_LIT(2.0) * (TS_REAL)px1 / (TS_REAL)width - TS_LIT(1.0)) * tan_x;
  TS_REAL sy1 = (TS_LIT(1.0) - TS_LIT(2.0) * (TS_REAL)py0 / (TS_REAL)height) * tan_y;
  TS_REAL sy0 = (TS_LIT(1.0) - TS_LIT(2.0) * (TS_REAL)py1 / (TS_REAL)height) * tan_y;
  return TS_MAKE4(sx0, sy0, sx1, sy1);
}

/* Sphere against the side planes through the eye: a point is inside when s0 <= x/w <= s1 (and
 * the same for y). Signed distance to the plane x - s*w = 0 is (x - s*w)/sqrt(1 + s*s). */
static inline int ts_sphere_meets_tile_planes(TS_REAL3 c, TS_REAL r, TS_REAL4 s) {
  TS_REAL w = -c.z;
  if ((c.x - s.x * w) < -r * sqrt(TS_LIT(1.0) + s.x * s.x)) return 0;
  if ((s.z * w - c.x) < -r * sqrt(TS_LIT(1.0) + s.z * s.z)) return 0;
  if ((c.y - s.y * w) < -r * sqrt(TS_LIT(1.0) + s.y * s.y)) return 0;
  if ((s.w * w - c.y) < -r * sqrt(TS_LIT(1.0) + s.w * s.w)) return 0;
  return 1;
}

/* Sphere against the axis-aligned box around the tile frustum between depths zmin and zmax. */
static inline int ts_sphere_meets_tile_box(TS_REAL3 c, TS_REAL r, TS_REAL4 s, TS_REAL zmin,
                                           TS_REAL zmax) {
  TS_REAL bx0 = min(s.x * zmin, s.x * zmax), bx1 = max(s.z * zmin, s.z * zmax);
  TS_REAL by0 = min(s.y * zmin, s.y * zmax), by1 = max(s.w * zmin, s.w * zmax);
  TS_REAL w = -c.z;
  TS_REAL dx = max(max(bx0 - c.x, c.x - bx1), TS_LIT(0.0));
  TS_REAL dy = max(max(by0 - c.y, c.y - by1), TS_LIT(0.0));
  TS_REAL dw = max(max(zmin - w, w - zmax), TS_LIT(0.0));
  return dx * dx + dy * dy + dw * dw <= r * r;
}

/* The extra per-tile test selected by `mode` (after the rectangle and the depth range). */
static inline int ts_sphere_meets_tile(TS_REAL3 c, TS_REAL r, int mode, int px0, int py0, int px1,
                                       int py1, int width, int height, TS_REAL tan_x,
                                       TS_REAL tan_y, TS_REAL zmin, TS_REAL zmax) {
  if (mode == TS_CULL_RECT) return 1;
  TS_REAL4 s = ts_tile_slopes(px0, py0, px1, py1, width, height, tan_x, tan_y);
  if (mode == TS_CULL_FRUSTUM) return ts_sphere_meets_tile_planes(c, r, s);
  return ts_sphere_meets_tile_box(c, r, s, zmin, zmax);
}

/* ---- Light volumes: spheres and cones --------------------------------------------------------
 * What a light can reach: a point light's range sphere, or a spot light's spherical sector (the
 * range ball cut by the cone of half-angle theta around its axis; kernels/shading.h gives it
 * nothing outside). A spot light is culled as that sector, not as its range sphere:
 *   - screen rectangle: the sector's tight bounding sphere's rectangle, intersected with the
 *     rectangle of the sector's exact view-space box (both conservative, so is the intersection);
 *   - depth range: the box's depth extent;
 *   - per tile: the cone against the tile's bounding sphere (always), then the culling knob's
 *     test on the bounding sphere, and with TS_CULL_AABB the two boxes.
 * Every bound is widened by TS_VOLUME_SLACK of the range, so float rounding in the culling can
 * only keep a light, never drop one (docs/techniques.md, "Spot lights"). A point light (axis 0,
 * cos_outer -1) gets exactly its sphere's tests. Light layout: kernels/shading.h. */
#define TS_VOLUME_SLACK 1e-5
/* How spot lights are culled (the spot culling knob; every mode is conservative):
 *   TS_SPOT_CULL_CONE          the sector, as above (default)
 *   TS_SPOT_CULL_BOUND_SPHERE  the sector's tight bounding sphere alone
 *   TS_SPOT_CULL_RANGE_SPHERE  the range sphere, as if it were a point light */
#define TS_SPOT_CULL_CONE 0
#define TS_SPOT_CULL_BOUND_SPHERE 1
#define TS_SPOT_CULL_RANGE_SPHERE 2

typedef struct {
  TS_REAL3 center; /* bounding sphere */
  TS_REAL radius;
  TS_REAL3 lo, hi; /* view-space box */
  int cone;        /* a spot light narrower than a half-space: the cone test applies */
  TS_REAL3 apex, axis;
  TS_REAL range, cos_outer, sin_outer;
} ts_light_volume;

/* Where a unit direction within angle theta (cosine c, sine s) of the unit vector with component
 * a along some axis can point along that axis: [lo, hi] of its component. */
static inline void ts_cone_extent(TS_REAL a, TS_REAL c, TS_REAL s, TS_REAL *lo, TS_REAL *hi) {
  TS_REAL across = sqrt(max(TS_LIT(1.0) - a * a, TS_LIT(0.0)));
  *hi = a >= c ? TS_LIT(1.0) : a * c + across * s;
  *lo = a <= -c ? TS_LIT(-1.0) : a * c - across * s;
}

static inline ts_light_volume ts_make_light_volume(TS_REAL4 pos_range, TS_REAL4 spot,
                                                   int spot_cull) {
  ts_light_volume v;
  TS_REAL r = pos_range.w;
  TS_REAL3 p = TS_MAKE3(pos_range.x, pos_range.y, pos_range.z);
  TS_REAL slack = TS_LIT(TS_VOLUME_SLACK) * r;
  v.apex = p;
  v.axis = TS_MAKE3(spot.x, spot.y, spot.z);
  v.range = r;
  v.cos_outer = spot.w;
  v.sin_outer = sqrt(max(TS_LIT(1.0) - spot.w * spot.w, TS_LIT(0.0)));
  v.cone = spot.w > TS_LIT(0.0) && spot_cull != TS_SPOT_CULL_RANGE_SPHERE;
  if (!v.cone) { /* a point light, or a cone of 90 degrees or more: the range sphere */
    v.center = p;
    v.radius = r;
    TS_REAL3 e = TS_MAKE3(r, r, r);
    v.lo = p - e;
    v.hi = p + e;
    return v;
  }
  /* The sector's smallest enclosing sphere: through the apex and the rim circle (which also holds
   * the cap's tip) for theta <= 45 degrees, else the one with the rim circle as a great circle. */
  if (v.cos_outer >= sqrt(TS_LIT(0.5))) {
    v.radius = r / (TS_LIT(2.0) * v.cos_outer);
    v.center = p + v.axis * v.radius;
  } else {
    v.radius = r * v.sin_outer;
    v.center = p + v.axis * (r * v.cos_outer);
  }
  v.radius += slack;
  if (spot_cull == TS_SPOT_CULL_BOUND_SPHERE) {
    TS_REAL3 e = TS_MAKE3(v.radius, v.radius, v.radius);
    v.lo = v.center - e;
    v.hi = v.center + e;
    v.cone = 0; /* tested as the sphere it now is */
    return v;
  }
  /* The exact box: along each axis the sector reaches from the apex to r times the extreme
   * component of a direction in the cone. */
  TS_REAL lx, hx, ly, hy, lz, hz;
  ts_cone_extent(v.axis.x, v.cos_outer, v.sin_outer, &lx, &hx);
  ts_cone_extent(v.axis.y, v.cos_outer, v.sin_outer, &ly, &hy);
  ts_cone_extent(v.axis.z, v.cos_outer, v.sin_outer, &lz, &hz);
  v.lo = p + TS_MAKE3(min(lx, TS_LIT(0.0)), min(ly, TS_LIT(0.0)), min(lz, TS_LIT(0.0))) * r -
         TS_MAKE3(slack, slack, slack);
  v.hi = p + TS_MAKE3(max(hx, TS_LIT(0.0)), max(hy, TS_LIT(0.0)), max(hz, TS_LIT(0.0))) * r +
         TS_MAKE3(slack, slack, slack);
  return v;
}

/* NDC bounds of a view-space box clipped to the near plane (the box's depth w = -z). */
static inline TS_REAL4 ts_box_ndc_bounds(TS_REAL3 lo, TS_REAL3 hi, TS_REAL znear, TS_REAL tan_x,
                                         TS_REAL tan_y) {
  TS_REAL w0 = max(-hi.z, znear), w1 = -lo.z;
  if (w1 < znear) return TS_MAKE4(TS_LIT(1.0), TS_LIT(1.0), TS_LIT(-1.0), TS_LIT(-1.0));
  /* x/w is smallest at the far side for x >= 0 and at the near side for x < 0, and so on. */
  TS_REAL sx0 = lo.x >= TS_LIT(0.0) ? lo.x / w1 : lo.x / w0;
  TS_REAL sx1 = hi.x >= TS_LIT(0.0) ? hi.x / w0 : hi.x / w1;
  TS_REAL sy0 = lo.y >= TS_LIT(0.0) ? lo.y / w1 : lo.y / w0;
  TS_REAL sy1 = hi.y >= TS_LIT(0.0) ? hi.y / w0 : hi.y / w1;
  return TS_MAKE4(sx0 / tan_x, sy0 / tan_y, sx1 / tan_x, sy1 / tan_y);
}

/* Conservative NDC bounds of the light volume (empty: xmin > xmax). */
static inline TS_REAL4 ts_light_ndc_bounds(const ts_light_volume *v, TS_REAL znear, TS_REAL tan_x,
                                           TS_REAL tan_y) {
  TS_REAL4 b = ts_sphere_ndc_bounds(v->center, v->radius, znear, tan_x, tan_y);
  if (!v->cone) return b;
  TS_REAL4 box = ts_box_ndc_bounds(v->lo, v->hi, znear, tan_x, tan_y);
  return TS_MAKE4(max(b.x, box.x), max(b.y, box.y), min(b.z, box.z), min(b.w, box.w));
}

/* Does the volume's depth extent meet the geometry depth range [zmin, zmax]? (Empty: no.) */
static inline int ts_light_meets_depth_range(const ts_light_volume *v, TS_REAL zmin,
                                             TS_REAL zmax) {
  return zmin <= zmax && -v->lo.z >= zmin && -v->hi.z <= zmax;
}

/* The cone against a sphere (c, R): 0 when the sphere lies wholly outside the cone's angle, in
 * front of its range or behind its apex (Wronski's test; conservative for the sector). */
static inline int ts_cone_meets_sphere(const ts_light_volume *v, TS_REAL3 c, TS_REAL R) {
  TS_REAL3 d = c - v->apex;
  TS_REAL along = dot(d, v->axis);
  TS_REAL across = sqrt(max(dot(d, d) - along * along, TS_LIT(0.0)));
  if (along > R + v->range || along < -R) return 0;
  return v->cos_outer * across - along * v->sin_outer <= R;
}

/* The per-tile test of a light volume, for a tile already inside the light's rectangle and
 * whose geometry depth range [zmin, zmax] the volume's depth extent meets. */
static inline int ts_light_meets_tile(const ts_light_volume *v, int mode, int px0, int py0,
                                      int px1, int py1, int width, int height, TS_REAL tan_x,
                                      TS_REAL tan_y, TS_REAL zmin, TS_REAL zmax) {
  if (!v->cone)
    return ts_sphere_meets_tile(v->center, v->radius, mode, px0, py0, px1, py1, width, height,
                                tan_x, tan_y, zmin, zmax);
  TS_REAL4 s = ts_tile_slopes(px0, py0, px1, py1, width, height, tan_x, tan_y);
  /* The tile's view-space box between zmin and zmax, and its bounding sphere. */
  TS_REAL3 blo = TS_MAKE3(min(s.x * zmin, s.x * zmax), min(s.y * zmin, s.y * zmax), -zmax);
  TS_REAL3 bhi = TS_MAKE3(max(s.z * zmin, s.z * zmax), max(s.w * zmin, s.w * zmax), -zmin);
  TS_REAL3 extent = (bhi - blo) * TS_LIT(0.5);
  if (!ts_cone_meets_sphere(v, blo + extent, sqrt(dot(extent, extent)))) return 0;
  if (mode == TS_CULL_FRUSTUM) return ts_sphere_meets_tile_planes(v->center, v->radius, s);
  if (mode == TS_CULL_AABB)
    return ts_sphere_meets_tile_box(v->center, v->radius, s, zmin, zmax) &&
           v->lo.x <= bhi.x && v->hi.x >= blo.x && v->lo.y <= bhi.y && v->hi.y >= blo.y;
  return 1;
}

/* ---- A cheap pre-test of the rectangle and depth-range tests (tiled_single.cl) --------------
 * Every tile of the single-kernel technique tests every light; building the volume and its
 * screen bounds (above) costs a few hundred instructions per (tile, light), for the ~95% of
 * lights that miss the tile. This test is a sphere against the tile's side planes and depth range
 * (branch-free, so that a CPU compiler can vectorise it across work-items; PoCL's output for it
 * has not been read yet), and never says 0 where the
 * full tests would say 1: the sphere, (pos_range.xyz, TS_PRETEST_REACH * pos_range.w), holds every
 * form of the volume's bounding sphere and box (a cone's bounding sphere lies within sqrt(2)
 * ranges of its apex); the rectangle's slopes are those of points of that bounding sphere, so a
 * tile inside the rectangle lies, on each axis alone, between the planes of both its sides that
 * the sphere reaches. `s` and `n` are the tile's slopes, widened by a pixel against rounding
 * (ts_pretest_slopes), and their planes' normal lengths; (zmin, zmax) its depth range. */
#define TS_PRETEST_REACH 1.001
#define TS_PRETEST_CONE_REACH 1.4152 /* sqrt(2) * 1.0007 */

static inline TS_REAL4 ts_pretest_slopes(int px0, int py0, int px1, int py1, int width,
                                         int height, TS_REAL tan_x, TS_REAL tan_y) {
  return ts_tile_slopes(px0 - 1, py0 - 1, px1 + 1, py1 + 1, width, height, tan_x, tan_y);
}

static inline TS_REAL4 ts_pretest_norms(TS_REAL4 s) {
  return TS_MAKE4(sqrt(TS_LIT(1.0) + s.x * s.x), sqrt(TS_LIT(1.0) + s.y * s.y),
                  sqrt(TS_LIT(1.0) + s.z * s.z), sqrt(TS_LIT(1.0) + s.w * s.w));
}

static inline int ts_light_may_meet_tile(TS_REAL4 pos_range, TS_REAL4 spot, TS_REAL4 s,
                                         TS_REAL4 n, TS_REAL zmin, TS_REAL zmax) {
  TS_REAL R = pos_range.w * (spot.w > TS_LIT(0.0) ? TS_LIT(TS_PRETEST_CONE_REACH)
                                                   : TS_LIT(TS_PRETEST_REACH));
  TS_REAL w = -pos_range.z;
  return (w + R >= zmin) & (w - R <= zmax) & (pos_range.x - s.x * w >= -R * n.x) &
         (s.z * w - pos_range.x >= -R * n.z) & (pos_range.y - s.y * w >= -R * n.y) &
         (s.w * w - pos_range.y >= -R * n.w);
}

/* Whether the light lights surface point P at all (what a stencil test of the light volume
 * decides): inside the range and, for a spot light, inside the cone. The same arithmetic as
 * kernels/shading.h's range cut and angular term, so no point it lights is rejected. */
static inline int ts_light_volume_holds(TS_REAL4 pos_range, TS_REAL4 spot, TS_REAL3 P) {
  TS_REAL3 v = TS_MAKE3(pos_range.x, pos_range.y, pos_range.z) - P;
  TS_REAL d2 = dot(v, v);
  if (!(d2 < pos_range.w * pos_range.w)) return 0;
  if (spot.w <= TS_LIT(-1.0)) return 1;
  TS_REAL d = sqrt(d2);
  TS_REAL cd = -(spot.x * (v.x / d) + spot.y * (v.y / d) + spot.z * (v.z / d));
  return cd > spot.w;
}
