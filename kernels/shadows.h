/*
 * The shadow factor of a shadow-casting light (issue #18; docs/shadows.md): the one sampling
 * function of the kernels (kernels/gbuffer.h, lanes.h) and of the double reference
 * (src/shading/shading_cpu.h) and of the forward techniques' fragment shader
 * (shaders/tiled_forward.frag), written in the common subset of OpenCL C, C++ and GLSL like
 * kernels/shading.h (its TS_CAST for casts), so all sample the same float atlas with the same
 * arithmetic.
 *
 * The includer includes kernels/shading.h first (TS_REAL, TS_REAL3, TS_REAL4, TS_CAST) and, for
 * C++ and GLSL, defines the face table's and atlas's parameter types and loads (defaults: OpenCL
 * __global buffers; GLSL's are shader storage and a texture, the parameters unused):
 *   TS_SHADOW_FACES        pointer to the face table (float4 records)
 *   TS_SHADOW_ATLAS        pointer to the atlas (float texels, row-major, row 0 at the top)
 *   TS_SHADOW_FACE(t, i)   record float4 i of the table, as TS_REAL4
 *   TS_SHADOW_TEXEL(a, i)  texel i of the atlas, as TS_REAL
 * and makes floor, sqrt, max, min visible for TS_REAL.
 *
 * Everything is in view space. A face is TS_SHADOW_FACE_RECORDS float4s (filled on the host by
 * shadowFaceTable, src/raster/shadow_maps.cpp):
 *   0, 1, 2  rows x, y, w of the face's clip matrix from view space (mapFromWorld x inverse view)
 *   3        the row giving the receiver's linear depth along the face's axis (-Z of the face's
 *            view: the maps' stored convention)
 *   4        the face's atlas rectangle (x, y, size) and the atlas's width, in texels
 *   5        a texel's world footprint at linear depth d: a + b d (perspective: b; ortho: a),
 *            then the bias's constant C and slope S (in footprints; below)
 *   6        the filter's taps a side N (1: none), the light's face count (6 cube, or 1), and
 *            1 for the receiver-plane bias (--shadow-bias receiver,C; below), else 0
 * A light's faces are consecutive; a light refers to its first.
 */
#ifndef TS_SHADOWS_H
#define TS_SHADOWS_H

#ifndef TS_CAST
#error "include kernels/shading.h (its TS_CAST) before kernels/shadows.h"
#endif

#ifndef TS_SHADOW_FACES
#define TS_SHADOW_FACES __global const float4 *
#define TS_SHADOW_ATLAS __global const float *
#define TS_SHADOW_FACE(t, i) ((t)[i])
#define TS_SHADOW_TEXEL(a, i) ((a)[i])
#endif

#define TS_SHADOW_FACE_RECORDS 7
/* Grazing light: tan(theta) is capped so the slope bias stays finite (at N.l = 0 the light term
 * is 0 anyway). */
#define TS_SHADOW_MAX_TAN 10.0

static inline TS_REAL ts_shadow_row(TS_REAL4 r, TS_REAL3 P) {
  return r.x * P.x + r.y * P.y + r.z * P.z + r.w;
}

/* The receiver-plane depth bias (Isidoro, GDC 2006; Schuler, ShaderX5): the gradient (gu, gv) of
 * the face's linear depth across the plane through P with normal N, per texel column and row.
 * The kernels have no screen derivatives, so the plane is the G-buffer's: with Gu, Gv the
 * gradients of the texel coordinates u, v in view space, the depth row's xyz is
 * gu Gu + gv Gv + k N (a change along N leaves the plane), solved by Cramer's rule. Linear in the
 * texel offset, so exact for planar receivers up to the perspective's curvature over the
 * filter's reach. A plane seen edge-on (det 0) or steeper than TS_SHADOW_MAX_TAN is clamped to
 * that slope, as the slope bias is. */
static inline void ts_shadow_receiver_gradient(TS_SHADOW_FACES faces, int base, TS_REAL3 N,
                                               TS_REAL nx, TS_REAL ny, TS_REAL w, TS_REAL size,
                                               TS_REAL limit, TS_OUT(TS_REAL, gu),
                                               TS_OUT(TS_REAL, gv)) {
  TS_REAL4 r0 = TS_SHADOW_FACE(faces, base + 0);
  TS_REAL4 r1 = TS_SHADOW_FACE(faces, base + 1);
  TS_REAL4 rw = TS_SHADOW_FACE(faces, base + 2);
  TS_REAL4 rd = TS_SHADOW_FACE(faces, base + 3);
  /* u = (nx + 1) size / 2, v = (1 - ny) size / 2, nx = (r0 . P) / w: d nx = (r0 - nx rw) / w. */
  TS_REAL su = TS_LIT(0.5) * size / w;
  TS_REAL ax = su * (r0.x - nx * rw.x), ay = su * (r0.y - nx * rw.y), az = su * (r0.z - nx * rw.z);
  TS_REAL bx = -su * (r1.x - ny * rw.x), by = -su * (r1.y - ny * rw.y),
          bz = -su * (r1.z - ny * rw.z);
  /* Gv x N, N x Gu */
  TS_REAL cx = by * N.z - bz * N.y, cy = bz * N.x - bx * N.z, cz = bx * N.y - by * N.x;
  TS_REAL ex = N.y * az - N.z * ay, ey = N.z * ax - N.x * az, ez = N.x * ay - N.y * ax;
  TS_REAL det = ax * cx + ay * cy + az * cz;
  TS_REAL du = rd.x * cx + rd.y * cy + rd.z * cz;
  TS_REAL dv = rd.x * ex + rd.y * ey + rd.z * ez;
  TS_REAL a = TS_LIT(0.0), b = TS_LIT(0.0);
  if (det != TS_LIT(0.0)) { /* det 0: edge-on, N.l ~ 0 and the light term ~ 0 */
    a = du / det;
    b = dv / det;
  }
  /* Also false for NaN: min/max keep a finite value. */
  TS_DEREF(gu) = !(a == a) ? TS_LIT(0.0) : max(-limit, min(limit, a));
  TS_DEREF(gv) = !(b == b) ? TS_LIT(0.0) : max(-limit, min(limit, b));
}

/* The face's share of the visibility of P (1 lit, 0 shadowed) given the bias in world units. P
 * outside the face's frustum (a spot light's rim beyond its map, a directional map's fit) is lit:
 * the map says nothing there. */
static inline TS_REAL ts_shadow_face(TS_SHADOW_FACES faces, TS_SHADOW_ATLAS atlas, int face,
                                     TS_REAL3 P, TS_REAL3 N, TS_REAL3 L) {
  int base = face * TS_SHADOW_FACE_RECORDS;
  TS_REAL4 rect = TS_SHADOW_FACE(faces, base + 4);
  TS_REAL4 bias = TS_SHADOW_FACE(faces, base + 5);
  TS_REAL4 misc = TS_SHADOW_FACE(faces, base + 6);
  TS_REAL w = ts_shadow_row(TS_SHADOW_FACE(faces, base + 2), P);
  if (!(w > TS_LIT(0.0))) return TS_LIT(1.0);
  TS_REAL nx = ts_shadow_row(TS_SHADOW_FACE(faces, base + 0), P) / w;
  TS_REAL ny = ts_shadow_row(TS_SHADOW_FACE(faces, base + 1), P) / w;
  /* Also false for NaN: no texel index is ever formed from one. */
  if (!(nx >= TS_LIT(-1.0) && nx <= TS_LIT(1.0) && ny >= TS_LIT(-1.0) && ny <= TS_LIT(1.0)))
    return TS_LIT(1.0);
  TS_REAL depth = ts_shadow_row(TS_SHADOW_FACE(faces, base + 3), P);
  TS_REAL size = rect.z;
  /* Texel coordinates within the face: column u, row v (row 0 at the top, NDC y = +1). */
  TS_REAL u = (nx + TS_LIT(1.0)) * TS_LIT(0.5) * size;
  TS_REAL v = (TS_LIT(1.0) - ny) * TS_LIT(0.5) * size;
  /* Slope bias: tan of the angle between N and the direction to the light. */
  TS_REAL ndl = max(N.x * L.x + N.y * L.y + N.z * L.z, TS_LIT(0.0));
  TS_REAL tan_theta = TS_LIT(TS_SHADOW_MAX_TAN);
  if (ndl * TS_LIT(TS_SHADOW_MAX_TAN) > sqrt(max(TS_LIT(1.0) - ndl * ndl, TS_LIT(0.0))))
    tan_theta = sqrt(max(TS_LIT(1.0) - ndl * ndl, TS_LIT(0.0))) / ndl;
  /* bias = footprint (C + S tan(theta) n/2): a plane at angle theta to the light changes depth
   * by footprint tan(theta) per texel, and the filter's farthest texel centre is n/2 texels
   * from the receiver (none: half a texel); S is the margin over that. */
  int n = TS_CAST(int, misc.x), isize = TS_CAST(int, size), stride = TS_CAST(int, rect.w);
  TS_REAL footprint = bias.x + bias.y * depth;
  TS_REAL reach = TS_LIT(0.5) * TS_CAST(TS_REAL, n);
  TS_REAL test = depth - footprint * (bias.z + bias.w * tan_theta * reach);
  int x0 = TS_CAST(int, floor(u - TS_LIT(0.5) * TS_CAST(TS_REAL, n - 1)));
  int y0 = TS_CAST(int, floor(v - TS_LIT(0.5) * TS_CAST(TS_REAL, n - 1)));
  int origin = TS_CAST(int, rect.y) * stride + TS_CAST(int, rect.x);
  /* Receiver plane: each tap compares the depth of P's tangent plane at the tap's texel centre
   * (gu, gv: the plane's depth per texel), so only C is left as bias (S is not used). */
  TS_REAL gu = TS_LIT(0.0), gv = TS_LIT(0.0);
  if (misc.z != TS_LIT(0.0)) {
    ts_shadow_receiver_gradient(faces, base, N, nx, ny, w, size,
                                footprint * TS_LIT(TS_SHADOW_MAX_TAN), TS_ADDR(gu), TS_ADDR(gv));
    test = depth - footprint * bias.z;
  }
  int lit = 0;
  /* N x N texels from (x0, y0), each clamped to the face's rectangle (never a neighbour's). */
  for (int j = 0; j < n; ++j) {
    int ty = y0 + j < 0 ? 0 : y0 + j >= isize ? isize - 1 : y0 + j;
    for (int i = 0; i < n; ++i) {
      int tx = x0 + i < 0 ? 0 : x0 + i >= isize ? isize - 1 : x0 + i;
      TS_REAL t = test;
      if (misc.z != TS_LIT(0.0))
        t = test + gu * (TS_CAST(TS_REAL, tx) + TS_LIT(0.5) - u) +
            gv * (TS_CAST(TS_REAL, ty) + TS_LIT(0.5) - v);
      if (t <= TS_SHADOW_TEXEL(atlas, origin + ty * stride + tx)) ++lit;
    }
  }
  return TS_CAST(TS_REAL, lit) / TS_CAST(TS_REAL, n * n);
}

/* The visibility factor in [0, 1] of view-space point P (normal N, unit direction L towards the
 * light) for the light whose first face is `first` (>= 0). A cube picks one face by the largest
 * linear depth of P over its six (the major axis of P - light, with its sign) and samples that
 * face only, its footprint clamped to it: no seam between faces can crack. */
static inline TS_REAL ts_shadow_factor(TS_SHADOW_FACES faces, TS_SHADOW_ATLAS atlas, int first,
                                       TS_REAL3 P, TS_REAL3 N, TS_REAL3 L) {
  int count = TS_CAST(int, TS_SHADOW_FACE(faces, first * TS_SHADOW_FACE_RECORDS + 6).y);
  int face = first;
  TS_REAL best = ts_shadow_row(TS_SHADOW_FACE(faces, first * TS_SHADOW_FACE_RECORDS + 3), P);
  for (int k = 1; k < count; ++k) {
    TS_REAL d =
        ts_shadow_row(TS_SHADOW_FACE(faces, (first + k) * TS_SHADOW_FACE_RECORDS + 3), P);
    if (d > best) {
      best = d;
      face = first + k;
    }
  }
  return ts_shadow_face(faces, atlas, face, P, N, L);
}

#endif
