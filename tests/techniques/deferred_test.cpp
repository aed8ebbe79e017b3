// Traditional deferred shading ("deferred", "deferred-stencil"; src/techniques/deferred.cpp):
// against the double reference on the built-in scenes, light rectangles conservative (also for
// lights around the camera and through the near plane), the stencil variant equal to the plain
// one with less work, and the work counters against brute counts.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <memory>
#include <string>

#include "reference/error_metrics.h"
#include "reference/reference.h"
#include "shading/shading_cpu.h"
#include "render/frame_setup.h"
#include "scene/scene_loader.h"
#include "techniques/technique.h"
#include "reference_check.h"
#include "test_support.h"

namespace ts {
namespace {

using test::builtinScene;
using test::Checked;
using test::kFp32RelativeTolerance;
using test::renderAndCheck;
using test::renderOnly;

Technique& deferred(GBufferFormat format, bool stencil) {
  TechniqueConfig config;
  config.format = format;
  return test::cachedTechnique(stencil ? "deferred-stencil" : "deferred", config);
}

ReferenceImage reference(const PreparedFrame& f) {
  return shadeReference(f.encoded, f.intrinsics, f.lights, f.ambient, 0);
}

int launches(const FrameResult& r, const std::string& kernel) {
  for (const auto& k : r.kernels)
    if (k.name == kernel) return k.launches;
  return 0;
}

bool empty(const glm::ivec4& r) { return r.z <= r.x || r.w <= r.y; }

std::string str(const glm::ivec4& r) {
  return "(" + std::to_string(r.x) + ", " + std::to_string(r.y) + ", " + std::to_string(r.z) +
         ", " + std::to_string(r.w) + ")";
}

// Brute counts, independent of the technique's rectangles: (geometry pixel, light) pairs whose
// float-reconstructed position lies strictly inside the light sphere (the stencil test), over
// the whole screen; `only` >= 0 restricts the count to that light.
uint64_t insidePairs(const PreparedFrame& f, int only = -1) {
  const auto& cam = f.intrinsics;
  uint64_t n = 0;
  for (int y = 0; y < cam.height; ++y)
    for (int x = 0; x < cam.width; ++x) {
      float depth = f.encoded.depth[size_t(y) * cam.width + x];
      if (depth <= 0.0f) continue;
      glm::vec3 p = shading_f::ts_view_position(x, y, depth, cam.tanHalfFovX, cam.tanHalfFovY,
                                                cam.width, cam.height);
      for (size_t i = 0; i < f.lights.size(); ++i) {
        if (only >= 0 && size_t(only) != i) continue;
        const glm::vec4& pr = f.lights.positionRange[i];
        glm::vec3 v = glm::vec3(pr) - p;
        n += shading_f::dot(v, v) < pr.w * pr.w;
      }
    }
  return n;
}

// Largest per-channel difference between two images.
double maxDifference(const std::vector<glm::vec4>& a, const std::vector<glm::vec4>& b) {
  double d = 0.0;
  for (size_t i = 0; i < a.size(); ++i)
    for (int c = 0; c < 3; ++c) d = std::max(d, double(std::abs(a[i][c] - b[i][c])));
  return d;
}

struct Case {
  std::string scene, lights;
  int frame;
  GBufferFormat format;
};

void PrintTo(const Case& k, std::ostream* os) {
  *os << k.scene << "/" << k.lights << " frame " << k.frame << " " << toString(k.format);
}

class DeferredMatchesReference : public ::testing::TestWithParam<Case> {};

// Both variants against the reference; the stencil variant against the plain one; the counters
// against brute counts on the same frame.
TEST_P(DeferredMatchesReference, BothVariantsWithinFp32RoundingWithConsistentCounters) {
  const Case& k = GetParam();
  PreparedFrame f = prepareFrame(builtinScene(k.scene, k.lights), k.frame, 200, 120, k.format);
  ASSERT_GT(f.gbuffer.geometryPixels(), f.gbuffer.pixelCount() / 4) << "camera sees little";
  ReferenceImage ref = reference(f);
  Checked plain = renderAndCheck(f, deferred(k.format, false), ref);
  Checked stencil = renderAndCheck(f, deferred(k.format, true), ref);
  for (const Checked* c : {&plain, &stencil}) {
    const char* which = c == &plain ? "deferred" : "deferred-stencil";
    EXPECT_EQ(c->missed, 0u) << which;
    EXPECT_LE(c->error.maxRelPeak, kFp32RelativeTolerance)
        << which << ": max abs " << c->error.maxAbs << " peak " << c->error.peak;
  }

  // The same contributions in the same light order: the stencil only skips exact zeros.
  EXPECT_LE(maxDifference(plain.result.image, stencil.result.image), 1e-6 * ref.peak);

  // Rectangles: the plain variant counts their on-screen area and shades their geometry pixels;
  // one launch per non-empty rectangle.
  const auto& rects = plain.result.assignment->lightRect;
  ASSERT_EQ(rects.size(), f.lights.size());
  EXPECT_TRUE(stencil.result.assignment->lightRect == rects);
  EXPECT_TRUE(plain.result.assignment->pixelBin.empty());
  uint64_t area = 0, geometryInRects = 0;
  int lit = 0;
  for (const auto& r : rects) {
    if (empty(r)) continue;
    ++lit;
    EXPECT_TRUE(r.x >= 0 && r.y >= 0 && r.z <= 200 && r.w <= 120) << str(r);
    area += uint64_t(r.z - r.x) * uint64_t(r.w - r.y);
    for (int y = r.y; y < r.w; ++y)
      for (int x = r.x; x < r.z; ++x) geometryInRects += f.encoded.depth[size_t(y) * 200 + x] > 0;
  }
  EXPECT_GT(lit, 0);
  EXPECT_EQ(launches(plain.result, "light"), lit);
  EXPECT_EQ(launches(stencil.result, "light"), lit);
  EXPECT_EQ(launches(plain.result, "base"), 1);
  const WorkCounters& pc = plain.result.counters;
  const WorkCounters& sc = stencil.result.counters;
  EXPECT_EQ(pc.lightingComputations, area);
  EXPECT_EQ(pc.evaluations, geometryInRects);

  // Stencil: exactly the pixels inside light volumes, found without the rectangles (so this also
  // says no inside pixel lies outside its light's rectangle); at most the plain variant's work.
  uint64_t inside = insidePairs(f);
  EXPECT_EQ(sc.lightingComputations, inside);
  EXPECT_EQ(sc.evaluations, inside);
  EXPECT_GE(inside, ref.contributing);  // every non-zero contribution lies inside its sphere
  EXPECT_LE(sc.evaluations, pc.evaluations);
  EXPECT_LT(sc.gbufferBytesRead, pc.gbufferBytesRead);

  // Bytes, from the access pattern: base pass + per covered pixel (see deferred.cpp).
  uint64_t pixels = f.encoded.pixelCount(), geometry = f.gbuffer.geometryPixels();
  uint64_t full = f.encoded.bytesPerPixel(), base = 4 * pixels + geometry * (full - 4);
  EXPECT_EQ(pc.gbufferBytesRead,
            base + 4 * (area - geometryInRects) + geometryInRects * (full + 16));
  EXPECT_EQ(sc.gbufferBytesRead, base + 4 * area + inside * (full - 4 + 16));
}

INSTANTIATE_TEST_SUITE_P(Builtins, DeferredMatchesReference,
                         ::testing::Values(Case{"street", "many", 0, GBufferFormat::FP32},
                                           Case{"street", "many", 60, GBufferFormat::FP16},
                                           Case{"atrium", "mixed", 0, GBufferFormat::FP16},
                                           Case{"atrium", "mixed", 90, GBufferFormat::FP32}),
                         [](const auto& info) {
                           const Case& k = info.param;
                           return k.scene + "_" + k.lights + "_f" + std::to_string(k.frame) + "_" +
                                  toString(k.format);
                         });

// Hand-placed view-space lights on a street frame: one around the camera (its rectangle must be
// the whole screen), one through the near plane beside the camera, one wholly behind it (never
// launched, empty rectangle).
TEST(DeferredNearPlane, LightAroundCameraCoversWholeScreen) {
  PreparedFrame f = prepareFrame(builtinScene("street", "few"), 0, 200, 120, GBufferFormat::FP32);
  float zn = f.intrinsics.znear;
  f.lights = ViewLights();
  f.lights.addPoint({0.3f, -0.2f, -0.5f * zn}, 40.0f, {30.0f, 25.0f, 20.0f});  // holds the camera
  f.lights.addPoint({3.0f, -1.6f, 0.0f}, 3.3f, {5.0f, 8.0f, 12.0f});  // straddles the near plane
  f.lights.addPoint({0.0f, 0.0f, 50.0f}, 3.0f, {100.0f, 100.0f, 100.0f});  // behind the camera
  ASSERT_GT(glm::length(glm::vec3(f.lights.positionRange[1])), f.lights.positionRange[1].w);
  ASSERT_GT(insidePairs(f, 1), 0u) << "the near-plane light reaches no geometry";
  ReferenceImage ref = reference(f);
  for (bool stencil : {false, true}) {
    Checked c = renderAndCheck(f, deferred(GBufferFormat::FP32, stencil), ref);
    const auto& rects = c.result.assignment->lightRect;
    ASSERT_EQ(rects.size(), 3u);
    EXPECT_TRUE(rects[0] == glm::ivec4(0, 0, 200, 120)) << str(rects[0]) << " stencil " << stencil;
    EXPECT_FALSE(empty(rects[1])) << str(rects[1]) << " stencil " << stencil;
    EXPECT_TRUE(empty(rects[2])) << str(rects[2]) << " stencil " << stencil;
    EXPECT_EQ(launches(c.result, "light"), 2);
    EXPECT_EQ(c.missed, 0u) << "stencil " << stencil;
    EXPECT_LE(c.error.maxRelPeak, kFp32RelativeTolerance) << "stencil " << stencil;
    if (!stencil) {
      EXPECT_GE(c.result.counters.lightingComputations, 200u * 120u);
    }
  }
  EXPECT_GT(ref.contributing, f.gbuffer.geometryPixels() / 2) << "the big light lights little";
}

// No lights: the base pass alone (emission + ambient), no light launches.
TEST(DeferredNoLights, BaseOnly) {
  PreparedFrame f = prepareFrame(builtinScene("atrium", "mixed"), 0, 96, 64, GBufferFormat::FP16);
  f.lights = ViewLights();
  ReferenceImage ref = reference(f);
  for (bool stencil : {false, true}) {
    Checked c = renderAndCheck(f, deferred(GBufferFormat::FP16, stencil), ref);
    EXPECT_EQ(launches(c.result, "light"), 0);
    EXPECT_EQ(c.missed, 0u);
    EXPECT_LE(c.error.maxRelPeak, kFp32RelativeTolerance);
    EXPECT_EQ(c.result.counters.evaluations, 0u);
    EXPECT_EQ(c.result.counters.lightingComputations, 0u);
  }
}

}  // namespace
}  // namespace ts
