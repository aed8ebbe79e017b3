// --msaa (issue #17): the forward techniques drawn into multisampled targets, shaded per
// fragment and resolved by OpenGL, against the per-sample reference (every sample's G-buffer
// shaded in double, averaged); the resolve against its samples; one sample against today's path;
// the refusals. llvmpipe, small frames; skips, saying why, without an OpenGL context or with
// fewer than 4 samples.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <map>

#include "gl_frame.h"
#include "raster/gl_rasterizer.h"
#include "render/pipeline_options.h"
#include "require_gl.h"
#include "scene/scene_loader.h"
#include "util/error.h"

namespace ts {
namespace {

// The forward family's bound (gl_tiled_forward_test.cpp): each sample's surface is the one the
// forward pass shades for it (the same fragment, interpolated at the same point), so the average
// of the samples' references is held to the same bound as a single-sampled frame.
constexpr double kForwardBound = 1e-4;
constexpr int kSamples = 4;

// The techniques that take --msaa (TechniqueInfo::multisamples).
const char* const kTechniques[] = {"tiled-forward", "tiled-forward-prez"};

const Scene& msaaScene(const std::string& name) {
  static std::map<std::string, Scene> cache;
  auto it = cache.find(name);
  if (it != cache.end()) return it->second;
  SceneOptions options;
  options.lightSet = name == "atrium" ? "small" : "few";
  return cache.emplace(name, loadScene("builtin:" + name, options)).first->second;
}

bool fewerSamplesThan(int samples) {
  GlRasterizer gl(msaaScene("atrium"));
  return gl.maxSamples() < samples;
}

#define REQUIRE_SAMPLES(n)                                       \
  do {                                                           \
    REQUIRE_GL();                                                \
    if (fewerSamplesThan(n))                                     \
      GTEST_SKIP() << "the OpenGL implementation renders fewer " \
                      "than "                                    \
                   << (n) << " samples";                         \
  } while (0)

struct MsaaFrame {
  test::GlFrame g;
  std::vector<EncodedGBuffer> samples;  // each sample's fp32 planes
  ReferenceImage reference;             // their references averaged
  std::vector<ReferenceImage> perSample;

  MsaaFrame(const Scene& scene, int w, int h, int n)
      : g(scene, 1, w, h, analyzeScene(scene, nativeShadingModel(scene)), n) {
    RasterOptions raster;
    raster.model = g.features.model;
    raster.normalMaps = g.features.normalMaps;
    raster.triangleIds = true;
    for (const GBuffer& b : g.forward->sampleGBuffers(raster)) {
      samples.push_back(encode(b, GBufferFormat::FP32));
      sampleTriangles.push_back(b.triangleId);
    }
    const PreparedFrame& f = g.prepared;
    for (const EncodedGBuffer& e : samples)
      perSample.push_back(shadeReference(e, f.intrinsics, f.lights, f.ambient, 0));
    reference = averageSamples(perSample);
  }
  std::vector<std::vector<int32_t>> sampleTriangles;
};

TEST(Msaa, ForwardTechniquesMatchThePerSampleReference) {
  REQUIRE_SAMPLES(kSamples);
  for (const char* name : {"atrium", "street"}) {
    MsaaFrame m(msaaScene(name), 96, 54, kSamples);
    ASSERT_EQ(m.samples.size(), size_t(kSamples));
    const PreparedFrame& f = m.g.prepared;
    for (const char* technique : kTechniques) {
      SCOPED_TRACE(std::string(technique) + " on " + name);
      const FrameResult r = m.g.render(technique);
      ASSERT_EQ(r.image.size(), f.encoded.pixelCount());
      const ErrorStats e =
          compareToReference(r.image, m.reference, kForwardBound * m.reference.peak);
      EXPECT_GT(m.reference.peak, 0.0);
      EXPECT_LE(e.maxRelPeak, kForwardBound);
      EXPECT_EQ(e.nonfinitePixels, 0u);
      ASSERT_TRUE(r.assignment.has_value());
      EXPECT_EQ(countMissedOverSamples(*r.assignment, m.samples, f.intrinsics, f.lights, 0), 0u);
      // The single-sample reference is not what an MSAA image is: its edges differ.
      const ReferenceImage one = shadeReference(f.encoded, f.intrinsics, f.lights, f.ambient, 0);
      const ErrorStats vsOne = compareToReference(r.image, one, kForwardBound * one.peak);
      EXPECT_GT(vsOne.maxRelPeak, kForwardBound);
      std::cout << "[ msaa ] " << technique << " " << name << " x" << kSamples << ": max error "
                << e.maxRelPeak << " of the peak against the per-sample "
                << "reference (" << vsOne.maxRelPeak << " against the single-sample one)\n";
    }
  }
}

// Pixels whose samples hold different triangles: the resolved value lies within its samples'
// reference shades (to the bound), and where they differ widely it is neither extreme, so the
// resolve mixes the samples (it does not pick one).
TEST(Msaa, AnEdgePixelLiesBetweenItsSamples) {
  REQUIRE_SAMPLES(kSamples);
  MsaaFrame m(msaaScene("street"), 96, 54, kSamples);
  const FrameResult r = m.g.render("tiled-forward");
  const double slack = kForwardBound * m.reference.peak;
  size_t edges = 0, mixed = 0;
  for (size_t i = 0; i < r.image.size(); ++i) {
    bool edge = false;
    for (int k = 1; k < kSamples; ++k) edge |= m.sampleTriangles[k][i] != m.sampleTriangles[0][i];
    if (!edge) continue;
    ++edges;
    bool wide = false, inside = true;
    for (int c = 0; c < 3; ++c) {
      double lo = 1e300, hi = -1e300;
      for (int k = 0; k < kSamples; ++k) {
        lo = std::min(lo, m.perSample[k].rgb[i][c]);
        hi = std::max(hi, m.perSample[k].rgb[i][c]);
      }
      const double v = r.image[i][c];
      EXPECT_GE(v, lo - slack) << "pixel " << i << " channel " << c;
      EXPECT_LE(v, hi + slack) << "pixel " << i << " channel " << c;
      if (hi - lo > 100.0 * slack) {
        wide = true;
        inside = inside && v > lo + slack && v < hi - slack;
      }
    }
    if (wide && inside) ++mixed;
  }
  EXPECT_GT(edges, 0u);
  EXPECT_GT(mixed, 0u);
  std::cout << "[ msaa ] street x" << kSamples << ": " << edges << " edge pixels, " << mixed
            << " strictly between their samples\n";
}

// Pixels whose samples all hold one triangle: the four samples hold the one fragment's colour,
// so the resolve is that colour, the single-sampled frame's to float rounding.
TEST(Msaa, AFlatInteriorPixelEqualsTheSingleSampleValue) {
  REQUIRE_SAMPLES(kSamples);
  MsaaFrame m(msaaScene("atrium"), 96, 54, kSamples);
  test::GlFrame one(msaaScene("atrium"), 1, 96, 54);
  for (const char* technique : kTechniques) {
    SCOPED_TRACE(technique);
    const FrameResult multi = m.g.render(technique);
    const FrameResult single = one.render(technique);
    size_t interior = 0;
    double worst = 0.0;
    for (size_t i = 0; i < multi.image.size(); ++i) {
      bool flat = m.sampleTriangles[0][i] >= 0;
      for (int k = 1; k < kSamples; ++k) flat &= m.sampleTriangles[k][i] == m.sampleTriangles[0][i];
      if (!flat) continue;
      ++interior;
      for (int c = 0; c < 3; ++c)
        worst = std::max(worst, double(std::abs(multi.image[i][c] - single.image[i][c])));
    }
    EXPECT_GT(interior, multi.image.size() / 4);  // most geometry pixels (the atrium: 41 %)
    EXPECT_LE(worst, 1e-6 * m.reference.peak);
  }
}

// --msaa 1 is the single-sampled path: its sample G-buffer is the frame's own, bit for bit.
TEST(Msaa, OneSampleIsTheSingleSampledGBuffer) {
  REQUIRE_GL();
  test::GlFrame g(msaaScene("atrium"), 1, 96, 54);
  ASSERT_EQ(g.forward->samples(), 1);
  RasterOptions raster;
  raster.model = g.features.model;
  raster.normalMaps = g.features.normalMaps;
  const std::vector<GBuffer> samples = g.forward->sampleGBuffers(raster);
  ASSERT_EQ(samples.size(), 1u);
  EXPECT_EQ(samples[0].depth, g.prepared.gbuffer.depth);
  EXPECT_EQ(samples[0].diffuse, g.prepared.gbuffer.diffuse);
}

// forward's and forward-single's passes with MSAA, given lists that hold every light for every
// batch (conservative however far a fragment is extrapolated; the techniques' own box-culled
// lists are not, so they refuse --msaa): the per-sample visible-triangle mask of forward's light
// passes and the per-sample batch ids, against the per-sample reference.
TEST(Msaa, ForwardPassesWithCompleteListsMatchThePerSampleReference) {
  REQUIRE_SAMPLES(kSamples);
  const Scene& scene = msaaScene("atrium");
  MsaaFrame m(scene, 96, 54, kSamples);
  const PreparedFrame& f = m.g.prepared;
  GlRasterizer gl(scene);
  ForwardLighting lighting;
  lighting.lights = &f.lights;
  lighting.ambient = f.ambient;
  lighting.features = m.g.features;
  lighting.samples = kSamples;
  const size_t batches = gl.batchCount(), lights = f.lights.size();
  auto everything = [](size_t lists, size_t entries) {
    IndexLists l;
    for (size_t i = 0; i < lists; ++i) {
      l.offsets.push_back(uint32_t(l.items.size()));
      l.counts.push_back(uint32_t(entries));
      for (size_t k = 0; k < entries; ++k) l.items.push_back(uint32_t(k));
    }
    return l;
  };
  const ForwardImage multi =
      gl.multiPassForward(f.camera, 96, 54, lighting, everything(lights, batches));
  const ForwardImage single =
      gl.singlePassForward(f.camera, 96, 54, lighting, everything(batches, lights));
  for (const ForwardImage* image : {&multi, &single}) {
    SCOPED_TRACE(image == &multi ? "forward's passes" : "forward-single's pass");
    const ErrorStats e =
        compareToReference(image->image, m.reference, kForwardBound * m.reference.peak);
    EXPECT_LE(e.maxRelPeak, kForwardBound);
    EXPECT_EQ(e.nonfinitePixels, 0u);
    // One batch id plane per sample, each sample's surface's (background -1 where the sample's
    // G-buffer has none).
    ASSERT_EQ(image->pixelBatch.size(), f.encoded.pixelCount() * kSamples);
    for (size_t k = 0; k < size_t(kSamples); ++k)
      for (size_t i = 0; i < f.encoded.pixelCount(); ++i)
        EXPECT_EQ(image->pixelBatch[k * f.encoded.pixelCount() + i] < 0,
                  m.sampleTriangles[k][i] < 0);
  }
}

// The techniques without --msaa refuse such a frame in one line; the ones with it say so.
TEST(Msaa, TechniquesWithoutItRefuseAMultisampledFrame) {
  REQUIRE_SAMPLES(2);
  test::GlFrame g(msaaScene("atrium"), 1, 96, 54,
                  analyzeScene(msaaScene("atrium"), nativeShadingModel(msaaScene("atrium"))), 2);
  for (const TechniqueInfo& t : techniqueRegistry()) {
    SCOPED_TRACE(t.name);
    EXPECT_EQ(t.multisamples, t.name == "tiled" || t.name == "clustered" ||
                                  t.name == "tiled-forward" || t.name == "tiled-forward-prez");
    if (t.multisamples) continue;
    try {
      g.render(t.name);
      ADD_FAILURE() << "rendered a 2-sample frame";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("--msaa 2"), std::string::npos) << e.what();
    }
  }
}

TEST(Msaa, BadSampleCountsAreRefused) {
  for (int bad : {0, 3, 5, 16, -4}) EXPECT_THROW(checkMsaa(bad, RasterBackend::Gl), Error);
  EXPECT_THROW(checkMsaa(4, RasterBackend::Software), Error);
  EXPECT_NO_THROW(checkMsaa(1, RasterBackend::Software));
  for (int good : {1, 2, 4, 8}) EXPECT_NO_THROW(checkMsaa(good, RasterBackend::Gl));
}

TEST(Msaa, MoreSamplesThanOpenGLGivesAreRefused) {
  REQUIRE_GL();
  GlRasterizer gl(msaaScene("atrium"));
  const int most = gl.maxSamples();
  EXPECT_GE(most, 1);
  EXPECT_THROW(gl.checkSamples(2 * most), Error);
  EXPECT_NO_THROW(gl.checkSamples(most));
}

}  // namespace
}  // namespace ts
