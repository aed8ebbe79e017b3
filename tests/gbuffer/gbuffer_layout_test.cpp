// G-buffer storage layouts (src/gbuffer/gbuffer_layout.cpp): sizes, format names, the fp32/fp16/
// packed encodings and decodeSurface, the host mirror of ts_load_surface in kernels/gbuffer.h.
// The packed bounds checked here are the ones docs/accuracy.md documents.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>

#include "gbuffer/gbuffer.h"
#include "gbuffer/gbuffer_layout.h"
#include "raster/rasterizer.h"
#include "util/error.h"
#include "random_draws.h"

namespace {

using ts::EncodedGBuffer;
using ts::GBuffer;
using ts::GBufferFormat;

// Independent IEEE binary16 decoder (so the tests do not only compare Imath with itself).
double halfToDouble(uint16_t h) {
  int sign = h >> 15, exponent = (h >> 10) & 31, mantissa = h & 1023;
  double v;
  if (exponent == 0) v = std::ldexp(double(mantissa), -24);
  else if (exponent == 31) v = mantissa ? NAN : INFINITY;
  else v = std::ldexp(double(1024 + mantissa), exponent - 25);
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
  ts::SceneCamera cam;
  cam.yfov = 1.1f;
  return ts::CameraIntrinsics::from(cam, w, h);
}

TEST(GBufferLayout, SizesNamesAndDefines) {
  GBuffer g = sampleGBuffer();
  EncodedGBuffer e32 = ts::encode(g, GBufferFormat::FP32);
  EncodedGBuffer e16 = ts::encode(g, GBufferFormat::FP16);
  EncodedGBuffer ep = ts::encode(g, GBufferFormat::PACKED);
  EXPECT_EQ(e32.bytesPerPixel(), 68u);
  EXPECT_EQ(e16.bytesPerPixel(), 36u);
  EXPECT_EQ(ep.bytesPerPixel(), 24u);  // depth 4 + normal 4 + diffuse 4 + specular 4 + half4 8
  EXPECT_EQ(e32.kernelDefines(), "");
  EXPECT_EQ(e16.kernelDefines(), "-DTS_GBUFFER_FP16");
  EXPECT_EQ(ep.kernelDefines(), "-DTS_GBUFFER_PACKED");
  EXPECT_EQ(ts::gbufferKernelDefines(GBufferFormat::PACKED), "-DTS_GBUFFER_PACKED");
  size_t n = g.pixelCount();
  EXPECT_EQ(e32.depth.size(), n);
  EXPECT_EQ(e32.normal.size(), n * 16);
  EXPECT_EQ(e16.normal.size(), n * 8);
  EXPECT_EQ(e16.emissive.size(), n * 8);
  EXPECT_EQ(
      n * 4 + e16.normal.size() + e16.diffuse.size() + e16.specular.size() + e16.emissive.size(),
      n * e16.bytesPerPixel());
  EXPECT_EQ(ep.depth.size(), n);
  EXPECT_EQ(ep.normal.size(), n * 4);
  EXPECT_EQ(ep.diffuse.size(), n * 4);
  EXPECT_EQ(ep.specular.size(), n * 4);
  EXPECT_EQ(ep.emissive.size(), n * 8);
  EXPECT_EQ(n * 4 + ep.normal.size() + ep.diffuse.size() + ep.specular.size() + ep.emissive.size(),
            n * ep.bytesPerPixel());
  EXPECT_EQ(ts::toString(GBufferFormat::FP32), "fp32");
  EXPECT_EQ(ts::toString(GBufferFormat::FP16), "fp16");
  EXPECT_EQ(ts::toString(GBufferFormat::PACKED), "packed");
  EXPECT_EQ(ts::parseGBufferFormat("fp32"), GBufferFormat::FP32);
  EXPECT_EQ(ts::parseGBufferFormat("fp16"), GBufferFormat::FP16);
  EXPECT_EQ(ts::parseGBufferFormat("packed"), GBufferFormat::PACKED);
  EXPECT_THROW(ts::parseGBufferFormat("FP16"), ts::Error);
  EXPECT_THROW(ts::parseGBufferFormat("PACKED"), ts::Error);
  EXPECT_THROW(ts::parseGBufferFormat("unorm8"), ts::Error);
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
      EXPECT_EQ(s.gloss, double(g.specular[i].w));
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
  // 70000 is beyond half's range: clamped to its largest, 65504 (not inf; issue #12).
  g.depth = {2.0f, 3.0f};
  g.diffuse[0] =
      glm::vec4(1.0f + std::ldexp(1.0f, -11), 1.0f + 3.0f * std::ldexp(1.0f, -11), 0.1f, 70000.0f);
  g.normal[0] = glm::vec4(0.0f, 0.6f, 0.8f, 0.0f);
  g.specular[0] = glm::vec4(0.04f, 0.04f, 0.04f, 1000.0f);
  g.emissive[1] = glm::vec4(-2.5f, 1e-6f, 5e-8f, 0.0f);  // subnormal half, and underflow to 0
  EncodedGBuffer e = ts::encode(g, GBufferFormat::FP16);
  EXPECT_EQ(halfBits(e.diffuse, 0, 0), 0x3C00);  // 1.0
  EXPECT_EQ(halfBits(e.diffuse, 0, 1), 0x3C02);  // 1 + 2^-9
  EXPECT_EQ(halfBits(e.diffuse, 0, 2), 0x2E66);
  EXPECT_EQ(halfBits(e.diffuse, 0, 3), 0x7BFF);   // 65504
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
  EXPECT_EQ(s.gloss, 1000.0);
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
  ts::SceneCamera cam;
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
  for (GBufferFormat format : {GBufferFormat::FP32, GBufferFormat::FP16, GBufferFormat::PACKED}) {
    EncodedGBuffer e = ts::encode(g, format);
    double worstPlane = 0, worstN = 0;
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) {
        ts::SurfaceD s;
        ASSERT_TRUE(ts::decodeSurface(e, in, x, y, s));
        // P lies on the pixel's ray at the stored depth, and on the plane.
        double ndcX = 2.0 * (x + 0.5) / W - 1.0;
        double depth = g.depth[size_t(y) * W + x];
        EXPECT_EQ(s.P.z, -depth);
        EXPECT_NEAR(s.P.x, ndcX * in.tanHalfFovX * depth, 1e-12);
        worstPlane = std::max(worstPlane, std::abs(glm::dot(n, s.P - p0)) / depth);
        worstN = std::max(worstN, glm::distance(s.N, n));
        EXPECT_NEAR(glm::length(s.V), 1.0, 1e-12);
      }
    EXPECT_LT(worstPlane, 1e-6);  // float depth rounding
    EXPECT_LT(worstN, format == GBufferFormat::FP32     ? 1e-6
                      : format == GBufferFormat::PACKED ? ts::packed::kMaxNormalErrorRad + 1e-6
                                                        : 1e-3);
  }
}

// ---- packed layout (kernels/gbuffer.h, TS_GBUFFER_PACKED) ----

uint32_t u32At(const std::vector<uint8_t>& plane, size_t pixel) {
  uint32_t v;
  std::memcpy(&v, plane.data() + pixel * 4, 4);
  return v;
}

double angleBetween(const glm::dvec3& a, const glm::dvec3& b) {
  return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

// Independent decoder of the packed normal, written from the layout comment in kernels/gbuffer.h
// (double precision, before normalization).
glm::dvec3 octahedralDecode(uint32_t v) {
  double x = std::max(double(int16_t(v & 0xffffu)) / 32767.0, -1.0);
  double y = std::max(double(int16_t(v >> 16)) / 32767.0, -1.0);
  double z = 1.0 - std::abs(x) - std::abs(y);
  if (z < 0.0) {
    double fx = (1.0 - std::abs(y)) * (x >= 0.0 ? 1.0 : -1.0);
    double fy = (1.0 - std::abs(x)) * (y >= 0.0 ? 1.0 : -1.0);
    x = fx;
    y = fy;
  }
  return glm::normalize(glm::dvec3(x, y, z));
}

TEST(GBufferLayout, PackedOctahedralNormalsWithinTheirBound) {
  namespace pk = ts::packed;
  // Exact points of the octahedral map: the axes and the fold.
  EXPECT_EQ(pk::encodeNormal({0, 0, 1}), 0u);
  EXPECT_EQ(pk::encodeNormal({1, 0, 0}), 32767u);
  EXPECT_EQ(pk::encodeNormal({0, -1, 0}), uint32_t(uint16_t(-32767)) << 16);
  EXPECT_EQ(pk::encodeNormal({0, 0, -1}), 32767u | 32767u << 16);  // folded corner (+1, +1)
  EXPECT_EQ(pk::encodeNormal({0, 0, 0}), 0u);                      // degenerate: +Z, no NaN
  EXPECT_EQ(pk::encodeNormal({NAN, 0, 1}), 0u);
  EXPECT_EQ(octahedralDecode(pk::encodeNormal({0, 0, -1})), glm::dvec3(0, 0, -1));
  EXPECT_EQ(octahedralDecode(pk::encodeNormal({-1, 0, 0})), glm::dvec3(-1, 0, 0));

  std::mt19937 rng(5);
  std::normal_distribution<double> gauss;
  std::vector<glm::vec3> normals = {{1, 1, 1},  {-1, 1, -1},     {1, -1, 0},     {0, 1, -1e-7f},
                                    {3, 0, -4}, {0.6f, 0.8f, 0}, {-1e-6f, 0, -1}};
  for (int i = 0; i < 200000; ++i) {
    const auto g = ts::test::drawnLastFirst<3>([&] { return gauss(rng); });
    normals.emplace_back(glm::normalize(glm::dvec3(g[0], g[1], g[2])));
  }
  double worst = 0.0, worstHost = 0.0;
  for (size_t i = 0; i < normals.size(); ++i) {
    const glm::vec3 n = normals[i];
    const glm::dvec3 unit = glm::normalize(glm::dvec3(n));
    const uint32_t v = pk::encodeNormal(n);
    const double a = angleBetween(octahedralDecode(v), unit);
    worst = std::max(worst, a);
    // The host decoder (the kernel's float arithmetic) agrees with the double decoder.
    const glm::dvec3 host = glm::normalize(glm::dvec3(pk::decodeNormalUnnormalized(v)));
    worstHost = std::max(worstHost, glm::distance(host, octahedralDecode(v)));
    // "Correct rounding": no neighbouring lattice point decodes closer to n.
    const int x = int16_t(v & 0xffffu), y = int16_t(v >> 16);
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy) {
        if (std::abs(x + dx) > 32767 || std::abs(y + dy) > 32767) continue;
        uint32_t w = uint32_t(uint16_t(int16_t(x + dx))) | uint32_t(uint16_t(int16_t(y + dy)))
                                                               << 16;
        ASSERT_GE(angleBetween(octahedralDecode(w), unit), a - 2e-7) << i << " " << dx << dy;
      }
  }
  RecordProperty("worst_normal_error_rad", std::to_string(worst));
  EXPECT_LE(worst, pk::kMaxNormalErrorRad);  // docs/accuracy.md: <= 4.5e-5 rad (0.0026 deg)
  EXPECT_GT(worst, 1e-5);                    // 16-bit coordinates do lose something
  EXPECT_LT(worstHost, 1e-6);                // float decode vs double decode
}

TEST(GBufferLayout, PackedColoursAreUnorm8WithinHalfAStep) {
  namespace pk = ts::packed;
  GBuffer g;
  g.resize(64, 64);
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (size_t i = 0; i < g.pixelCount(); ++i) {
    g.depth[i] = 2.0f;
    g.normal[i] = glm::vec4(0, 0, 1, 0);
    const auto kd = ts::test::drawnLastFirst<3>([&] { return u(rng); });
    g.diffuse[i] = glm::vec4(kd[0], kd[1], kd[2], 1.0f);
    const auto ks = ts::test::drawnLastFirst<3>([&] { return u(rng); });
    g.specular[i] = glm::vec4(ks[0], ks[1], ks[2], 32.0f);
  }
  // Exact codes, the rounding midpoints and out-of-range values (clamped).
  g.diffuse[0] = glm::vec4(0.0f, 1.0f, 0.5f, 1.0f);            // 0, 255, 127.5 -> 128 (half up)
  g.diffuse[1] = glm::vec4(-0.3f, 1.7f, 1.0f / 255.0f, 0.0f);  // 0, 255, 1
  g.specular[0] = glm::vec4(0.04f, NAN, 0.001f, 32.0f);        // 10.2 -> 10, NaN -> 0, 0.255 -> 0
  EncodedGBuffer e = ts::encode(g, GBufferFormat::PACKED);
  EXPECT_EQ(u32At(e.diffuse, 0), 0u | 255u << 8 | 128u << 16 | 255u << 24);
  EXPECT_EQ(u32At(e.diffuse, 1), 0u | 255u << 8 | 1u << 16 | 0u << 24);
  EXPECT_EQ(u32At(e.specular, 0) & 0xffffffu, 10u);
  const ts::CameraIntrinsics cam = intrinsics(64, 64);
  double worst = 0.0;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      const size_t i = size_t(y) * 64 + x;
      const uint32_t d = u32At(e.diffuse, i), sp = u32At(e.specular, i);
      ts::SurfaceD s;
      ASSERT_TRUE(ts::decodeSurface(e, cam, x, y, s));
      for (int c = 0; c < 3; ++c) {
        // The decoder returns exactly float(byte) / 255.
        EXPECT_EQ(s.kd[c], double(float((d >> (8 * c)) & 255u) / 255.0f));
        EXPECT_EQ(s.ks[c], double(float((sp >> (8 * c)) & 255u) / 255.0f));
        if (i < 2) continue;  // the clamped and NaN ones above
        const double kd = g.diffuse[i][c], ks = g.specular[i][c];
        worst = std::max({worst, std::abs(s.kd[c] - kd), std::abs(s.ks[c] - ks)});
        // Stored byte = round(255 c) (independently: floor(255 c + 0.5) in double).
        EXPECT_EQ((d >> (8 * c)) & 255u, uint32_t(std::floor(255.0 * kd + 0.5)));
      }
    }
  RecordProperty("worst_colour_error", std::to_string(worst));
  EXPECT_LE(worst, pk::kMaxUnorm8Error);  // docs/accuracy.md: 0.5/255 (+ float rounding)
  EXPECT_GT(worst, 0.49 / 255.0);
  EXPECT_EQ(pk::encodeUnorm8(0.5f / 255.0f), 1);  // halfway rounds up
  EXPECT_EQ(pk::decodeUnorm8(255), 1.0f);
}

TEST(GBufferLayout, PackedShininessByteWithinItsRelativeBound) {
  namespace pk = ts::packed;
  // b = round(255 log2(clamp(s, 1, 2048)) / 11); s' = 2^(11 b / 255).
  EXPECT_EQ(pk::encodeShininess(1.0f), 0);
  EXPECT_EQ(pk::encodeShininess(2048.0f), 255);
  EXPECT_EQ(pk::encodeShininess(0.0f), 0);  // clamped to 1
  EXPECT_EQ(pk::encodeShininess(-5.0f), 0);
  EXPECT_EQ(pk::encodeShininess(1e6f), 255);  // clamped to 2048
  EXPECT_EQ(pk::encodeShininess(NAN), 0);
  EXPECT_EQ(pk::encodeShininess(32.0f), 116);  // 255 * 5 / 11 = 115.9
  EXPECT_EQ(pk::decodeShininess(0), 1.0f);
  EXPECT_NEAR(pk::decodeShininess(255), 2048.0, 2048.0 * 1e-6);
  double worst = 0.0;
  uint8_t last = 0;
  for (int k = 0; k <= 40000; ++k) {
    const float s = float(std::pow(2048.0, k / 40000.0));
    const uint8_t b = pk::encodeShininess(s);
    EXPECT_EQ(b, uint8_t(std::lround(255.0 * std::log2(double(s)) / 11.0))) << s;
    EXPECT_GE(b, last);  // monotonic
    last = b;
    worst = std::max(worst, std::abs(double(pk::decodeShininess(b)) / s - 1.0));
  }
  RecordProperty("worst_shininess_rel_error", std::to_string(worst));
  EXPECT_LE(worst, pk::kMaxShininessRelError);  // docs/accuracy.md: 2^(11/510) - 1 = 1.51%
  EXPECT_GT(worst, 0.015);
  // Through the G-buffer: the top byte of the specular plane.
  GBuffer g = sampleGBuffer();
  EncodedGBuffer e = ts::encode(g, GBufferFormat::PACKED);
  ts::SurfaceD s;
  ASSERT_TRUE(ts::decodeSurface(e, intrinsics(3, 2), 2, 0, s));
  EXPECT_EQ(u32At(e.specular, 2) >> 24, pk::encodeShininess(g.specular[2].w));
  EXPECT_EQ(s.gloss, double(pk::decodeShininess(uint8_t(u32At(e.specular, 2) >> 24))));
  EXPECT_NEAR(s.gloss, g.specular[2].w, g.specular[2].w * pk::kMaxShininessRelError);
}

TEST(GBufferLayout, PackedEmissiveIsHalfAndDepthFloat) {
  GBuffer g = sampleGBuffer();
  g.emissive[1] = glm::vec4(70000.0f, 1e-6f, -2.5f, 0.0f);  // clamped, subnormal half, exact
  EncodedGBuffer e = ts::encode(g, GBufferFormat::PACKED);
  EncodedGBuffer e16 = ts::encode(g, GBufferFormat::FP16);
  EXPECT_EQ(e.emissive, e16.emissive);  // the same half4 plane as the fp16 layout
  EXPECT_EQ(e.depth, g.depth);
  const ts::CameraIntrinsics cam = intrinsics(3, 2);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 3; ++x) {
      const size_t i = size_t(y) * 3 + x;
      ts::SurfaceD s;
      if (!ts::decodeSurface(e, cam, x, y, s)) continue;
      for (int c = 0; c < 3; ++c) {
        EXPECT_EQ(s.ke[c], halfToDouble(halfBits(e.emissive, i, c)));
        if (std::abs(g.emissive[i][c]) >= 6.2e-5f && std::abs(g.emissive[i][c]) <= ts::kMaxHalf) {
          EXPECT_LE(std::abs(s.ke[c] - g.emissive[i][c]), std::abs(g.emissive[i][c]) * 0x1p-11);
        }
      }
      EXPECT_NEAR(-s.P.z, double(g.depth[i]), 1e-15);
      // Normal and colours through the codecs.
      EXPECT_LE(angleBetween(s.N, glm::normalize(glm::dvec3(glm::vec3(g.normal[i])))),
                ts::packed::kMaxNormalErrorRad + 1e-7);
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(s.kd[c], std::clamp(g.diffuse[i][c], 0.0f, 1.0f), ts::packed::kMaxUnorm8Error);
    }
  ts::SurfaceD s;
  ASSERT_TRUE(ts::decodeSurface(e, cam, 1, 0, s));
  EXPECT_EQ(s.ke.x, double(ts::kMaxHalf));  // 70000 clamped, not inf
  EXPECT_EQ(s.ke.y, 17.0 * std::ldexp(1.0, -24));
  EXPECT_EQ(s.ke.z, -2.5);
}

TEST(GBufferLayout, DecodeRejectsMismatchedCameraAndOutOfRangePixels) {
  EncodedGBuffer e = ts::encode(sampleGBuffer(), GBufferFormat::FP32);
  ts::SurfaceD s;
  EXPECT_THROW(ts::decodeSurface(e, intrinsics(4, 2), 0, 0, s), ts::Error);
  EXPECT_THROW(ts::decodeSurface(e, intrinsics(3, 2), 3, 0, s), std::out_of_range);
  EXPECT_FALSE(ts::decodeSurface(e, intrinsics(3, 2), 1, 1, s));  // pixel 4: background
  EncodedGBuffer p = ts::encode(sampleGBuffer(), GBufferFormat::PACKED);
  EXPECT_THROW(ts::decodeSurface(p, intrinsics(3, 3), 0, 0, s), ts::Error);
  EXPECT_THROW(ts::decodeSurface(p, intrinsics(3, 2), 0, -1, s), std::out_of_range);
  EXPECT_FALSE(ts::decodeSurface(p, intrinsics(3, 2), 1, 1, s));
}

}  // namespace

namespace ts {
namespace {

// The packed normal's part of the exact round trip: every code the encoder can emit decodes (before
// the kernels' renormalisation) to a vector that encodes back to that code. The fold's edges,
// where two codes give one direction that only the sign of a zero component tells apart, are
// checked exhaustively; the rest at random.
TEST(GBufferImport, PackedNormalCodesReencodeToThemselves) {
  auto code = [](int x, int y) {
    return uint32_t(uint16_t(int16_t(x))) | uint32_t(uint16_t(int16_t(y))) << 16;
  };
  auto check = [&](int x, int y) {
    const uint32_t c = code(x, y);
    const uint32_t again = packed::encodeNormal(packed::decodeNormalUnnormalized(c));
    if (again != c) ADD_FAILURE() << "code (" << x << ", " << y << ") re-encodes to " << again;
    return again == c;
  };
  int failures = 0;
  for (int v = -32767; v <= 32767 && failures < 5; ++v)
    for (int edge : {-32767, 32767, 0}) failures += !check(v, edge) + !check(edge, v);
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> u(-32767, 32767);
  for (int i = 0; i < 2000000 && failures < 5; ++i) {
    const auto xy = test::drawnLastFirst<2>([&] { return u(rng); });
    failures += !check(xy[0], xy[1]);
  }
}

}  // namespace
}  // namespace ts
