// The software rasterizer (src/raster/rasterizer.cpp): fill rule, depth, perspective-correct
// interpolation, near-plane clipping, determinism across thread counts, odd resolutions.
// Scenes are built by hand with the camera at the origin looking down -Z (view = world), so
// screen positions can be placed exactly with unproject().
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <set>

#include <glm/gtc/matrix_transform.hpp>

#include "raster/rasterizer.h"
#include "scene/scene_loader.h"
#include "util/error.h"
#include "random_draws.h"

namespace {

using ts::CameraIntrinsics;
using ts::GBuffer;
using ts::RasterOptions;
using ts::Scene;
using ts::SceneCamera;

constexpr float kYfov = 1.5707963f;  // 90 degrees

SceneCamera identityCamera(float znear = 0.1f, float zfar = 1000.0f) {
  SceneCamera c;
  c.viewFromWorld = glm::mat4(1.0f);
  c.yfov = kYfov;
  c.znear = znear;
  c.zfar = zfar;
  return c;
}

// View-space point at linear depth d whose projection is the screen position (sx, sy) in pixels
// (pixel centres at +0.5, y down).
glm::vec3 unproject(const CameraIntrinsics& in, double sx, double sy, double d) {
  double ndcX = 2.0 * sx / in.width - 1.0, ndcY = 1.0 - 2.0 * sy / in.height;
  return glm::vec3(glm::dvec3(ndcX * in.tanHalfFovX * d, ndcY * in.tanHalfFovY * d, -d));
}

// View ray direction through the centre of pixel (x, y), with z = -1.
glm::dvec3 pixelRay(const CameraIntrinsics& in, int x, int y) {
  double ndcX = 2.0 * (x + 0.5) / in.width - 1.0, ndcY = 1.0 - 2.0 * (y + 0.5) / in.height;
  return {ndcX * in.tanHalfFovX, ndcY * in.tanHalfFovY, -1.0};
}

uint32_t addMaterial(Scene& s, glm::vec3 diffuse, bool doubleSided = false) {
  ts::Material m;
  m.name = "m" + std::to_string(s.materials.size());
  m.diffuse = diffuse;
  m.doubleSided = doubleSided;
  s.materials.push_back(m);
  return uint32_t(s.materials.size() - 1);
}

void addTriangle(Scene& s, glm::vec3 a, glm::vec3 b, glm::vec3 c, uint32_t material,
                 glm::vec2 ta = {}, glm::vec2 tb = {}, glm::vec2 tc = {}) {
  glm::vec3 n = glm::normalize(glm::cross(b - a, c - a));
  uint32_t base = uint32_t(s.vertices.size());
  s.vertices.push_back({a, n, ta});
  s.vertices.push_back({b, n, tb});
  s.vertices.push_back({c, n, tc});
  s.indices.insert(s.indices.end(), {base, base + 1, base + 2});
  s.triangleMaterial.push_back(material);
}

// Counter-clockwise (as seen from the camera) quad a-b-c-d split along a-c.
void addQuad(Scene& s, glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d, uint32_t m0,
             uint32_t m1) {
  addTriangle(s, a, b, c, m0);
  addTriangle(s, a, c, d, m1);
}

RasterOptions instrumented(int threads = 2) {
  RasterOptions o;
  o.threads = threads;
  o.triangleIds = true;
  o.fragmentCounts = true;
  return o;
}

TEST(RasterCamera, IntrinsicsAndProjectionAgreeWithTheDefinitions) {
  SceneCamera cam = identityCamera(0.25f, 300.0f);
  cam.yfov = 0.9f;
  CameraIntrinsics in = CameraIntrinsics::from(cam, 160, 90);
  EXPECT_FLOAT_EQ(in.tanHalfFovY, std::tan(0.45f));
  EXPECT_FLOAT_EQ(in.tanHalfFovX, std::tan(0.45f) * 160.0f / 90.0f);
  glm::mat4 gl = glm::perspective(0.9f, 160.0f / 90.0f, 0.25f, 300.0f);
  glm::mat4 p = in.projection();
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) EXPECT_NEAR(p[c][r], gl[c][r], 1e-5f * (1 + std::abs(gl[c][r])));
  glm::vec4 clip = p * glm::vec4(1.0f, -0.5f, -4.0f, 1.0f);
  EXPECT_NEAR(clip.x / clip.w, 1.0 / (4.0 * in.tanHalfFovX), 1e-6);
  EXPECT_NEAR(clip.y / clip.w, -0.5 / (4.0 * in.tanHalfFovY), 1e-6);
  EXPECT_NEAR(clip.z / clip.w, 1.0, 1.0);  // in [-1, 1]
  EXPECT_EQ(in.kernelCamera(), glm::vec4(in.tanHalfFovX, in.tanHalfFovY, 160.0f, 90.0f));
  EXPECT_THROW(CameraIntrinsics::from(cam, 0, 10), ts::Error);
  cam.znear = 0.0f;
  EXPECT_THROW(CameraIntrinsics::from(cam, 10, 10), ts::Error);
}

TEST(RasterFillRule, RectangleOnPixelCentresIncludesTopLeftExcludesBottomRight) {
  const int W = 64, H = 48;
  SceneCamera cam = identityCamera();
  CameraIntrinsics in = CameraIntrinsics::from(cam, W, H);
  Scene s;
  uint32_t m = addMaterial(s, glm::vec3(1.0f));
  // Corners on pixel centres: x from 10.5 to 30.5, y from 5.5 to 25.5, so every border pixel
  // centre lies exactly on an edge: the top row and left column are in, bottom and right out.
  const double d = 5.0;
  glm::vec3 tl = unproject(in, 10.5, 5.5, d), tr = unproject(in, 30.5, 5.5, d);
  glm::vec3 br = unproject(in, 30.5, 25.5, d), bl = unproject(in, 10.5, 25.5, d);
  addQuad(s, tl, bl, br, tr, m, m);  // counter-clockwise on screen (y up in view space)
  GBuffer g = ts::rasterize(s, cam, W, H, instrumented());
  size_t covered = 0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      bool inside = x >= 10 && x < 30 && y >= 5 && y < 25;
      size_t i = size_t(y) * W + x;
      ASSERT_EQ(g.fragmentCount[i], inside ? 1u : 0u) << x << "," << y;
      EXPECT_EQ(g.depth[i] > 0.0f, inside) << x << "," << y;
      covered += inside;
    }
  EXPECT_EQ(covered, 400u);
  EXPECT_EQ(g.geometryPixels(), 400u);
}

TEST(RasterFillRule, SharedEdgesThroughPixelCentresCoverEachPixelOnce) {
  const int W = 64, H = 64;
  SceneCamera cam = identityCamera();
  CameraIntrinsics in = CameraIntrinsics::from(cam, W, H);
  Scene s;
  uint32_t red = addMaterial(s, {1, 0, 0}), green = addMaterial(s, {0, 1, 0});
  const double d = 3.0;
  // Square split along the diagonal through the pixel centres (k + 0.5, k + 0.5).
  addQuad(s, unproject(in, 4.5, 4.5, d), unproject(in, 4.5, 36.5, d), unproject(in, 36.5, 36.5, d),
          unproject(in, 36.5, 4.5, d), red, green);
  // Two triangles sharing the vertical edge x = 50.5 (through pixel centres), plus one sharing the
  // steep edge with another slope.
  glm::vec3 top = unproject(in, 50.5, 2.5, d), bottom = unproject(in, 50.5, 60.5, d);
  addTriangle(s, top, unproject(in, 40.25, 40.0, d), bottom, red);
  addTriangle(s, top, bottom, unproject(in, 62.75, 20.0, d), green);
  GBuffer g = ts::rasterize(s, cam, W, H, instrumented());
  int seen[2] = {0, 0};
  int diagonal = 0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      size_t i = size_t(y) * W + x;
      ASSERT_LE(g.fragmentCount[i], 1u) << "double coverage at " << x << "," << y;
      if (g.depth[i] > 0) ++seen[g.diffuse[i].x > 0.5f ? 0 : 1];
      bool inSquare = x >= 4 && x < 36 && y >= 4 && y < 36;
      if (inSquare) {
        ASSERT_EQ(g.fragmentCount[i], 1u) << "gap at " << x << "," << y;
        if (x == y) ++diagonal;
      }
      if (x == 50 && y >= 3 && y < 60) {
        ASSERT_EQ(g.fragmentCount[i], 1u) << "gap at " << x << "," << y;
      }
    }
  EXPECT_EQ(diagonal, 32);
  EXPECT_GT(seen[0], 0);
  EXPECT_GT(seen[1], 0);
}

TEST(RasterFillRule, FullScreenQuadAndRandomMeshCoverEveryPixelExactlyOnce) {
  for (auto [W, H] : {std::pair{97, 61}, std::pair{64, 64}, std::pair{130, 70}}) {
    SceneCamera cam = identityCamera();
    CameraIntrinsics in = CameraIntrinsics::from(cam, W, H);
    // Quad exactly on the screen corners, split along the diagonal.
    Scene quad;
    uint32_t a = addMaterial(quad, {1, 0, 0}), b = addMaterial(quad, {0, 1, 0});
    addQuad(quad, unproject(in, 0, 0, 2), unproject(in, 0, H, 2), unproject(in, W, H, 2),
            unproject(in, W, 0, 2), a, b);
    // A jittered grid mesh with shared vertices reaching beyond the screen, random diagonals and
    // random depths (jitter < 0.2 cell keeps every quad convex; vertices are shared, so edges are
    // shared exactly).
    Scene mesh;
    uint32_t mm = addMaterial(mesh, {1, 1, 1});
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> jitter(-0.2, 0.2), depth(2.0, 6.0);
    const int N = 9;
    for (int j = 0; j <= N; ++j)
      for (int i = 0; i <= N; ++i) {
        bool border = i == 0 || j == 0 || i == N || j == N;
        double sx = (i + (border ? 0.0 : jitter(rng))) * (W + 20.0) / N - 10.0;
        double sy = (j + (border ? 0.0 : jitter(rng))) * (H + 20.0) / N - 10.0;
        mesh.vertices.push_back({unproject(in, sx, sy, depth(rng)), {0, 0, 1}, {}});
      }
    for (int j = 0; j < N; ++j)
      for (int i = 0; i < N; ++i) {
        uint32_t v00 = uint32_t(j * (N + 1) + i), v10 = v00 + 1, v01 = v00 + N + 1, v11 = v01 + 1;
        if (rng() & 1) {
          mesh.indices.insert(mesh.indices.end(), {v00, v01, v11, v00, v11, v10});
        } else {
          mesh.indices.insert(mesh.indices.end(), {v00, v01, v10, v10, v01, v11});
        }
        mesh.triangleMaterial.insert(mesh.triangleMaterial.end(), {mm, mm});
      }
    for (const Scene* s : {&quad, &mesh}) {
      GBuffer g = ts::rasterize(*s, cam, W, H, instrumented(3));
      for (size_t i = 0; i < g.pixelCount(); ++i) {
        ASSERT_EQ(g.fragmentCount[i], 1u) << W << "x" << H << " pixel " << i;
        ASSERT_GT(g.depth[i], 0.0f);
        ASSERT_GE(g.triangleId[i], 0);
      }
    }
  }
}

TEST(RasterDepth, FrontoParallelPlaneHasItsDistanceEverywhere) {
  const int W = 80, H = 50;
  SceneCamera cam = identityCamera();
  CameraIntrinsics in = CameraIntrinsics::from(cam, W, H);
  Scene s;
  uint32_t m = addMaterial(s, glm::vec3(1.0f));
  const double d = 7.3;
  addQuad(s, unproject(in, -5, -5, d), unproject(in, -5, H + 5, d), unproject(in, W + 5, H + 5, d),
          unproject(in, W + 5, -5, d), m, m);
  GBuffer g = ts::rasterize(s, cam, W, H);
  for (size_t i = 0; i < g.pixelCount(); ++i) {
    ASSERT_NEAR(g.depth[i], d, 1e-5 * d);
    ASSERT_NEAR(g.normal[i].z, 1.0f, 1e-6f);
  }
}

TEST(RasterDepth, TiltedPlaneDepthIsTheRayPlaneIntersection) {
  const int W = 96, H = 64;
  SceneCamera cam = identityCamera();
  CameraIntrinsics in = CameraIntrinsics::from(cam, W, H);
  // Plane through (0, 0, -10) with normal n, tilted so depth varies >10x over the screen (every
  // pixel ray still meets it in front of the camera).
  const glm::dvec3 n = glm::normalize(glm::dvec3(0.25, 0.35, 0.9)), p0(0, 0, -10);
  // Corners: intersect the corner rays (a bit outside the screen) with the plane.
  auto onPlane = [&](double sx, double sy) {
    glm::dvec3 r(2.0 * sx / W - 1.0, 1.0 - 2.0 * sy / H, -1.0);
    r.x *= in.tanHalfFovX;
    r.y *= in.tanHalfFovY;
    return glm::vec3(r * (glm::dot(n, p0) / glm::dot(n, r)));
  };
  Scene s;
  uint32_t m = addMaterial(s, glm::vec3(1.0f));
  addQuad(s, onPlane(-3, -3), onPlane(-3, H + 3), onPlane(W + 3, H + 3), onPlane(W + 3, -3), m, m);
  GBuffer g = ts::rasterize(s, cam, W, H);
  double minD = 1e9, maxD = 0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      glm::dvec3 r = pixelRay(in, x, y);
      double expected = glm::dot(n, p0) / glm::dot(n, r);  // t with r.z = -1 -> depth = t
      double got = g.depth[size_t(y) * W + x];
      ASSERT_NEAR(got, expected, 2e-6 * expected) << x << "," << y;
      minD = std::min(minD, got);
      maxD = std::max(maxD, got);
    }
  EXPECT_GT(maxD / minD, 5.0);  // the plane really is tilted
}

TEST(RasterDepth, NearerTriangleWinsInEitherOrderAndTiesGoToTheLowerIndex) {
  const int W = 40, H = 40;
  SceneCamera cam = identityCamera();
  CameraIntrinsics in = CameraIntrinsics::from(cam, W, H);
  for (int order = 0; order < 2; ++order) {
    Scene s;
    uint32_t near = addMaterial(s, {1, 0, 0}), far = addMaterial(s, {0, 0, 1});
    auto addAt = [&](double d, uint32_t m) {
      addTriangle(s, unproject(in, 2, 2, d), unproject(in, 5, 38, d), unproject(in, 38, 20, d), m);
    };
    if (order == 0) {
      addAt(4.0, near);
      addAt(6.0, far);
    } else {
      addAt(6.0, far);
      addAt(4.0, near);
    }
    GBuffer g = ts::rasterize(s, cam, W, H, instrumented());
    size_t i = size_t(20) * W + 20;
    EXPECT_EQ(g.fragmentCount[i], 2u);
    EXPECT_EQ(g.diffuse[i], glm::vec4(1, 0, 0, 1));
    EXPECT_NEAR(g.depth[i], 4.0f, 1e-5f);
  }
  // Coincident triangles: the first one wins everywhere, whatever the thread count.
  Scene s;
  uint32_t first = addMaterial(s, {1, 0, 0}), second = addMaterial(s, {0, 1, 0});
  for (uint32_t m : {first, second})
    addTriangle(s, unproject(in, 0, 0, 5), unproject(in, 0, 40, 5), unproject(in, 40, 20, 5), m);
  for (int threads : {1, 4}) {
    GBuffer g = ts::rasterize(s, cam, W, H, instrumented(threads));
    for (size_t i = 0; i < g.pixelCount(); ++i)
      if (g.depth[i] > 0) {
        ASSERT_EQ(g.triangleId[i], 0);
      }
  }
}

TEST(RasterInterpolation, UvOnASlantedQuadIsPerspectiveCorrect) {
  const int W = 64, H = 64;
  SceneCamera cam = identityCamera();
  CameraIntrinsics in = CameraIntrinsics::from(cam, W, H);
  Scene s;
  // Texture whose red channel is u exactly (bilinear between texel centres (i + 0.5) / N).
  ts::Texture tex;
  tex.width = 1024;
  tex.height = 1;
  for (int i = 0; i < tex.width; ++i)
    tex.texels.push_back(glm::vec4((i + 0.5f) / tex.width, 0.0f, 0.0f, 1.0f));
  s.textures.push_back(tex);
  uint32_t m = addMaterial(s, glm::vec3(1.0f));
  s.materials[m].diffuseTexture = 0;
  // Floor-like quad receding in depth: x in [-2, 2], from z = -1.2 (u = 0.05) to z = -20
  // (u = 0.95).
  glm::vec3 a(-2, -1, -1.2f), b(2, -1, -1.2f), c(2, 1.5f, -20), d(-2, 1.5f, -20);
  const float u0 = 0.05f, u1 = 0.95f;
  addTriangle(s, a, b, c, m, {u0, 0}, {u0, 0}, {u1, 0});
  addTriangle(s, a, c, d, m, {u0, 0}, {u1, 0}, {u1, 0});
  GBuffer g = ts::rasterize(s, cam, W, H);
  // Analytic: intersect the pixel ray with the plane through a, b, c; u is linear in view z.
  glm::dvec3 A(a), B(b), C(c);
  glm::dvec3 n = glm::cross(B - A, C - A);
  int checked = 0;
  double maxAffineGap = 0.0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      size_t i = size_t(y) * W + x;
      if (g.depth[i] <= 0) continue;
      glm::dvec3 r = pixelRay(in, x, y);
      glm::dvec3 P = r * (glm::dot(n, A) / glm::dot(n, r));
      double t = (P.z - A.z) / (C.z - A.z);
      if (P.x < -1.95 || P.x > 1.95 || t < 0.01 || t > 0.99) continue;  // stay off the edges
      double u = u0 + t * (u1 - u0);
      ASSERT_NEAR(g.diffuse[i].x, u, 2e-5) << x << "," << y;
      // Affine (screen-linear) interpolation along the depth direction: screen y is linear
      // between the projections of the near and far edges.
      double yNear = (1.0 - (A.y / -A.z) / in.tanHalfFovY) * 0.5 * H;
      double yFar = (1.0 - (C.y / -C.z) / in.tanHalfFovY) * 0.5 * H;
      double affine = u0 + (y + 0.5 - yNear) / (yFar - yNear) * (u1 - u0);
      maxAffineGap = std::max(maxAffineGap, std::abs(affine - u));
      ++checked;
    }
  EXPECT_GT(checked, 500);
  EXPECT_GT(maxAffineGap, 0.1);  // affine interpolation would fail the check above
}

TEST(RasterClipping, TriangleCrossingTheNearPlaneRendersItsVisiblePart) {
  const int W = 64, H = 48;
  const float znear = 0.5f;
  const double floorY = -0.3;  // low enough that the clipped edge (depth znear) is on screen
  SceneCamera cam = identityCamera(znear, 100.0f);
  CameraIntrinsics in = CameraIntrinsics::from(cam, W, H);
  Scene s;
  uint32_t m = addMaterial(s, glm::vec3(1.0f));
  // Floor triangle from behind the camera (z = +3, wide) to far in front.
  const glm::dvec2 a(-30, 3), b(30, 3), c(0, -40);  // (x, z)
  addTriangle(s, glm::vec3(a.x, floorY, a.y), glm::vec3(b.x, floorY, b.y),
              glm::vec3(c.x, floorY, c.y), m);
  GBuffer g = ts::rasterize(s, cam, W, H, instrumented());
  // Signed distance of (x, z) to the edge p-q, positive inside (the triangle is a, c, b in xz).
  auto dist = [](glm::dvec2 p, glm::dvec2 q, glm::dvec2 v) {
    glm::dvec2 e = q - p;
    return (e.x * (v.y - p.y) - e.y * (v.x - p.x)) / glm::length(e);
  };
  int agree = 0, disagree = 0, clippedAway = 0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      size_t i = size_t(y) * W + x;
      ASSERT_LE(g.fragmentCount[i], 1u);
      glm::dvec3 r = pixelRay(in, x, y);
      double t = r.y < 0 ? floorY / r.y : -1.0;  // ray-floor intersection, depth = t
      bool got = g.depth[i] > 0;
      if (got) {
        ASSERT_NEAR(g.depth[i], t, 1e-5 * t) << x << "," << y;
      }
      bool expected = false;
      if (t > 0) {
        glm::dvec2 P(r.x * t, -t);
        double margin = 2.0 * t * 2.0 * in.tanHalfFovX / W;  // two pixels at that depth
        double d0 = dist(a, c, P), d1 = dist(c, b, P), d2 = dist(b, a, P);
        if (std::abs(t - znear) < 0.05 || std::abs(d0) < margin || std::abs(d1) < margin ||
            std::abs(d2) < margin)
          continue;
        bool inTriangle = d0 > 0 && d1 > 0 && d2 > 0;
        expected = inTriangle && t >= znear;
        clippedAway += inTriangle && t < znear;
      }
      (got == expected ? agree : disagree)++;
    }
  EXPECT_EQ(disagree, 0);
  EXPECT_GT(agree, W * H / 2);
  EXPECT_GT(clippedAway, W);  // rows whose floor point lies nearer than znear: not drawn
  // Nearest rendered depth is at the near plane (the clipped edge is on screen).
  float nearest = 1e9f;
  for (float d : g.depth)
    if (d > 0) nearest = std::min(nearest, d);
  EXPECT_GE(nearest, znear * 0.999f);
  EXPECT_LT(nearest, znear * 1.1f);
}

TEST(RasterClipping, TriangleBehindTheCameraOrBeyondFarRendersNothing) {
  SceneCamera cam = identityCamera(0.1f, 50.0f);
  Scene s;
  uint32_t m = addMaterial(s, glm::vec3(1.0f));
  addTriangle(s, {-5, -5, 1}, {5, -5, 1}, {0, 5, 0.05f}, m);              // behind the eye
  addTriangle(s, {-5, -5, -0.05f}, {5, -5, -0.05f}, {0, 5, -0.09f}, m);   // between eye and near
  addTriangle(s, {-500, -500, -60}, {500, -500, -60}, {0, 500, -60}, m);  // beyond zfar
  GBuffer g = ts::rasterize(s, cam, 33, 17, instrumented());
  EXPECT_EQ(g.geometryPixels(), 0u);
  for (size_t i = 0; i < g.pixelCount(); ++i) {
    EXPECT_EQ(g.triangleId[i], -1);
    EXPECT_EQ(g.normal[i], glm::vec4(0.0f));
    EXPECT_EQ(g.diffuse[i], glm::vec4(0.0f));
  }
  // A triangle straddling the far plane keeps only its part within zfar.
  Scene f;
  uint32_t fm = addMaterial(f, glm::vec3(1.0f));
  addTriangle(f, {-100, -5, -10}, {100, -5, -10}, {0, -5, -90}, fm);
  GBuffer gf = ts::rasterize(f, cam, 64, 64);
  float deepest = 0;
  for (float d : gf.depth) deepest = std::max(deepest, d);
  EXPECT_GT(deepest, 40.0f);
  EXPECT_LE(deepest, 50.0f);
}

TEST(RasterClipping, HugeTriangleCoveringTheScreenIsExact) {
  const int W = 101, H = 77;
  SceneCamera cam = identityCamera(0.01f, 1e9f);
  CameraIntrinsics in = CameraIntrinsics::from(cam, W, H);
  Scene s;
  uint32_t m = addMaterial(s, glm::vec3(1.0f));
  // Spans about 1e8 pixels; one vertex even lies behind the camera.
  addTriangle(s, {-1e7f, -1e7f, -20}, {1e7f, -1e7f, -20}, {0, 3e7f, 5}, m);
  GBuffer g = ts::rasterize(s, cam, W, H, instrumented());
  glm::dvec3 A(-1e7, -1e7, -20), B(1e7, -1e7, -20), C(0, 3e7, 5);
  glm::dvec3 n = glm::cross(B - A, C - A);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      size_t i = size_t(y) * W + x;
      ASSERT_EQ(g.fragmentCount[i], 1u);
      glm::dvec3 r = pixelRay(in, x, y);
      double t = glm::dot(n, A) / glm::dot(n, r);
      ASSERT_NEAR(g.depth[i], t, 1e-5 * t);
    }
}

TEST(RasterShading, MaterialsNormalsAndDoubleSidedBackFaces) {
  const int W = 32, H = 32;
  SceneCamera cam = identityCamera();
  CameraIntrinsics in = CameraIntrinsics::from(cam, W, H);
  Scene s;
  ts::Material single;
  single.diffuse = {0.2f, 0.4f, 0.6f};
  single.specular = {0.1f, 0.2f, 0.3f};
  single.shininess = 40.0f;
  single.emissive = {1.0f, 2.0f, 3.0f};
  s.materials.push_back(single);
  ts::Material twoSided = single;
  twoSided.doubleSided = true;
  s.materials.push_back(twoSided);
  // Left half: single-sided back face (clockwise on screen); right half: double-sided back face.
  const double d = 4.0;
  auto backFace = [&](double x0, double x1, uint32_t m) {
    addTriangle(s, unproject(in, x0, 0, d), unproject(in, x1, 0, d), unproject(in, x0, H, d), m);
  };
  backFace(0, 16, 0);
  backFace(16, 32, 1);
  GBuffer g = ts::rasterize(s, cam, W, H);
  size_t left = size_t(4) * W + 4, right = size_t(4) * W + 20;
  ASSERT_GT(g.depth[left], 0.0f);  // back faces are not culled
  ASSERT_GT(g.depth[right], 0.0f);
  EXPECT_NEAR(g.normal[left].z, -1.0f, 1e-6f);  // as the vertex data says
  EXPECT_NEAR(g.normal[right].z, 1.0f, 1e-6f);  // flipped towards the viewer
  EXPECT_EQ(g.normal[left].w, 0.0f);
  EXPECT_EQ(g.diffuse[left], glm::vec4(0.2f, 0.4f, 0.6f, 1.0f));
  EXPECT_EQ(g.specular[left], glm::vec4(0.1f, 0.2f, 0.3f, 40.0f));
  EXPECT_EQ(g.emissive[left], glm::vec4(1.0f, 2.0f, 3.0f, 0.0f));
  // Seen from an oblique camera: depth at the centre is the eye distance, normals stay unit.
  Scene r;
  uint32_t m = addMaterial(r, glm::vec3(1.0f));
  r.vertices = {{{-10, -10, 0}, {-0.5f, 0, 1}, {}},
                {{10, -10, 0}, {0.5f, 0, 1}, {}},
                {{0, 10, 0}, {0, 0.5f, 1}, {}}};
  r.indices = {0, 1, 2};
  r.triangleMaterial = {m};
  SceneCamera turned = SceneCamera::lookAt({3, 0, 4}, {0, 0, 0}, {0, 1, 0}, kYfov, 0.1f, 100.0f);
  GBuffer gr = ts::rasterize(r, turned, 33, 33);  // odd: the centre pixel is on the optical axis
  size_t centre = size_t(16) * 33 + 16;
  ASSERT_GT(gr.depth[centre], 0.0f);
  EXPECT_NEAR(gr.depth[centre], 5.0f, 1e-5f);
  // The centre sees the world origin, barycentrics (1/4, 1/4, 1/2): the normalized vertex normals
  // blended there, in view space.
  glm::vec3 world = glm::normalize(0.25f * glm::normalize(glm::vec3(-0.5f, 0, 1)) +
                                   0.25f * glm::normalize(glm::vec3(0.5f, 0, 1)) +
                                   0.5f * glm::normalize(glm::vec3(0, 0.5f, 1)));
  glm::vec3 expected = glm::mat3(turned.viewFromWorld) * world;
  EXPECT_LT(glm::distance(glm::vec3(gr.normal[centre]), expected), 1e-5f);
  EXPECT_GT(std::abs(expected.x), 0.3f);  // really rotated
  for (size_t i = 0; i < gr.pixelCount(); ++i)
    if (gr.depth[i] > 0) {
      ASSERT_NEAR(glm::length(glm::vec3(gr.normal[i])), 1.0f, 1e-5f);
    }
}

Scene randomScene(int triangles, uint32_t seed) {
  Scene s;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1, 1), depth(0.05f, 30.0f), size(0.05f, 3.0f);
  ts::Texture tex;
  tex.width = tex.height = 8;
  for (int i = 0; i < 64; ++i) tex.texels.push_back(glm::vec4(u(rng) * 0.5f + 0.5f, 0.5f, 1, 1));
  s.textures.push_back(tex);
  for (int k = 0; k < 6; ++k) {
    uint32_t m = addMaterial(s, glm::vec3(0.1f * k + 0.3f), k % 2 == 1);
    if (k % 3 == 0) s.materials[m].diffuseTexture = 0;
  }
  for (int t = 0; t < triangles; ++t) {
    // Mostly triangles about a tenth of the view wide at their depth; every 97th one straddles the
    // near plane or lies behind the camera, every 211th is large.
    float z = t % 97 == 0 ? u(rng) * 0.6f : -depth(rng);
    auto draw = [&] { return u(rng); };
    const auto xy = ts::test::drawnLastFirst<2>(draw);
    glm::vec3 c(xy[0] * std::abs(z), xy[1] * std::abs(z), z);
    float r = size(rng) * (t % 97 == 0 ? 0.2f : 0.06f * std::abs(z)) * (t % 211 == 0 ? 5.0f : 1.0f);
    uint32_t base = uint32_t(s.vertices.size());
    for (int v = 0; v < 3; ++v) {
      const auto p = ts::test::drawnLastFirst<3>(draw);
      const auto n = ts::test::drawnLastFirst<2>(draw);
      const float uvX = u(rng);  // a braced list's elements were drawn in order
      const float uvY = u(rng);
      s.vertices.push_back({c + r * glm::vec3(p[0], p[1], p[2]),
                            glm::normalize(glm::vec3(n[0], n[1], 1.0f)),
                            {uvX, uvY}});
    }
    s.indices.insert(s.indices.end(), {base, base + 1, base + 2});
    s.triangleMaterial.push_back(uint32_t(rng() % s.materials.size()));
  }
  return s;
}

void expectIdentical(const GBuffer& a, const GBuffer& b) {
  ASSERT_EQ(a.width, b.width);
  ASSERT_EQ(a.height, b.height);
  size_t n = a.pixelCount();
  EXPECT_EQ(std::memcmp(a.depth.data(), b.depth.data(), n * sizeof(float)), 0);
  EXPECT_EQ(std::memcmp(a.normal.data(), b.normal.data(), n * sizeof(glm::vec4)), 0);
  EXPECT_EQ(std::memcmp(a.diffuse.data(), b.diffuse.data(), n * sizeof(glm::vec4)), 0);
  EXPECT_EQ(std::memcmp(a.specular.data(), b.specular.data(), n * sizeof(glm::vec4)), 0);
  EXPECT_EQ(std::memcmp(a.emissive.data(), b.emissive.data(), n * sizeof(glm::vec4)), 0);
  EXPECT_EQ(a.triangleId, b.triangleId);
  EXPECT_EQ(a.fragmentCount, b.fragmentCount);
}

TEST(RasterThreads, OutputIsIdenticalForAnyThreadCount) {
  Scene s = randomScene(3000, 11);  // >= 1024 triangles: setup is split across the threads too
  SceneCamera cam = identityCamera(0.1f, 25.0f);
  for (auto [W, H] : {std::pair{97, 61}, std::pair{200, 150}}) {
    GBuffer one = ts::rasterize(s, cam, W, H, instrumented(1));
    EXPECT_GT(one.geometryPixels(), size_t(W * H / 2));
    std::set<int32_t> visible(one.triangleId.begin(), one.triangleId.end());
    EXPECT_GT(visible.size(), 50u);
    for (int threads : {2, 4, 7}) {
      SCOPED_TRACE(threads);
      expectIdentical(one, ts::rasterize(s, cam, W, H, instrumented(threads)));
    }
  }
}

TEST(RasterResolution, OddSizesAndTinyImagesWork) {
  SceneCamera cam = identityCamera();
  for (auto [W, H] : {std::pair{97, 61}, std::pair{1, 1}, std::pair{65, 1}, std::pair{1, 129}}) {
    CameraIntrinsics in = CameraIntrinsics::from(cam, W, H);
    Scene s;
    uint32_t m = addMaterial(s, glm::vec3(1.0f));
    addQuad(s, unproject(in, -1, -1, 3), unproject(in, -1, H + 1, 3),
            unproject(in, W + 1, H + 1, 3), unproject(in, W + 1, -1, 3), m, m);
    GBuffer g = ts::rasterize(s, cam, W, H, instrumented());
    ASSERT_EQ(g.width, W);
    ASSERT_EQ(g.depth.size(), size_t(W) * H);
    EXPECT_EQ(g.geometryPixels(), size_t(W) * H);
    for (uint32_t c : g.fragmentCount) ASSERT_EQ(c, 1u);
  }
  Scene empty;
  GBuffer g = ts::rasterize(empty, cam, 10, 10);
  EXPECT_EQ(g.geometryPixels(), 0u);
  EXPECT_TRUE(g.triangleId.empty());
  EXPECT_THROW(ts::rasterize(empty, cam, 0, 10), ts::Error);
}

// ---- alphaMode (issue #17) ---------------------------------------------------------------------

// A full-screen quad at depth 5 (triangles 0, 1) behind a quad at depth 2 over pixels x 4..28,
// y 2..14 (triangles 2, 3) whose texture (2x1, NEAREST) has alpha 0.2 in its left half (x < 16)
// and 1 in its right half; its material is the scene's material 1.
constexpr int kAlphaW = 32, kAlphaH = 16;
Scene alphaScene(ts::AlphaMode mode) {
  Scene s;
  s.name = "alpha";
  const CameraIntrinsics in = CameraIntrinsics::from(identityCamera(), kAlphaW, kAlphaH);
  const uint32_t back = addMaterial(s, glm::vec3(0.2f, 0.3f, 0.4f));
  ts::Material m;
  m.name = "leaf";
  m.diffuse = glm::vec3(0.9f);
  m.alphaMode = mode;
  m.diffuseTexture = m.baseColorTexture = 0;
  s.materials.push_back(m);
  ts::Texture t;
  t.width = 2;
  t.height = 1;
  t.texels = {glm::vec4(1.0f, 1.0f, 1.0f, 0.2f), glm::vec4(1.0f)};
  t.nearest = true;
  t.wrapS = t.wrapT = ts::TextureWrap::ClampToEdge;
  s.textures.push_back(t);
  addQuad(s, unproject(in, 0, kAlphaH, 5), unproject(in, kAlphaW, kAlphaH, 5),
          unproject(in, kAlphaW, 0, 5), unproject(in, 0, 0, 5), back, back);
  const glm::vec3 a = unproject(in, 4, 14, 2), b = unproject(in, 28, 14, 2),
                  c = unproject(in, 28, 2, 2), d = unproject(in, 4, 2, 2);
  addTriangle(s, a, b, c, 1, {0, 1}, {1, 1}, {1, 0});
  addTriangle(s, a, c, d, 1, {0, 1}, {1, 0}, {0, 0});
  return s;
}

// Inside the front quad's rectangle: how many pixels of its left and right halves show it.
std::pair<int, int> frontPixels(const GBuffer& g) {
  int left = 0, right = 0;
  for (int y = 2; y < 14; ++y)
    for (int x = 4; x < 28; ++x) {
      const size_t i = size_t(y) * kAlphaW + size_t(x);
      const bool front = g.triangleId[i] >= 2;
      EXPECT_NEAR(g.depth[i], front ? 2.0f : 5.0f, 1e-5f) << x << "," << y;
      (x < 16 ? left : right) += front ? 1 : 0;
    }
  return {left, right};
}

TEST(RasterAlpha, MaskLeavesFragmentsBelowTheCutoffOutWhateverTheShadingModel) {
  constexpr int kHalf = 12 * 12;  // pixels of each half of the front quad
  for (ts::ShadingModel model : {ts::ShadingModel::BlinnPhong, ts::ShadingModel::MetallicRoughness})
    for (ts::ShadingModel written :
         {ts::ShadingModel::BlinnPhong, ts::ShadingModel::MetallicRoughness}) {
      SCOPED_TRACE(ts::toString(model) + " frame, material written " + ts::toString(written));
      Scene s = alphaScene(ts::AlphaMode::Mask);
      ts::Material& m = s.materials[1];
      m.model = written;
      // Only the written model's base colour texture carries the alpha.
      (written == ts::ShadingModel::BlinnPhong ? m.baseColorTexture : m.diffuseTexture) = -1;
      RasterOptions o = instrumented();
      o.model = model;
      EXPECT_EQ(frontPixels(ts::rasterize(s, identityCamera(), kAlphaW, kAlphaH, o)),
                std::make_pair(0, kHalf));
    }
  RasterOptions o = instrumented();
  Scene s = alphaScene(ts::AlphaMode::Mask);
  // The factor multiplies the texture: 0.4 x 1 is below 0.5, and is not below 0.4 (glTF: a
  // fragment is drawn where alpha >= alphaCutoff).
  s.materials[1].opacity = 0.4f;
  EXPECT_EQ(frontPixels(ts::rasterize(s, identityCamera(), kAlphaW, kAlphaH, o)),
            std::make_pair(0, 0));
  s.materials[1].alphaCutoff = 0.4f;
  EXPECT_EQ(frontPixels(ts::rasterize(s, identityCamera(), kAlphaW, kAlphaH, o)),
            std::make_pair(0, kHalf));
  s.materials[1].alphaCutoff = 0.0f;
  EXPECT_EQ(frontPixels(ts::rasterize(s, identityCamera(), kAlphaW, kAlphaH, o)),
            std::make_pair(kHalf, kHalf));
  // OPAQUE ignores alpha.
  Scene opaque = alphaScene(ts::AlphaMode::Opaque);
  opaque.materials[1].opacity = 0.0f;
  EXPECT_EQ(frontPixels(ts::rasterize(opaque, identityCamera(), kAlphaW, kAlphaH, o)),
            std::make_pair(kHalf, kHalf));
}

TEST(RasterAlpha, BlendIsRefusedNamingTheMaterialUnlessThePolicyDrawsIt) {
  Scene s = alphaScene(ts::AlphaMode::Blend);
  try {
    ts::rasterize(s, identityCamera(), kAlphaW, kAlphaH, instrumented());
    ADD_FAILURE() << "a BLEND material was drawn";
  } catch (const ts::Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("material 'leaf' is alphaMode BLEND: --blend blend composites it"),
              std::string::npos)
        << what;
    EXPECT_NE(what.find("--blend as-opaque"), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
  // A BLEND material no triangle uses draws nothing: nothing to refuse.
  Scene unused = alphaScene(ts::AlphaMode::Opaque);
  unused.materials.push_back(s.materials[1]);
  EXPECT_NO_THROW(ts::rasterize(unused, identityCamera(), kAlphaW, kAlphaH, instrumented()));
  constexpr int kHalf = 12 * 12;
  Scene opaque = s;
  ts::applyBlendPolicy(opaque, ts::BlendPolicy::AsOpaque);
  EXPECT_EQ(frontPixels(ts::rasterize(opaque, identityCamera(), kAlphaW, kAlphaH, instrumented())),
            std::make_pair(kHalf, kHalf));
  Scene masked = s;
  ts::applyBlendPolicy(masked, ts::BlendPolicy::AsMask);
  EXPECT_EQ(frontPixels(ts::rasterize(masked, identityCamera(), kAlphaW, kAlphaH, instrumented())),
            std::make_pair(0, kHalf));
  ts::applyBlendPolicy(s, ts::BlendPolicy::Refuse);
  EXPECT_THROW(ts::rasterize(s, identityCamera(), kAlphaW, kAlphaH, instrumented()), ts::Error);
}

TEST(RasterScene, InvalidIndicesThrow) {
  Scene s;
  addMaterial(s, glm::vec3(1.0f));
  s.vertices.resize(3);
  s.indices = {0, 1, 3};
  s.triangleMaterial = {0};
  EXPECT_THROW(ts::rasterize(s, identityCamera(), 8, 8), ts::Error);
  s.indices = {0, 1, 2};
  s.triangleMaterial = {1};
  EXPECT_THROW(ts::rasterize(s, identityCamera(), 8, 8), ts::Error);
}

}  // namespace
