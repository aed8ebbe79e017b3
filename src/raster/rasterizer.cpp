// The software rasterizer behind ts::rasterize: a deterministic, multithreaded, tiled triangle
// rasterizer that writes the G-buffer planes.
//
// Pipeline (all phases on `threads` std::threads):
//  1. Vertices to view space (double positions, float view-space unit normals), once per vertex.
//  2. Triangle setup, triangles split into one contiguous range per thread:
//     - clip space (x, y, w) = (X / tanHalfFovX, Y / tanHalfFovY, -Z), with the float tangents of
//       CameraIntrinsics so depth and the kernels' position reconstruction agree;
//     - trivial reject when all three vertices lie outside one frustum plane (w < znear, w > zfar,
//       |x| > w, |y| > w) or a coordinate is not finite;
//     - Sutherland-Hodgman clipping in homogeneous clip space against the near plane w = znear
//       (= clip z = -w of projection()) and, only when a vertex lies outside it, a guard band of
//       2^20 pixels around the screen (keeps the fixed-point values small: see below). Edge
//       intersections are computed from the (inside, outside) vertex pair whatever the edge's
//       direction, so two triangles sharing an edge produce bit-identical clipped vertices and
//       stay watertight. The clipped polygon (<= 8 vertices) is fanned into triangles;
//     - far plane: not clipped; fragments deeper than zfar are rejected per pixel (and triangles
//       entirely beyond it are dropped in setup);
//     - each (sub-)triangle is snapped to 24.8 fixed point (8 sub-pixel bits) and gets three
//       integer edge functions in int64 (|coordinate| < 2^29, so products < 2^59: exact, no
//       overflow) with the top-left fill rule folded in as a bias of 1 on edges that are neither
//       top nor left. Image y points down; with the interior on the positive side, an edge
//       (dx, dy) is "top" when dy == 0 && dx > 0 and "left" when dy < 0;
//     - each triangle is binned into the 64x64 screen tiles its bounding box overlaps (skipping
//       tiles that lie wholly outside one edge).
//  3. Tiles are handed out dynamically; one thread owns a whole tile, so no two threads write one
//     pixel. Per tile a visibility pass runs every binned triangle over its pixels and keeps, per
//     pixel, the nearest fragment (compared as 1/depth: larger wins; equal -> lower triangle
//     index), then a resolve pass interpolates the attributes once per visible pixel. Because the
//     winner is a total order on (depth, triangle index) and every value is computed by the same
//     code from the same inputs, the output is bit-identical for any thread count or bin order.
//
// Interpolation is perspective-correct and computed from the unsnapped double-precision geometry
// (2D homogeneous rasterization, Olano & Greer 1997): with M = [c0 c1 c2] the clip-space vertex
// columns, a pixel with NDC (u, v) sees the triangle's plane at barycentrics B = t M^-1 (u, v, 1),
// where t = 1 / sum(M^-1 (u, v, 1)) is exactly the linear depth -Z_view. So depth is the exact
// ray-plane intersection at the pixel centre, and attributes are 1/w-linear. For the rare pixels
// where this is unreliable (triangles seen nearly edge-on, or sub-pixel triangles whose snapped
// coverage strays more than kBaryTolerance outside the exact triangle) the fragment falls back to
// perspective-correct interpolation over the snapped sub-triangle, whose barycentrics are >= 0
// there by construction.
//
// Facing and normals: nothing is culled (scenes may have inconsistent winding). A triangle is
// back-facing when its geometric normal (counter-clockwise winding, as in glTF) points away from
// the eye. The shading normal is the perspective-correct interpolation of the vertex normals,
// normalized; for doubleSided materials it is negated on back-facing triangles (so it faces the
// viewer, as glTF specifies), for single-sided materials it is kept as the vertex data says. A
// vertex-normal interpolation of (near) zero length is replaced by the geometric normal.
//
// Normal maps (a material's normalTexture, with the scene's tangents; RasterOptions::normalMaps):
// ts_normal_mapped in shaders/normal_mapping.h perturbs the interpolated normal before the
// double-sided flip, with the perspective-correct interpolation of the view-space tangents.
//
// Depth only (rasterizeDepth, the shadow maps of raster/shadow_maps.h): the same setup, clipping,
// binning and fill rule over a list of triangles, without the vertex pass (positions are
// transformed as the setup reads them: a face draws few of the scene's triangles) and without
// attributes: a tile keeps the nearest depth per pixel. Orthographic views (directional lights)
// use clip w = 1, no near clip, and interpolate -Z_view with the barycentrics; depth outside
// [znear, zfar] is rejected per pixel.
// alphaMode MASK: a fragment that would win a pixel is first alpha-tested (ts_material_covered in
// shaders/material_planes.h, at the barycentrics and UV resolve() would use); one below the
// cutoff is left out, so what lies behind wins. The depth-only path tests the same way (so a
// leaf's cut-out casts no shadow). BLEND is refused (validateForRaster) unless the scene's
// --blend policy already turned it into OPAQUE or MASK (applyBlendPolicy, at load); with
// `--blend blend` the G-buffer pass refuses it too (the forward techniques composite it in
// OpenGL) and the depth-only path leaves it out (composited surfaces cast no shadow).
//
// Material planes: ts_material_planes in shaders/material_planes.h, the one definition the OpenGL
// rasterizer (src/raster/gl_rasterizer.cpp, shaders/gbuffer.frag) compiles as GLSL; these notes'
// conventions are mirrored there, convention by convention (docs/opengl.md).
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <thread>
#include <vector>

#include "raster/rasterizer.h"
#include "gbuffer/plane_alloc.h"
#include "raster/scene_validation.h"
#include "shaders/material_planes.h"
#include "shaders/normal_mapping.h"
#include "util/error.h"

namespace ts {
namespace {

constexpr int kSubBits = 8;
constexpr int64_t kSubOne = int64_t(1) << kSubBits;  // 256 fixed-point units per pixel
constexpr int64_t kSubHalf = kSubOne / 2;
constexpr int kTileSize = 64;
constexpr double kGuardBandPixels = double(1 << 20);
constexpr int kMaxImageSize = 1 << 16;
constexpr int kMaxWorkers = 256;
// Most negative barycentric accepted from the exact-plane interpolation before a fragment uses the
// snapped-triangle fallback (snapping moves edges by <= 1/512 pixel: only sub-pixel triangles get
// near this).
constexpr double kBaryTolerance = 1e-2;
constexpr uint32_t kNone = std::numeric_limits<uint32_t>::max();

int64_t floorDiv(int64_t a, int64_t b) {  // b > 0
  int64_t q = a / b;
  return (a % b != 0 && a < 0) ? q - 1 : q;
}

// floor(v + 0.5) for |v| < 2^52 (snapped coordinates stay below 2^30), without a libm call.
inline int64_t roundToInt(double v) {
  double r = v + 0.5;
  int64_t i = int64_t(r);
  return double(i) > r ? i - 1 : i;
}

// Runs body(begin, end, worker) over [0, n) split into `workers` contiguous ranges.
template <typename Body>
void parallelRanges(size_t n, int workers, Body body) {
  if (workers <= 1 || n < 2) {
    body(size_t(0), n, 0);
    return;
  }
  std::vector<std::thread> pool;
  for (int k = 0; k < workers; ++k) {
    size_t b = n * size_t(k) / size_t(workers), e = n * size_t(k + 1) / size_t(workers);
    pool.emplace_back([=, &body] { body(b, e, k); });
  }
  for (auto& t : pool) t.join();
}

// Runs body(item, worker) for every item in [0, n), handed out dynamically.
template <typename Body>
void parallelItems(int n, int workers, Body body) {
  if (workers <= 1 || n < 2) {
    for (int i = 0; i < n; ++i) body(i, 0);
    return;
  }
  std::atomic<int> next{0};
  std::vector<std::thread> pool;
  for (int k = 0; k < workers; ++k)
    pool.emplace_back([&, k] {
      for (int i; (i = next.fetch_add(1, std::memory_order_relaxed)) < n;) body(i, k);
    });
  for (auto& t : pool) t.join();
}

// A vertex during clipping: clip-space position and barycentrics in the original triangle.
struct ClipVertex {
  double x, y, w;
  double b[3];
};

// Per visible triangle, shared by its clipped sub-triangles.
struct TriangleSetup {
  double f[3][3];  // f_i(px, py) = f[i][0] px + f[i][1] py + f[i][2]; B_i = f_i / sum f
  uint32_t triangle;
  bool homogeneous;  // M invertible enough for the exact-plane path
  bool backFacing;
};

// A snapped (sub-)triangle ready for the tile loops.
struct SubTriangle {
  int64_t ea[3], eb[3], ec[3];  // e_i(X, Y) = ea X + eb Y + ec at fixed-point pixel centres,
                                // covered when all three are >= 0 (fill-rule bias folded into ec)
  int32_t x0, y0, x1, y1;       // inclusive pixel bounds, clamped to the screen
  uint32_t setup;               // index into the worker's TriangleSetup list
  uint32_t triangle;
  uint8_t bias;  // bit i: edge i is not top-left (ec holds -1 for it)
};

// Fallback data of a sub-triangle: per vertex (in edge order) 1/w and barycentrics in the
// original triangle. Vertex i is opposite edge i.
struct SubFallback {
  double invW[3];
  double b[3][3];
};

struct WorkerOutput {
  std::vector<TriangleSetup> setups;
  std::vector<SubTriangle> subs;
  std::vector<SubFallback> fallbacks;
  std::vector<std::vector<uint32_t>> bins;  // per tile: indices into subs
};

struct Frame {
  int width, height;
  int tilesX, tilesY;
  double znear, zfar;
  double tanX, tanY;      // orthographic: the half extents
  double guardX, guardY;  // guard band in NDC units (|ndc| <= guard)
  bool ortho = false;     // rasterizeDepth's orthographic views: clip w = 1, depth interpolated
};

// A covered fragment: returns its inverse linear depth 1 / -Z_view (> 0) and, when kBary, its
// perspective-correct barycentrics in the original triangle. `e` are the edge functions at the
// pixel centre without the fill-rule bias (all >= 0; their sum is the sub-triangle's area).
template <bool kBary>
inline double evaluate(const TriangleSetup& t, const SubFallback& fb, double px, double py,
                       const int64_t e[3], double* B) {
  if (t.homogeneous) {
    const double f0 = t.f[0][0] * px + t.f[0][1] * py + t.f[0][2];
    const double f1 = t.f[1][0] * px + t.f[1][1] * py + t.f[1][2];
    const double f2 = t.f[2][0] * px + t.f[2][1] * py + t.f[2][2];
    const double s = f0 + f1 + f2;
    const double limit = -kBaryTolerance * s;  // B_i = f_i / s >= -tolerance
    if (s > 0.0 && s <= std::numeric_limits<double>::max() && f0 >= limit && f1 >= limit &&
        f2 >= limit) {
      if (kBary) {
        const double depth = 1.0 / s;
        B[0] = f0 * depth;
        B[1] = f1 * depth;
        B[2] = f2 * depth;
      }
      return s;
    }
  }
  // Perspective-correct over the snapped sub-triangle: screen barycentrics e_i / area, 1/w-linear.
  const double m0 = double(e[0]) * fb.invW[0], m1 = double(e[1]) * fb.invW[1],
               m2 = double(e[2]) * fb.invW[2];
  const double m = m0 + m1 + m2;
  if (kBary)
    for (int k = 0; k < 3; ++k) B[k] = (m0 * fb.b[0][k] + m1 * fb.b[1][k] + m2 * fb.b[2][k]) / m;
  return m / (double(e[0]) + double(e[1]) + double(e[2]));
}

class Rasterizer {
 public:
  Rasterizer(const Scene& scene, const SceneCamera& camera, int width, int height,
             const RasterOptions& options)
      : scene_(scene), view_(camera.viewFromWorld), options_(options) {
    CameraIntrinsics in = CameraIntrinsics::from(camera, width, height);
    setFrame(width, height, in.znear, in.zfar, in.tanHalfFovX, in.tanHalfFovY, options.threads);
    validateForRaster(scene_);
    if (scene_.blendComposited && drawsBlendedMaterials(scene_))
      throw Error(
          "scene '" + scene_.name +
          "': --blend blend composites its alphaMode BLEND surfaces in the forward "
          "techniques' OpenGL passes; the software rasterizer draws none (use --raster gl)");
    normalMaps_ = options.normalMaps && !scene_.tangents.empty();
  }

  // Depth only (rasterizeDepth): `triangles` of a scene that passed validateForRaster.
  Rasterizer(const Scene& scene, const DepthView& view, const std::vector<uint32_t>& triangles,
             int width, int height, int threads)
      : scene_(scene), view_(view.viewFromWorld), triangles_(&triangles), depthOnly_(true) {
    setFrame(width, height, view.znear, view.zfar, view.halfX, view.halfY, threads);
    frame_.ortho = view.orthographic;
  }

  void setFrame(int width, int height, double znear, double zfar, double tanX, double tanY,
                int threads) {
    if (width > kMaxImageSize || height > kMaxImageSize)
      throw Error("image size is limited to " + std::to_string(kMaxImageSize) + " per side, got " +
                  std::to_string(width) + "x" + std::to_string(height));
    frame_.width = width;
    frame_.height = height;
    frame_.tilesX = (width + kTileSize - 1) / kTileSize;
    frame_.tilesY = (height + kTileSize - 1) / kTileSize;
    frame_.znear = znear;
    frame_.zfar = zfar;
    frame_.tanX = tanX;
    frame_.tanY = tanY;
    frame_.guardX = 1.0 + 2.0 * kGuardBandPixels / width;
    frame_.guardY = 1.0 + 2.0 * kGuardBandPixels / height;
    workers_ = threads > 0 ? threads : int(std::max(1u, std::thread::hardware_concurrency()));
    workers_ = std::min(workers_, kMaxWorkers);
  }

  // The nearest depth per pixel into `target` (rows of `stride` floats), `clear` where none.
  void runDepth(float* target, size_t stride, float clear) {
    // No vertex pass: a face draws few of the scene's triangles (those its frustum touches), and
    // many small faces would each pay for every vertex (viewPositionOf transforms per use).
    size_t triangles = triangles_->size();
    int ranges = triangles < 1024 ? 1 : workers_;
    outputs_.assign(size_t(ranges), WorkerOutput{});
    parallelRanges(triangles, ranges, [&](size_t b, size_t e, int k) { setup(b, e, outputs_[k]); });
    parallelItems(frame_.tilesX * frame_.tilesY, workers_,
                  [&](int tile, int) { depthTile(tile, target, stride, clear); });
  }

  GBuffer run() {
    transformVertices();
    size_t triangles = scene_.triangleCount();
    // Enough ranges to balance, few enough that the per-range bins stay cheap.
    int ranges = triangles < 1024 ? 1 : workers_;
    outputs_.assign(size_t(ranges), WorkerOutput{});
    parallelRanges(triangles, ranges, [&](size_t b, size_t e, int k) { setup(b, e, outputs_[k]); });

    GBuffer g;
    g.resize(frame_.width, frame_.height);
    g.model = options_.model;
    if (options_.triangleIds) g.triangleId.assign(g.pixelCount(), -1);
    if (options_.fragmentCounts) g.fragmentCount.assign(g.pixelCount(), 0u);
    int tiles = frame_.tilesX * frame_.tilesY;
    std::vector<TileScratch> scratch(size_t(std::max(1, workers_)));
    parallelItems(tiles, workers_, [&](int tile, int k) { renderTile(tile, scratch[k], g); });
    return g;
  }

 private:
  struct TileScratch {
    double invDepth[kTileSize * kTileSize];  // 1 / linear depth of the nearest fragment, 0 = none
    uint32_t triangle[kTileSize * kTileSize];
    uint32_t worker[kTileSize * kTileSize];
    uint32_t sub[kTileSize * kTileSize];
    uint32_t fragments[kTileSize * kTileSize];
  };

  void transformVertices() {
    const glm::dmat4 view(view_);
    const glm::mat3 normalMatrix(glm::transpose(glm::inverse(glm::dmat3(view))));
    size_t n = scene_.vertices.size();
    viewPosition_.reserve(n);
    viewNormal_.reserve(n);
    plane_alloc::adviseHugePages(viewPosition_.data(), n * sizeof(glm::dvec3));
    plane_alloc::adviseHugePages(viewNormal_.data(), n * sizeof(glm::vec3));
    viewPosition_.resize(n);
    viewNormal_.resize(n);
    // Tangents only for a scene with normal maps that are applied (a scene without pays nothing).
    const glm::mat3 rotation{
        glm::dmat3(view)};  // tangents lie in the surface: not the normal matrix
    if (normalMaps_) viewTangent_.resize(n);
    parallelRanges(n, n < 4096 ? 1 : workers_, [&](size_t b, size_t e, int) {
      for (size_t i = b; i < e; ++i) {
        const Vertex& v = scene_.vertices[i];
        viewPosition_[i] = glm::dvec3(view * glm::dvec4(glm::dvec3(v.position), 1.0));
        glm::vec3 nv = normalMatrix * v.normal;
        float len2 = glm::dot(nv, nv);
        viewNormal_[i] = len2 > 0.0f ? nv / std::sqrt(len2) : glm::vec3(0.0f);
        if (normalMaps_) {
          const glm::vec4& t = scene_.tangents[i];
          viewTangent_[i] = glm::vec4(rotation * glm::vec3(t), t.w);
        }
      }
    });
  }

  // A vertex in view space: from the vertex pass, or computed now (depth only), the same way.
  glm::dvec3 viewPositionOf(uint32_t i) const {
    if (!depthOnly_) return viewPosition_[i];
    return glm::dvec3(view_ * glm::dvec4(glm::dvec3(scene_.vertices[i].position), 1.0));
  }

  ClipVertex toClip(const glm::dvec3& p, int corner) const {
    ClipVertex c{p.x / frame_.tanX, p.y / frame_.tanY, frame_.ortho ? 1.0 : -p.z, {0.0, 0.0, 0.0}};
    c.b[corner] = 1.0;
    return c;
  }

  // Clips `poly` (n vertices) against plane dist(v) >= 0; returns the new vertex count. The
  // intersection point is computed from the (inside, outside) pair, independent of edge direction.
  template <typename Dist>
  static int clipPolygon(const ClipVertex* poly, int n, ClipVertex* out, Dist dist) {
    double d[9];
    for (int i = 0; i < n; ++i) d[i] = dist(poly[i]);
    int m = 0;
    for (int i = 0; i < n; ++i) {
      int j = i + 1 == n ? 0 : i + 1;
      bool inI = d[i] >= 0.0, inJ = d[j] >= 0.0;
      if (inI) out[m++] = poly[i];
      if (inI != inJ) {
        const ClipVertex& a = inI ? poly[i] : poly[j];
        const ClipVertex& o = inI ? poly[j] : poly[i];
        double da = inI ? d[i] : d[j], dO = inI ? d[j] : d[i];
        double t = da / (da - dO);
        ClipVertex& r = out[m++];
        r.x = a.x + t * (o.x - a.x);
        r.y = a.y + t * (o.y - a.y);
        r.w = a.w + t * (o.w - a.w);
        for (int k = 0; k < 3; ++k) r.b[k] = a.b[k] + t * (o.b[k] - a.b[k]);
      }
    }
    return m;
  }

  void setup(size_t begin, size_t end, WorkerOutput& out) {
    out.bins.assign(size_t(frame_.tilesX) * frame_.tilesY, {});
    // Most triangles give at most one sub-triangle; clipped ones may give more (rare).
    out.setups.reserve(end - begin);
    out.subs.reserve(end - begin);
    out.fallbacks.reserve(end - begin);
    plane_alloc::adviseHugePages(out.setups.data(), out.setups.capacity() * sizeof(TriangleSetup));
    plane_alloc::adviseHugePages(out.subs.data(), out.subs.capacity() * sizeof(SubTriangle));
    plane_alloc::adviseHugePages(out.fallbacks.data(),
                                 out.fallbacks.capacity() * sizeof(SubFallback));
    const double zn = frame_.znear, zf = frame_.zfar;
    const double gx = frame_.guardX, gy = frame_.guardY;
    for (size_t item = begin; item < end; ++item) {
      const size_t tri = triangles_ ? size_t((*triangles_)[item]) : item;
      const glm::dvec3 p0 = viewPositionOf(scene_.indices[3 * tri]);
      const glm::dvec3 p1 = viewPositionOf(scene_.indices[3 * tri + 1]);
      const glm::dvec3 p2 = viewPositionOf(scene_.indices[3 * tri + 2]);
      ClipVertex v[3] = {toClip(p0, 0), toClip(p1, 1), toClip(p2, 2)};

      bool finite = true;
      for (const auto& c : v)
        finite = finite && std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.w);
      if (!finite) continue;
      auto allOutside = [&](auto outside) {
        return outside(v[0]) && outside(v[1]) && outside(v[2]);
      };
      // Linear depth -Z: clip w, except in orthographic views (w = 1 there).
      const double d0 = -p0.z, d1 = -p1.z, d2 = -p2.z;
      if ((d0 < zn && d1 < zn && d2 < zn) || (d0 > zf && d1 > zf && d2 > zf) ||
          allOutside([&](const ClipVertex& c) { return c.x > c.w; }) ||
          allOutside([&](const ClipVertex& c) { return c.x < -c.w; }) ||
          allOutside([&](const ClipVertex& c) { return c.y > c.w; }) ||
          allOutside([&](const ClipVertex& c) { return c.y < -c.w; }))
        continue;

      // Clip: near plane, then the guard band where needed.
      ClipVertex bufA[9], bufB[9];
      ClipVertex* poly = v;
      int n = 3;
      auto clipIf = [&](auto dist) {
        bool need = false;
        for (int i = 0; i < n; ++i) need = need || dist(poly[i]) < 0.0;
        if (!need) return;
        ClipVertex* dst = poly == bufA ? bufB : bufA;
        n = clipPolygon(poly, n, dst, dist);
        poly = dst;
      };
      // Orthographic views need no near clip (w = 1): depth is tested per pixel.
      if (!frame_.ortho) clipIf([&](const ClipVertex& c) { return c.w - zn; });
      clipIf([&](const ClipVertex& c) { return gx * c.w - c.x; });
      clipIf([&](const ClipVertex& c) { return gx * c.w + c.x; });
      clipIf([&](const ClipVertex& c) { return gy * c.w - c.y; });
      clipIf([&](const ClipVertex& c) { return gy * c.w + c.y; });
      if (n < 3) continue;

      // Snap to fixed point: sx = (x/w + 1) W/2, sy = (1 - y/w) H/2 (row 0 = top).
      int64_t fx[9], fy[9];
      for (int i = 0; i < n; ++i) {
        double sx = (poly[i].x / poly[i].w + 1.0) * 0.5 * frame_.width;
        double sy = (1.0 - poly[i].y / poly[i].w) * 0.5 * frame_.height;
        fx[i] = roundToInt(sx * double(kSubOne));
        fy[i] = roundToInt(sy * double(kSubOne));
      }

      uint32_t setupIndex = uint32_t(out.setups.size());
      bool emitted = false;
      for (int k = 1; k + 1 < n; ++k) {
        int idx[3] = {0, k, k + 1};
        if (emitSub(poly, fx, fy, idx, uint32_t(tri), setupIndex, out)) emitted = true;
      }
      if (emitted) out.setups.push_back(makeSetup(v, p0, p1, p2, uint32_t(tri)));
    }
  }

  TriangleSetup makeSetup(const ClipVertex* v, const glm::dvec3& p0, const glm::dvec3& p1,
                          const glm::dvec3& p2, uint32_t tri) const {
    TriangleSetup t{};
    t.triangle = tri;
    glm::dvec3 c0(v[0].x, v[0].y, v[0].w), c1(v[1].x, v[1].y, v[1].w), c2(v[2].x, v[2].y, v[2].w);
    glm::dvec3 r0 = glm::cross(c1, c2), r1 = glm::cross(c2, c0), r2 = glm::cross(c0, c1);
    double det = glm::dot(c0, r0);
    double scale = glm::length(c0) * glm::length(c1) * glm::length(c2);
    t.homogeneous = std::isfinite(det) && std::abs(det) > 1e-12 * scale;
    if (t.homogeneous) {
      // Rows of M^-1 are r_i / det; u = 2 px / W - 1, v = 1 - 2 py / H.
      const glm::dvec3 rows[3] = {r0 / det, r1 / det, r2 / det};
      double sxu = 2.0 / frame_.width, syv = -2.0 / frame_.height;
      for (int i = 0; i < 3; ++i) {
        t.f[i][0] = rows[i].x * sxu;
        t.f[i][1] = rows[i].y * syv;
        t.f[i][2] = rows[i].z - rows[i].x + rows[i].y;
      }
    }
    // Geometric normal (counter-clockwise front) pointing away from the eye at the origin.
    t.backFacing = glm::dot(glm::cross(p1 - p0, p2 - p0), p0) > 0.0;
    return t;
  }

  bool emitSub(const ClipVertex* poly, const int64_t* fx, const int64_t* fy, int idx[3],
               uint32_t tri, uint32_t setupIndex, WorkerOutput& out) const {
    int64_t ax = fx[idx[0]], ay = fy[idx[0]];
    int64_t bx = fx[idx[1]], by = fy[idx[1]];
    int64_t cx = fx[idx[2]], cy = fy[idx[2]];
    int64_t area = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
    if (area == 0) return false;
    if (area < 0) {  // make the interior the positive side of every edge
      std::swap(idx[1], idx[2]);
      std::swap(bx, cx);
      std::swap(by, cy);
    }
    const int64_t X[3] = {ax, bx, cx}, Y[3] = {ay, by, cy};

    int64_t minX = std::min({ax, bx, cx}), maxX = std::max({ax, bx, cx});
    int64_t minY = std::min({ay, by, cy}), maxY = std::max({ay, by, cy});
    // Pixels whose centres (x * 256 + 128) lie in the bounding box, clamped to the screen.
    int64_t px0 = std::max<int64_t>(0, floorDiv(minX - kSubHalf + kSubOne - 1, kSubOne));
    int64_t px1 = std::min<int64_t>(frame_.width - 1, floorDiv(maxX - kSubHalf, kSubOne));
    int64_t py0 = std::max<int64_t>(0, floorDiv(minY - kSubHalf + kSubOne - 1, kSubOne));
    int64_t py1 = std::min<int64_t>(frame_.height - 1, floorDiv(maxY - kSubHalf, kSubOne));
    if (px0 > px1 || py0 > py1) return false;

    SubTriangle s;
    s.bias = 0;
    for (int i = 0; i < 3; ++i) {  // edge i runs from vertex i+1 to vertex i+2 (opposite i)
      int j = (i + 1) % 3, k = (i + 2) % 3;
      int64_t dx = X[k] - X[j], dy = Y[k] - Y[j];
      bool topLeft = dy < 0 || (dy == 0 && dx > 0);
      s.ea[i] = -dy;
      s.eb[i] = dx;
      s.ec[i] = dy * X[j] - dx * Y[j] - (topLeft ? 0 : 1);
      if (!topLeft) s.bias |= uint8_t(1u << i);
    }
    s.x0 = int32_t(px0);
    s.x1 = int32_t(px1);
    s.y0 = int32_t(py0);
    s.y1 = int32_t(py1);
    s.setup = setupIndex;
    s.triangle = tri;

    SubFallback fb;
    for (int i = 0; i < 3; ++i) {
      const ClipVertex& c = poly[idx[i]];
      fb.invW[i] = 1.0 / c.w;
      for (int k = 0; k < 3; ++k) fb.b[i][k] = c.b[k];
    }

    uint32_t subIndex = uint32_t(out.subs.size());
    out.subs.push_back(s);
    out.fallbacks.push_back(fb);

    int tx0 = int(px0) / kTileSize, tx1 = int(px1) / kTileSize;
    int ty0 = int(py0) / kTileSize, ty1 = int(py1) / kTileSize;
    bool single = tx0 == tx1 && ty0 == ty1;
    for (int ty = ty0; ty <= ty1; ++ty)
      for (int tx = tx0; tx <= tx1; ++tx) {
        if (!single && !touchesTile(s, tx, ty)) continue;
        out.bins[size_t(ty) * frame_.tilesX + tx].push_back(subIndex);
      }
    return true;
  }

  // False when some edge is negative at every pixel centre of the tile (its most positive corner).
  bool touchesTile(const SubTriangle& s, int tx, int ty) const {
    int64_t x0 = int64_t(tx) * kTileSize, y0 = int64_t(ty) * kTileSize;
    int64_t x1 = std::min<int64_t>(x0 + kTileSize, frame_.width) - 1;
    int64_t y1 = std::min<int64_t>(y0 + kTileSize, frame_.height) - 1;
    for (int i = 0; i < 3; ++i) {
      int64_t X = (s.ea[i] >= 0 ? x1 : x0) * kSubOne + kSubHalf;
      int64_t Y = (s.eb[i] >= 0 ? y1 : y0) * kSubOne + kSubHalf;
      if (s.ea[i] * X + s.eb[i] * Y + s.ec[i] < 0) return false;
    }
    return true;
  }

  void renderTile(int tile, TileScratch& sc, GBuffer& g) const {
    int tx = tile % frame_.tilesX, ty = tile / frame_.tilesX;
    int x0 = tx * kTileSize, y0 = ty * kTileSize;
    int x1 = std::min(x0 + kTileSize, frame_.width) - 1;
    int y1 = std::min(y0 + kTileSize, frame_.height) - 1;
    int tw = x1 - x0 + 1, th = y1 - y0 + 1;
    for (int i = 0; i < tw * th; ++i) {
      sc.invDepth[i] = 0.0;
      sc.triangle[i] = kNone;
      sc.fragments[i] = 0;
    }
    const bool count = options_.fragmentCounts;
    for (size_t k = 0; k < outputs_.size(); ++k) {
      const WorkerOutput& w = outputs_[k];
      for (uint32_t si : w.bins[size_t(tile)]) {
        if (count) visibility<true>(w, si, uint32_t(k), x0, y0, x1, y1, tw, sc);
        else visibility<false>(w, si, uint32_t(k), x0, y0, x1, y1, tw, sc);
      }
    }
    resolve(x0, y0, tw, th, sc, g);
  }

  template <bool kCount>
  void visibility(const WorkerOutput& w, uint32_t si, uint32_t worker, int x0, int y0, int x1,
                  int y1, int tw, TileScratch& sc) const {
    const SubTriangle& s = w.subs[si];
    const TriangleSetup& t = w.setups[s.setup];
    const SubFallback& fb = w.fallbacks[si];
    int bx0 = std::max(x0, int(s.x0)), bx1 = std::min(x1, int(s.x1));
    int by0 = std::max(y0, int(s.y0)), by1 = std::min(y1, int(s.y1));
    if (bx0 > bx1 || by0 > by1) return;
    const double invFar = 1.0 / frame_.zfar;
    // alphaMode MASK: a fragment that would win is first alpha-tested (ts_material_covered, the
    // one test the OpenGL shaders' discard uses); one that fails leaves what lies behind.
    const Material& material = materialOf(s.triangle);
    const bool masked = material.alphaMode == AlphaMode::Mask;
    const int64_t step0 = s.ea[0] * kSubOne, step1 = s.ea[1] * kSubOne, step2 = s.ea[2] * kSubOne;
    const int64_t bias[3] = {int64_t(s.bias & 1), int64_t((s.bias >> 1) & 1),
                             int64_t((s.bias >> 2) & 1)};
    const int64_t cx0 = int64_t(bx0) * kSubOne + kSubHalf;
    for (int y = by0; y <= by1; ++y) {
      const int64_t cy = int64_t(y) * kSubOne + kSubHalf;
      int64_t e0 = s.ea[0] * cx0 + s.eb[0] * cy + s.ec[0];
      int64_t e1 = s.ea[1] * cx0 + s.eb[1] * cy + s.ec[1];
      int64_t e2 = s.ea[2] * cx0 + s.eb[2] * cy + s.ec[2];
      const int row = (y - y0) * tw - x0;
      for (int x = bx0; x <= bx1; ++x, e0 += step0, e1 += step1, e2 += step2) {
        if ((e0 | e1 | e2) < 0) continue;
        const int p = row + x;
        if (kCount) ++sc.fragments[p];
        const int64_t e[3] = {e0 + bias[0], e1 + bias[1], e2 + bias[2]};
        const double inv = evaluate<false>(t, fb, x + 0.5, y + 0.5, e, nullptr);
        if (!(inv >= invFar)) continue;  // beyond the far plane
        // Nearer (larger 1/depth) wins; equal depth -> lower triangle index.
        if (inv > sc.invDepth[p] || (inv == sc.invDepth[p] && s.triangle < sc.triangle[p])) {
          if (masked && !covered(material, t, fb, x, y, e)) continue;
          sc.invDepth[p] = inv;
          sc.triangle[p] = s.triangle;
          sc.worker[p] = worker;
          sc.sub[p] = si;
        }
      }
    }
  }

  // rasterizeDepth's tile: the nearest depth per pixel (which triangle does not matter, so no
  // tie-break is needed for the same output on any thread count).
  void depthTile(int tile, float* target, size_t stride, float clear) const {
    const int tx = tile % frame_.tilesX, ty = tile / frame_.tilesX;
    const int x0 = tx * kTileSize, y0 = ty * kTileSize;
    const int x1 = std::min(x0 + kTileSize, frame_.width) - 1;
    const int y1 = std::min(y0 + kTileSize, frame_.height) - 1;
    const int tw = x1 - x0 + 1, th = y1 - y0 + 1;
    // Perspective: 1 / depth (larger is nearer, 0 none); orthographic: depth (inf none).
    double best[kTileSize * kTileSize];
    const bool ortho = frame_.ortho;
    std::fill(best, best + tw * th, ortho ? std::numeric_limits<double>::infinity() : 0.0);
    const double invFar = 1.0 / frame_.zfar, zn = frame_.znear, zf = frame_.zfar;
    for (const WorkerOutput& w : outputs_)
      for (uint32_t si : w.bins[size_t(tile)]) {
        const SubTriangle& s = w.subs[si];
        const TriangleSetup& t = w.setups[s.setup];
        const SubFallback& fb = w.fallbacks[si];
        const int bx0 = std::max(x0, int(s.x0)), bx1 = std::min(x1, int(s.x1));
        const int by0 = std::max(y0, int(s.y0)), by1 = std::min(y1, int(s.y1));
        // alphaMode MASK: only a fragment that would be nearer is alpha-tested, at the
        // barycentrics and UV the G-buffer's test uses (affine in orthographic views: w = 1), so
        // the map holds the nearest covered fragment whatever the order; opaque ones skip it.
        const Material& material = materialOf(t.triangle);
        const bool masked = material.alphaMode == AlphaMode::Mask;
        if (material.alphaMode == AlphaMode::Blend) continue;  // composited glass casts none
        double vd[3] = {0.0, 0.0, 0.0};  // the vertices' depths (orthographic)
        if (ortho)
          for (int k = 0; k < 3; ++k) vd[k] = -viewPositionOf(scene_.indices[3 * t.triangle + k]).z;
        for (int y = by0; y <= by1; ++y) {
          const int64_t cy = int64_t(y) * kSubOne + kSubHalf;
          for (int x = bx0; x <= bx1; ++x) {
            const int64_t cx = int64_t(x) * kSubOne + kSubHalf;
            int64_t e[3];
            for (int i = 0; i < 3; ++i) e[i] = s.ea[i] * cx + s.eb[i] * cy + s.ec[i];
            if ((e[0] | e[1] | e[2]) < 0) continue;
            for (int i = 0; i < 3; ++i) e[i] += int64_t((s.bias >> i) & 1);
            const int p = (y - y0) * tw + (x - x0);
            if (ortho) {
              double B[3];
              evaluate<true>(t, fb, x + 0.5, y + 0.5, e, B);
              const double depth = B[0] * vd[0] + B[1] * vd[1] + B[2] * vd[2];
              if (depth >= zn && depth <= zf && depth < best[p] &&
                  (!masked || covered(material, t, fb, x, y, e)))
                best[p] = depth;
            } else {
              const double inv = evaluate<false>(t, fb, x + 0.5, y + 0.5, e, nullptr);
              if (inv >= invFar && inv > best[p] && (!masked || covered(material, t, fb, x, y, e)))
                best[p] = inv;
            }
          }
        }
      }
    for (int ly = 0; ly < th; ++ly)
      for (int lx = 0; lx < tw; ++lx) {
        const double b = best[ly * tw + lx];
        const bool none = ortho ? !(b < std::numeric_limits<double>::infinity()) : !(b > 0.0);
        target[size_t(y0 + ly) * stride + size_t(x0 + lx)] =
            none ? clear : float(ortho ? b : 1.0 / b);
      }
  }

  const Material& materialOf(uint32_t tri) const {
    static const Material kDefaultMaterial;
    return scene_.triangleMaterial.empty()
               ? (scene_.materials.empty() ? kDefaultMaterial : scene_.materials[0])
               : scene_.materials[scene_.triangleMaterial[tri]];
  }

  // The pixel's interpolated UV (one set per vertex) at barycentrics B of triangle tri.
  glm::vec2 uvAt(uint32_t tri, const double B[3]) const {
    const Vertex& v0 = scene_.vertices[scene_.indices[3 * tri]];
    const Vertex& v1 = scene_.vertices[scene_.indices[3 * tri + 1]];
    const Vertex& v2 = scene_.vertices[scene_.indices[3 * tri + 2]];
    return glm::vec2(B[0] * glm::dvec2(v0.uv) + B[1] * glm::dvec2(v1.uv) +
                     B[2] * glm::dvec2(v2.uv));
  }

  // The material's texture in `slot` at uv (1 without one), as ts_material_planes samples it.
  glm::vec4 sampleSlot(const Material& m, int slot, glm::vec2 uv) const {
    const int texture = materialTexture(m, slot);
    if (texture < 0) return glm::vec4(1.0f);
    return scene_.textures[size_t(texture)].sample(uv);
  }

  // The alpha test of a fragment at pixel (x, y) with edge values e, at the barycentrics and UV
  // that resolve() would interpolate there.
  bool covered(const Material& m, const TriangleSetup& t, const SubFallback& fb, int x, int y,
               const int64_t e[3]) const {
    double B[3];
    evaluate<true>(t, fb, x + 0.5, y + 0.5, e, B);
    const glm::vec2 uv = uvAt(t.triangle, B);
    return ts_material_covered(m, [&](int slot) { return sampleSlot(m, slot, uv); });
  }

  void resolve(int x0, int y0, int tw, int th, const TileScratch& sc, GBuffer& g) const {
    for (int ly = 0; ly < th; ++ly)
      for (int lx = 0; lx < tw; ++lx) {
        int p = ly * tw + lx;
        int x = x0 + lx, y = y0 + ly;
        size_t gi = size_t(y) * size_t(frame_.width) + size_t(x);
        if (!g.fragmentCount.empty()) g.fragmentCount[gi] = sc.fragments[p];
        if (sc.triangle[p] == kNone) continue;
        const WorkerOutput& w = outputs_[sc.worker[p]];
        const SubTriangle& s = w.subs[sc.sub[p]];
        const TriangleSetup& t = w.setups[s.setup];
        const int64_t cx = int64_t(x) * kSubOne + kSubHalf, cy = int64_t(y) * kSubOne + kSubHalf;
        int64_t e[3];
        for (int i = 0; i < 3; ++i)
          e[i] = s.ea[i] * cx + s.eb[i] * cy + s.ec[i] + int64_t((s.bias >> i) & 1);
        double B[3];
        evaluate<true>(t, w.fallbacks[sc.sub[p]], x + 0.5, y + 0.5, e, B);

        const uint32_t tri = t.triangle;
        const uint32_t i0 = scene_.indices[3 * tri], i1 = scene_.indices[3 * tri + 1],
                       i2 = scene_.indices[3 * tri + 2];
        const Material& m = materialOf(tri);

        glm::dvec3 n = B[0] * glm::dvec3(viewNormal_[i0]) + B[1] * glm::dvec3(viewNormal_[i1]) +
                       B[2] * glm::dvec3(viewNormal_[i2]);
        double len2 = glm::dot(n, n);
        if (len2 > 1e-24) {
          n /= std::sqrt(len2);
        } else {
          const glm::dvec3 &p0 = viewPosition_[i0], &p1 = viewPosition_[i1],
                           &p2 = viewPosition_[i2];
          glm::dvec3 gn = glm::cross(p1 - p0, p2 - p0);
          double gl = glm::length(gn);
          n = gl > 0.0 ? gn / gl : glm::dvec3(0.0, 0.0, 1.0);
        }

        // Textures are sampled at the pixel's interpolated UV (one set per vertex), only those
        // the model reads (shaders/material_planes.h, shared with the OpenGL rasterizer).
        auto sample = [&](int slot) { return sampleSlot(m, slot, uvAt(tri, B)); };
        const TsMaterialPlanes planes =
            ts_material_planes(options_.model == ShadingModel::MetallicRoughness, m, sample);

        glm::vec3 normal(n);
        if (normalMaps_ && m.normalTexture >= 0) {
          const glm::vec4 tangent =
              glm::vec4(B[0] * glm::dvec4(viewTangent_[i0]) + B[1] * glm::dvec4(viewTangent_[i1]) +
                        B[2] * glm::dvec4(viewTangent_[i2]));
          const glm::vec4 texel = scene_.textures[size_t(m.normalTexture)].sample(uvAt(tri, B));
          normal = ts_normal_mapped(normal, tangent, glm::vec3(texel), m.normalScale);
        }
        if (m.doubleSided && t.backFacing) normal = -normal;

        g.depth[gi] = float(1.0 / sc.invDepth[p]);
        g.normal[gi] = glm::vec4(normal, 0.0f);
        g.diffuse[gi] = planes.diffuse;
        g.specular[gi] = planes.specular;
        g.emissive[gi] = planes.emissive;
        if (!g.triangleId.empty()) g.triangleId[gi] = int32_t(tri);
      }
  }

  const Scene& scene_;
  glm::dmat4 view_;
  const std::vector<uint32_t>* triangles_ = nullptr;  // rasterizeDepth's; null: every triangle
  bool depthOnly_ = false;  // rasterizeDepth: no vertex pass, no attributes
  RasterOptions options_;
  Frame frame_{};
  int workers_ = 1;
  std::vector<glm::dvec3> viewPosition_;
  std::vector<glm::vec3> viewNormal_;
  std::vector<glm::vec4> viewTangent_;  // xyz view space, w the bitangent's sign; normalMaps_ only
  bool normalMaps_ = false;             // the scene's normal maps are applied
  std::vector<WorkerOutput> outputs_;
};

}  // namespace

GBuffer rasterize(const Scene& scene, const SceneCamera& camera, int width, int height,
                  const RasterOptions& options) {
  return Rasterizer(scene, camera, width, height, options).run();
}

void rasterizeDepth(const Scene& scene, const DepthView& view,
                    const std::vector<uint32_t>& triangles, int width, int height, float* target,
                    size_t rowStride, float clear, int threads) {
  if (width < 1 || height < 1) return;
  Rasterizer(scene, view, triangles, width, height, threads).runDepth(target, rowStride, clear);
}

}  // namespace ts
