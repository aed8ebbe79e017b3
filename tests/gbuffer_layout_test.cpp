// G-buffer storage layouts (src/raster/gbuffer_layout.cpp): sizes, format names, the fp32/fp16
// encodings and decodeSurface, the host mirror of ts_load_surface in kernels/gbuffer.h.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "raster/gbuffer.h"
#include "raster/gbuffer_layout.h"
#include "util/error.h"

namespace {

using ts::EncodedGBuffer;
using ts::GBuffer;
using ts::GBufferFormat;

// Independent IEEE binary16 decoder (so the tests do not only compare Imath with itself).
double halfToDouble(uint16_t h) {
  int sign = h >> 15, exponent = (h >> 10) & 31, mantissa = h & 1023;
  double v;
  if (exponent == 0)
    v = std::ldexp(double(mantissa), -24);
  else if (exponent == 31)
    v = mantissa ? NAN : INFINITY;
  else
    v = std::ldexp(double(1024 + mantissa), exponent - 25);
  return sign ? -v : v;
}

uint16_t halfBits(const std::vector<uint8_t>& plane, size_t pixel, int component) {
  uint16_t h;
  std::memcpy(&h, plane.data() + (pixel * 4 + size_t(component)) * 2, 2);
  return h;
}

glm::vec4 fp32At(const std::vector<uint8_t>& plane, size_t pixel) {
  glm::vec4 v;
  std::memcpy(&v, plane.data() + pixel * 16, 16);
  return v;
}

GBuffer sampleGBuffer() {
  GBuffer g;
  g.resize(3, 2);
  for (size_t i = 0; i < g.pixelCount(); ++i) {
    float k = float(i);
    g.depth[i] = i == 4 ? 0.0f : 1.5f + 0.37f * k;
    g.normal[i] = glm::vec4(glm::normalize(glm::vec3(0.3f + k, -0.7f, 1.1f)), 0.0f);
    g.diffuse[i] = glm::vec4(0.1f * k, 0.333333f, 0.7f, 1.0f);
    g.specular[i] = glm::vec4(0.04f, 0.05f + 0.01f * k, 0.9f, 17.3f + k);
    g.emissive[i] = glm::vec4(3.14159f * k, 0.0f, 1e-3f, 0.0f);
  }
  return g;
}

ts::CameraIntrinsics intrinsics(int w, int h) {
  ts::Camera cam;
  cam.yfov = 1.1f;
  return ts::CameraIntrinsics::from(cam, w, h);
}

TEST(GBufferLayout, SizesNamesAndDefines) {
  GBuffer g = sampleGBuffer();
  EncodedGBuffer e32 = ts::encode(g, GBufferFormat::FP32);
  EncodedGBuffer e16 = ts::encode(g, GBufferFormat::FP16);
  EXPECT_EQ(e32.bytesPerPixel(), 68u);
  EXPECT_EQ(e16.bytesPerPixel(), 36u);
  EXPECT_EQ(e32.kernelDefines(), "");
  EXPECT_EQ(e16.kernelDefines(), "-DTS_GBUFFER_FP16");
  size_t n = g.pixelCount();
  EXPECT_EQ(e32.depth.size(), n);
  EXPECT_EQ(e32.normal.size(), n * 16);
  EXPECT_EQ(e16.normal.size(), n * 8);
  EXPECT_EQ(e16.emissive.size(), n * 8);
  EXPECT_EQ(n * 4 + e16.normal.size() + e16.diffuse.size() + e16.specular.size() +
                e16.emissive.size(),
            n * e16.bytesPerPixel());
  EXPECT_EQ(ts::toString(GBufferFormat::FP32), "fp32");
  EXPECT_EQ(ts::toString(GBufferFormat::FP16), "fp16");
  EXPECT_EQ(ts::parseGBufferFormat("fp32"), GBufferFormat::FP32);
  EXPECT_EQ(ts::parseGBufferFormat("fp16"), GBufferFormat::FP16);
  EXPECT_THROW(ts::parseGBufferFormat("FP16"), ts::Error);
  EXPECT_THROW(ts::parseGBufferFormat("packed"), ts::Error);
  EXPECT_THROW(ts::parseGBufferFormat(""), ts::Error);
}

TEST(GBufferLayout, Fp32RoundTripIsExact) {
  GBuffer g = sampleGBuffer();
  EncodedGBuffer e = ts::encode(g, GBufferFormat::FP32);
  ts::CameraIntrinsics cam = intrinsics(3, 2);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 3; ++x) {
      size_t i = size_t(y) * 3 + x;
      EXPECT_EQ(e.depth[i], g.depth[i]);
      EXPECT_EQ(fp32At(e.normal, i), g.normal[i]);
      EXPECT_EQ(fp32At(e.specular, i), g.specular[i]);
      ts::SurfaceD s;
      bool geometry = ts::decodeSurface(e, cam, x, y, s);
      ASSERT_EQ(geometry, g.depth[i] > 0) << i;
      if (!geometry) continue;
      EXPECT_EQ(s.kd, glm::dvec3(glm::vec3(g.diffuse[i])));
      EXPECT_EQ(s.ks, glm::dvec3(glm::vec3(g.specular[i])));
      EXPECT_EQ(s.shininess, double(g.specular[i].w));
      EXPECT_EQ(s.ke, glm::dvec3(glm::vec3(g.emissive[i])));
      glm::dvec3 n = glm::normalize(glm::dvec3(glm::vec3(g.normal[i])));
      EXPECT_NEAR(glm::distance(s.N, n), 0.0, 1e-15);
      EXPECT_NEAR(-s.P.z, double(g.depth[i]), 1e-15);
      EXPECT_NEAR(glm::distance(s.V, glm::normalize(-s.P)), 0.0, 1e-15);
    }
}

TEST(GBufferLayout, Fp16StoresRoundToNearestEvenHalves) {
  GBuffer g;
  g.resize(2, 1);
  // 1 + 2^-11 is halfway between 1 and 1 + 2^-10: ties to even -> 1.
  // 1 + 3 * 2^-11 is halfway between 1 + 2^-10 and 1 + 2^-9: ties to even -> 1 + 2^-9.
  // 0.1 is not representable: nearest half is 0x2E66 (0.0999755859375).
  // 70000 overflows half's range (65504): infinity.
  g.depth = {2.0f, 3.0f};
  g.diffuse[0] = glm::vec4(1.0f + std::ldexp(1.0f, -11), 1.0f + 3.0f * std::ldexp(1.0f, -11),
                           0.1f, 70000.0f);
  g.normal[0] = glm::vec4(0.0f, 0.6f, 0.8f, 0.0f);
  g.specular[0] = glm::vec4(0.04f, 0.04f, 0.04f, 1000.0f);
  g.emissive[1] = glm::vec4(-2.5f, 1e-6f, 5e-8f, 0.0f);  // subnormal half, and underflow to 0
  EncodedGBuffer e = ts::encode(g, GBufferFormat::FP16);
  EXPECT_EQ(halfBits(e.diffuse, 0, 0), 0x3C00);  // 1.0
  EXPECT_EQ(halfBits(e.diffuse, 0, 1), 0x3C02);  // 1 + 2^-9
  EXPECT_EQ(halfBits(e.diffuse, 0, 2), 0x2E66);
  EXPECT_EQ(halfBits(e.diffuse, 0, 3), 0x7C00);  // +inf
  EXPECT_EQ(halfBits(e.specular, 0, 3), 0x63D0);  // 1000 exactly
  EXPECT_EQ(halfBits(e.emissive, 1, 0), 0xC100);  // -2.5
  EXPECT_EQ(halfBits(e.emissive, 1, 1), 0x0011);  // 1e-6 -> 17 * 2^-24 (nearest subnormal)
  EXPECT_EQ(halfBits(e.emissive, 1, 2), 0x0001);  // 5e-8 -> 2^-24 (nearest)
  EXPECT_EQ(e.depth, g.depth);                    // depth stays float32
  // Every stored half is the nearest one to the float (independently of the encoder).
  for (const auto* plane : {&e.normal, &e.diffuse, &e.specular, &e.emissive})
    for (size_t i = 0; i < 2; ++i)
      for (int c = 0; c < 3; ++c) {
        uint16_t h = halfBits(*plane, i, c);
        double v = halfToDouble(h);
        ASSERT_TRUE(std::isfinite(v));
        double below = halfToDouble(uint16_t(h - 1)), above = halfToDouble(uint16_t(h + 1));
        const glm::vec4* src = plane == &e.normal     ? &g.normal[i]
                               : plane == &e.diffuse  ? &g.diffuse[i]
                               : plane == &e.specular ? &g.specular[i]
                                                      : &g.emissive[i];
        double f = (*src)[c];
        if ((h & 0x7FFF) != 0 && (h & 0x7FFF) != 0x7BFF) {  // neighbours exist on both sides
          EXPECT_LE(std::abs(f - v), std::abs(f - below)) << f;
          EXPECT_LE(std::abs(f - v), std::abs(f - above)) << f;
        }
      }
  // The decoder reads back exactly those halves.
  ts::SurfaceD s;
  ASSERT_TRUE(ts::decodeSurface(e, intrinsics(2, 1), 0, 0, s));
  EXPECT_EQ(s.kd, glm::dvec3(1.0, 1.0 + std::ldexp(1.0, -9), halfToDouble(0x2E66)));
  EXPECT_EQ(s.shininess, 1000.0);
  EXPECT_EQ(s.ks.x, halfToDouble(halfBits(e.specular, 0, 0)));
  EXPECT_NE(s.ks.x, 0.04);  // 0.04 is not a half
  glm::dvec3 n(halfToDouble(halfBits(e.normal, 0, 0)), halfToDouble(halfBits(e.normal, 0, 1)),
               halfToDouble(halfBits(e.normal, 0, 2)));
  EXPECT_NEAR(glm::distance(s.N, glm::normalize(n)), 0.0, 1e-15);
  ASSERT_TRUE(ts::decodeSurface(e, intrinsics(2, 1), 1, 0, s));
  EXPECT_EQ(s.ke, glm::dvec3(-2.5, 17.0 * std::ldexp(1.0, -24), std::ldexp(1.0, -24)));
  // A zero normal decodes to zero like OpenCL's normalize (no NaN).
  EXPECT_EQ(s.N, glm::dvec3(0.0));
}

TEST(GBufferLayout, DecodedPositionsReconstructTheRasterizedPlane) {
  const int W = 72, H = 40;
  ts::Camera cam;
  cam.viewFromWorld = glm::mat4(1.0f);
  cam.yfov = 1.0f;
  cam.znear = 0.1f;
  cam.zfar = 100.0f;
  ts::CameraIntrinsics in = ts::CameraIntrinsics::from(cam, W, H);
  // A tilted plane through (0, 0, -6), covering the screen.
  const glm::dvec3 n = glm::normalize(glm::dvec3(-0.3, 0.5, 0.8)), p0(0, 0, -6);
  auto onPlane = [&](double ndcX, double ndcY) {
    glm::dvec3 r(ndcX * in.tanHalfFovX, ndcY * in.tanHalfFovY, -1.0);
    return glm::vec3(r * (glm::dot(n, p0) / glm::dot(n, r)));
  };
  ts::Scene scene;
  scene.materials.push_back(ts::Material{});
  glm::vec3 a = onPlane(-1.1, 1.1), b = onPlane(-1.1, -1.1), c = onPlane(1.1, -1.1),
            d = onPlane(1.1, 1.1);
  glm::vec3 fn(n);
  for (glm::vec3 v : {a, b, c, d}) scene.vertices.push_back({v, fn, {}});
  scene.indices = {0, 1, 2, 0, 2, 3};
  scene.triangleMaterial = {0, 0};
  GBuffer g = ts::rasterize(scene, cam, W, H);
  ASSERT_EQ(g.geometryPixels(), size_t(W) * H);
  for (GBufferFormat format : {GBufferFormat::FP32, GBufferFormat::FP16}) {
    EncodedGBuffer e = ts::encode(g, format);
    double worstPlane = 0, worstN = 0;
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) {
        ts::SurfaceD s;
        ASSERT_TRUE(ts::decodeSurface(e, in, x, y, s));
        // P lies on the pixel's ray at the stored depth, and on the plane.
        double ndcX = 2.0 * (x + 0.5) / W - 1.0, ndcY = 1.0 - 2.0 * (y + 0.5) / H;
        double depth = g.depth[size_t(y) * W + x];
        EXPECT_EQ(s.P.z, -depth);
        EXPECT_NEAR(s.P.x, ndcX * in.tanHalfFovX * depth, 1e-12);
        worstPlane = std::max(worstPlane, std::abs(glm::dot(n, s.P - p0)) / depth);
        worstN = std::max(worstN, glm::distance(s.N, n));
        EXPECT_NEAR(glm::length(s.V), 1.0, 1e-12);
      }
    EXPECT_LT(worstPlane, 1e-6);  // float depth rounding
    EXPECT_LT(worstN, format == GBufferFormat::FP32 ? 1e-6 : 1e-3);
  }
}

TEST(GBufferLayout, DecodeRejectsMismatchedCameraAndOutOfRangePixels) {
  EncodedGBuffer e = ts::encode(sampleGBuffer(), GBufferFormat::FP32);
  ts::SurfaceD s;
  EXPECT_THROW(ts::decodeSurface(e, intrinsics(4, 2), 0, 0, s), ts::Error);
  EXPECT_THROW(ts::decodeSurface(e, intrinsics(3, 2), 3, 0, s), std::out_of_range);
  EXPECT_FALSE(ts::decodeSurface(e, intrinsics(3, 2), 1, 1, s));  // pixel 4: background
}

}  // namespace
