/*
 * Light-culling geometry shared by the binning kernels and by host tests, in the common subset of
 * OpenCL C and C++ (same conventions as shading.h, TS_LIT included; the includer also defines
 * TS_REAL4/TS_MAKE4 and min).
 *
 * Conventions: view space, camera at the origin looking down -Z; "depth" w = -z > 0.
 * A sphere's screen bounds are returned as NDC slopes' images: (xmin, ymin, xmax, ymax) in NDC,
 * y up. An empty result has xmin > xmax.
 */
#ifndef TS_REAL4
#error "define TS_REAL4 and TS_MAKE4 before including culling.h"
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
  TS_REAL h = h2 > (TS_REAL)0 ? sqrt(h2) : (TS_REAL)0;
  TS_REAL chord_lo = (a - h) / znear, chord_hi = (a + h) / znear;
  TS_REAL s0 = tw0 >= znear ? ta0 / tw0 : (ta0 > (TS_REAL)0 ? chord_hi : chord_lo);
  TS_REAL s1 = tw1 >= znear ? ta1 / tw1 : (ta1 > (TS_REAL)0 ? chord_hi : chord_lo);
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
  TS_REAL4 empty = TS_MAKE4((TS_REAL)1, (TS_REAL)1, (TS_REAL)-1, (TS_REAL)-1);
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
  if (b.z < (TS_REAL)-1 || b.x > (TS_REAL)1 || b.w < (TS_REAL)-1 || b.y > (TS_REAL)1) return 0;
  TS_REAL px0 = (max(b.x, (TS_REAL)-1) + (TS_REAL)1) * TS_LIT(0.5) * (TS_REAL)width;
  TS_REAL px1 = (min(b.z, (TS_REAL)1) + (TS_REAL)1) * TS_LIT(0.5) * (TS_REAL)width;
  TS_REAL py0 = ((TS_REAL)1 - min(b.w, (TS_REAL)1)) * TS_LIT(0.5) * (TS_REAL)height;
  TS_REAL py1 = ((TS_REAL)1 - max(b.y, (TS_REAL)-1)) * TS_LIT(0.5) * (TS_REAL)height;
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
  TS_REAL sx0 = ((TS_REAL)2 * (TS_REAL)px0 / (TS_REAL)width - (TS_REAL)1) * tan_x;
  TS_REAL sx1 = ((TS_REAL)2 * (TS_REAL)px1 / (TS_REAL)width - (TS_REAL)1) * tan_x;
  TS_REAL sy1 = ((TS_REAL)1 - (TS_REAL)2 * (TS_REAL)py0 / (TS_REAL)height) * tan_y;
  TS_REAL sy0 = ((TS_REAL)1 - (TS_REAL)2 * (TS_REAL)py1 / (TS_REAL)height) * tan_y;
  return TS_MAKE4(sx0, sy0, sx1, sy1);
}

/* Sphere against the side planes through the eye: a point is inside when s0 <= x/w <= s1 (and
 * the same for y). Signed distance to the plane x - s*w = 0 is (x - s*w)/sqrt(1 + s*s). */
static inline int ts_sphere_meets_tile_planes(TS_REAL3 c, TS_REAL r, TS_REAL4 s) {
  TS_REAL w = -c.z;
  if ((c.x - s.x * w) < -r * sqrt((TS_REAL)1 + s.x * s.x)) return 0;
  if ((s.z * w - c.x) < -r * sqrt((TS_REAL)1 + s.z * s.z)) return 0;
  if ((c.y - s.y * w) < -r * sqrt((TS_REAL)1 + s.y * s.y)) return 0;
  if ((s.w * w - c.y) < -r * sqrt((TS_REAL)1 + s.w * s.w)) return 0;
  return 1;
}

/* Sphere against the axis-aligned box around the tile frustum between depths zmin and zmax. */
static inline int ts_sphere_meets_tile_box(TS_REAL3 c, TS_REAL r, TS_REAL4 s, TS_REAL zmin,
                                           TS_REAL zmax) {
  TS_REAL bx0 = min(s.x * zmin, s.x * zmax), bx1 = max(s.z * zmin, s.z * zmax);
  TS_REAL by0 = min(s.y * zmin, s.y * zmax), by1 = max(s.w * zmin, s.w * zmax);
  TS_REAL w = -c.z;
  TS_REAL dx = max(max(bx0 - c.x, c.x - bx1), (TS_REAL)0);
  TS_REAL dy = max(max(by0 - c.y, c.y - by1), (TS_REAL)0);
  TS_REAL dw = max(max(zmin - w, w - zmax), (TS_REAL)0);
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
