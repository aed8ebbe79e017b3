// --msaa for `tiled` and `clustered` (issue #17): the multisampled G-buffer (one plane per sample,
// in the frame's layout), the edge mask (kernels/msaa_edges.h: samples whose stored planes differ
// in any bit) and the edges shaded per sample, against the per-sample reference (every sample's
// G-buffer in the same layout shaded in double, averaged). llvmpipe rasterizes, PoCL shades; 96x54
// frames; skips, saying why, without an OpenGL context or with fewer than 4 samples.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <iostream>
#include <map>

#include "gl_frame.h"
#include "raster/gl_rasterizer.h"
#include "require_gl.h"
#include "scene/scene_loader.h"
#include "util/error.h"

namespace ts {
namespace {

constexpr double kBound = 1e-4;  // --check's: of the reference's peak, 0 missed
constexpr int kSamples = 4;

const Scene& builtin(const std::string& name) {
  static std::map<std::string, Scene> cache;
  auto it = cache.find(name);
  if (it != cache.end()) return it->second;
  SceneOptions options;
  options.lightSet = name == "atrium" ? "small" : "few";
  return cache.emplace(name, loadScene("builtin:" + name, options)).first->second;
}

#define REQUIRE_SAMPLES(n)                                                                  \
  do {                                                                                      \
    REQUIRE_GL();                                                                           \
    if (GlRasterizer(builtin("atrium")).maxSamples() < (n))                                 \
      GTEST_SKIP() << "the OpenGL implementation renders fewer than " << (n) << " samples"; \
  } while (0)

// A frame of `scene` with 4 samples in `format`, and its per-sample reference in that layout.
struct TiledMsaaFrame {
  test::GlFrame g;
  ReferenceImage reference;

  TiledMsaaFrame(const Scene& scene, int w, int h, GBufferFormat format, int frame = 1)
      : g(scene, frame, w, h, analyzeScene(scene, nativeShadingModel(scene)), kSamples, format) {
    const PreparedFrame& f = g.prepared;
    reference = shadeSampleAverage(planes(), f.intrinsics, f.lights, f.ambient, 0,
                                   ReferencePositions::FromDepth, nullptr);
  }
  const std::vector<EncodedGBuffer>& planes() const {
    return g.sampleGBuffers->like(g.prepared.encoded);
  }
  FrameResult render(int lanes, const std::string& technique = "tiled") const {
    TechniqueConfig c = g.config();
    c.format = g.prepared.encoded.format;
    c.lanes = lanes;
    return g.render(*createTechnique(technique, test::context(), c));
  }
  // r within the bound of the per-sample reference, no NaN, 0 missed; returns the error.
  double expectMatches(const FrameResult& r) const {
    const PreparedFrame& f = g.prepared;
    EXPECT_GT(reference.peak, 0.0);
    const ErrorStats e = compareToReference(r.image, reference, kBound * reference.peak);
    EXPECT_LE(e.maxRelPeak, kBound);
    EXPECT_EQ(e.nonfinitePixels, 0u);
    EXPECT_TRUE(r.assignment.has_value());
    if (r.assignment) {
      EXPECT_EQ(countMissedOverSamples(*r.assignment, planes(), f.intrinsics, f.lights, 0), 0u);
    }
    return e.maxRelPeak;
  }
};

uint64_t edgesOf(const FrameResult& r) {
  EXPECT_TRUE(r.counters.sampleShading.has_value());
  return r.counters.sampleShading ? r.counters.sampleShading->pixelsShadedPerSample : 0;
}

TEST(TiledMsaa, MatchesThePerSampleReference) {
  REQUIRE_SAMPLES(kSamples);
  for (const char* name : {"atrium", "street"}) {
    SCOPED_TRACE(name);
    const TiledMsaaFrame m(builtin(name), 96, 54, GBufferFormat::FP32);
    const FrameResult r = m.render(0);
    const double error = m.expectMatches(r);
    const uint64_t edges = edgesOf(r), pixels = r.image.size();
    EXPECT_GT(edges, 0u);
    EXPECT_LT(edges, pixels);
    // The G-buffer on the device: every sample's planes.
    EXPECT_EQ(r.counters.sampleShading->samples, kSamples);
    EXPECT_EQ(r.counters.sampleShading->gbufferBytes,
              uint64_t(kSamples) * pixels * m.g.prepared.encoded.bytesPerPixel());
    // The single-sample reference is not what an MSAA image is: its edges differ.
    const PreparedFrame& f = m.g.prepared;
    const ReferenceImage one = shadeReference(f.encoded, f.intrinsics, f.lights, f.ambient, 0);
    EXPECT_GT(compareToReference(r.image, one, kBound * one.peak).maxRelPeak, kBound);
    std::cout << "[ tiled msaa ] " << name << " x" << kSamples << ": " << edges << " of " << pixels
              << " pixels shaded per sample, max error " << error
              << " of the peak against the per-sample reference\n";
  }
}

// Every G-buffer layout and lanes width, at an odd size (partial tiles, a lanes vector across
// the frame's edge): the same bound, and the same edges whatever the lanes.
TEST(TiledMsaa, EveryLayoutAndLanesWidth) {
  REQUIRE_SAMPLES(kSamples);
  for (GBufferFormat format : {GBufferFormat::FP32, GBufferFormat::FP16, GBufferFormat::PACKED}) {
    const TiledMsaaFrame m(builtin("street"), 67, 37, format);
    std::optional<uint64_t> edges;
    for (int lanes : {1, 4, 8, 16}) {
      if (format != GBufferFormat::FP32 && (lanes == 4 || lanes == 8)) continue;  // time
      SCOPED_TRACE(toString(format) + ", lanes " + std::to_string(lanes));
      const FrameResult r = m.render(lanes);
      m.expectMatches(r);
      if (!edges) edges = edgesOf(r);
      EXPECT_EQ(edgesOf(r), *edges);
    }
  }
}

// clustered: every sample in its own cluster (the slices and bounds over every sample's depth),
// in every layout and lanes width at an odd size, against the same per-sample reference; its
// edges are tiled's (the same G-buffer, the same rule), and it shades each edge sample once.
TEST(ClusteredMsaa, EveryLayoutAndLanesWidthMatchesThePerSampleReference) {
  REQUIRE_SAMPLES(kSamples);
  for (const char* name : {"atrium", "street"})
    for (GBufferFormat format : {GBufferFormat::FP32, GBufferFormat::FP16, GBufferFormat::PACKED}) {
      if (format != GBufferFormat::FP32 && std::string(name) == "atrium") continue;  // time
      const TiledMsaaFrame m(builtin(name), 67, 37, format);
      const uint64_t edges = edgesOf(m.render(1));
      EXPECT_GT(edges, 0u);
      for (int lanes : {1, 16}) {
        SCOPED_TRACE(std::string(name) + ", " + toString(format) + ", lanes " +
                     std::to_string(lanes));
        const FrameResult r = m.render(lanes, "clustered");
        const double error = m.expectMatches(r);
        EXPECT_EQ(edgesOf(r), edges);
        EXPECT_EQ(r.counters.sampleShading->gbufferBytes,
                  uint64_t(kSamples) * r.image.size() * m.g.prepared.encoded.bytesPerPixel());
        // The assignment holds one plane of clusters per sample (countMissedOverSamples).
        ASSERT_TRUE(r.assignment.has_value());
        EXPECT_EQ(r.assignment->pixelBin.size(), r.image.size() * kSamples);
        if (lanes == 1 && format == GBufferFormat::FP32)
          std::cout << "[ clustered msaa ] " << name << " x" << kSamples << ": " << edges
                    << " edge pixels, max error " << error << " of the peak\n";
      }
    }
}

// One triangle filling the view, lit by two lights: every sample of every pixel holds the same
// stored surface, so no pixel is an edge and the image is the single-sampled frame's, bit for
// bit (sample 0's G-buffer is the single-sampled one: both interpolate at the pixel centre).
Scene flatWall() {
  Scene s;
  s.name = "flat-wall";
  s.materials.push_back(Material{});
  const glm::vec3 n(0.0f, 0.0f, 1.0f);
  s.vertices = {{{-100.0f, -100.0f, -5.0f}, n, {0.0f, 0.0f}},
                {{100.0f, -100.0f, -5.0f}, n, {1.0f, 0.0f}},
                {{0.0f, 100.0f, -5.0f}, n, {0.5f, 1.0f}}};
  s.indices = {0, 1, 2};
  s.triangleMaterial = {0};
  s.lights.push_back(SceneLight::point({-1.0, 0.5, -3.0}, glm::vec3(2.0f), 6.0f));
  s.lights.push_back(SceneLight::point({1.5, -0.5, -4.0}, glm::vec3(1.0f, 0.5f, 0.2f), 4.0f));
  s.cameraPath.push_back(
      SceneCamera::lookAt({0.0, 0.0, 0.0}, {0.0, 0.0, -1.0}, {0.0, 1.0, 0.0}, 1.0f, 0.1f, 50.0f));
  return s;
}

TEST(TiledMsaa, AFlatWallHasNoEdgesAndIsTheSingleSampledImage) {
  REQUIRE_SAMPLES(kSamples);
  const Scene wall = flatWall();
  const TiledMsaaFrame m(wall, 96, 54, GBufferFormat::FP32, 0);
  const test::GlFrame one(wall, 0, 96, 54);
  for (int lanes : {1, 16}) {
    SCOPED_TRACE("lanes " + std::to_string(lanes));
    const FrameResult r = m.render(lanes);
    EXPECT_EQ(edgesOf(r), 0u);
    TechniqueConfig c = one.config();
    c.lanes = lanes;
    for (const char* technique : {"tiled", "clustered"}) {
      SCOPED_TRACE(technique);
      const FrameResult ms = m.render(lanes, technique);
      EXPECT_EQ(edgesOf(ms), 0u);
      const FrameResult single = one.render(*createTechnique(technique, test::context(), c));
      ASSERT_EQ(ms.image.size(), single.image.size());
      size_t differ = 0;
      for (size_t i = 0; i < ms.image.size(); ++i) differ += ms.image[i] != single.image[i];
      EXPECT_EQ(differ, 0u);
      EXPECT_EQ(single.image[single.image.size() / 2].x > 0.0f, true);  // lit
      // Shading per sample counts no more than shading per pixel.
      EXPECT_EQ(ms.counters.evaluations, single.counters.evaluations);
    }
  }
}

// The rule measured (docs/techniques.md "MSAA"): Lauritzen's thresholds (depth beyond 1e-3 of
// sample 0's, normals 0.999 apart, material terms beyond 1/255) against the exact rule's edges,
// and what shading those pixels once would cost in accuracy (the per-sample references' mean
// against sample 0's). The exact rule flags a superset.
TEST(TiledMsaa, ThresholdRuleAgainstTheExactOne) {
  REQUIRE_SAMPLES(kSamples);
  for (const char* name : {"atrium", "street"}) {
    const TiledMsaaFrame m(builtin(name), 96, 54, GBufferFormat::FP32);
    const FrameResult r = m.render(0);
    const std::vector<EncodedGBuffer>& s = m.planes();
    const PreparedFrame& f = m.g.prepared;
    std::vector<ReferenceImage> perSample;
    for (const EncodedGBuffer& e : s)
      perSample.push_back(shadeReference(e, f.intrinsics, f.lights, f.ambient, 0));
    const ReferenceImage mean = averageSamples(perSample);
    uint64_t threshold = 0, exact = 0;
    double worst = 0.0;
    for (size_t i = 0; i < r.image.size(); ++i) {
      bool differs = false, beyond = false;
      for (size_t k = 1; k < s.size(); ++k) {
        const float z0 = s[0].depth[i], z = s[k].depth[i];
        bool bits = std::memcmp(&z0, &z, sizeof z) != 0;
        bool far = (z0 > 0.0f) != (z > 0.0f) || std::abs(z - z0) > 1e-3f * z0;
        for (GBufferPlane p : {GBufferPlane::Normal, GBufferPlane::Diffuse, GBufferPlane::Specular,
                               GBufferPlane::Emissive}) {
          const glm::vec4 a = decodeStored(s[0], p, i), b = decodeStored(s[k], p, i);
          bits |= a != b;
          if (p == GBufferPlane::Normal)
            far |= glm::dot(glm::vec3(a), glm::vec3(b)) <
                   0.999f * glm::length(glm::vec3(a)) * glm::length(glm::vec3(b));
          else
            for (int c = 0; c < 4; ++c) far |= std::abs(a[c] - b[c]) > 1.0f / 255.0f;
        }
        differs |= bits;
        beyond |= far;
      }
      exact += differs;
      threshold += beyond;
      EXPECT_TRUE(differs || !beyond);
      if (differs && !beyond)
        for (int c = 0; c < 3; ++c)
          worst = std::max(worst, std::abs(mean.rgb[i][c] - perSample[0].rgb[i][c]));
    }
    EXPECT_EQ(exact, edgesOf(r));
    std::cout << "[ tiled msaa ] " << name << ": exact rule " << exact
              << " edge pixels, thresholds " << threshold << "; the " << exact - threshold
              << " pixels the thresholds shade once would be off by up to "
              << worst / m.reference.peak << " of the peak\n";
  }
}

// A technique shading the multisampled frame without its per-sample G-buffer says so.
TEST(TiledMsaa, AFrameWithoutItsSampleGBuffersIsRefused) {
  REQUIRE_SAMPLES(2);
  const Scene& scene = builtin("atrium");
  test::GlFrame g(scene, 1, 40, 24, analyzeScene(scene, nativeShadingModel(scene)), 2);
  DeviceFrame frame = g.upload(g.prepared.lights);
  frame.samples = nullptr;
  for (const char* name : {"tiled", "clustered"}) {
    auto technique = createTechnique(name, test::context(), g.config());
    try {
      technique->render(frame, FrameRequest{});
      ADD_FAILURE() << name << " rendered without the per-sample G-buffer";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("no per-sample G-buffer"), std::string::npos)
          << e.what();
    }
  }
}

}  // namespace
}  // namespace ts
