// tiled's and clustered's --msaa kernels (kernels/msaa_edges.h, shade_tiled_edge_samples,
// shade_clustered_edge_samples, cluster_depth_bounds over every sample) without OpenGL, so
// that Oclgrind can run them (tests/extra_tests.cmake, Oclgrind.tiled.msaa: OpenGL's llvmpipe
// and Oclgrind do not run in one process): a software-rasterized frame whose "samples" are its
// G-buffer and the same G-buffer shifted by a pixel (every sample a real surface; edges wherever
// neighbours differ; for clustered, samples in slices sample 0 never holds), against the
// per-sample reference, every layout, lanes 1 and 16.
#include <gtest/gtest.h>

#include <stdexcept>

#include "raster/sample_gbuffers.h"
#include "reference/error_metrics.h"
#include "reference/reference.h"
#include "render/frame_setup.h"
#include "scene/scene_loader.h"
#include "techniques/technique.h"
#include "test_support.h"

namespace ts {
namespace {

// Only what SampleGBuffers, tiled and clustered ask of a multisampled frame.
class ShiftedSamples : public ForwardScene {
 public:
  explicit ShiftedSamples(const GBuffer& g) : g_(g) {}
  int samples() const override { return 2; }
  std::vector<GBuffer> sampleGBuffers(const RasterOptions&) override {
    GBuffer shifted = g_;
    for (int y = 0; y < g_.height; ++y)
      for (int x = 0; x + 1 < g_.width; ++x) {
        const size_t to = size_t(y) * size_t(g_.width) + size_t(x), from = to + 1;
        shifted.depth[to] = g_.depth[from];
        shifted.normal[to] = g_.normal[from];
        shifted.diffuse[to] = g_.diffuse[from];
        shifted.specular[to] = g_.specular[from];
        shifted.emissive[to] = g_.emissive[from];
      }
    return {g_, shifted};
  }
  size_t transparentDraws() const override { return 0; }
  [[noreturn]] static void unused() { throw std::logic_error("not drawn in this test"); }
  std::vector<float> depthPrepass(double&) override { unused(); }
  ForwardImage tiledForward(const ViewLights&, glm::vec3, const SceneFeatures&, int,
                            const ForwardLightGrid&, bool, const ForwardLightGrid*) override {
    unused();
  }
  ForwardImage transparentOver(const std::vector<glm::vec4>&, const ViewLights&, glm::vec3,
                               const SceneFeatures&, int, const ForwardLightGrid&) override {
    unused();
  }
  std::vector<TransparentFragment> captureTransparent(const SceneFeatures&, size_t) override {
    unused();
  }
  std::vector<ViewBox> batchBoxes() override { unused(); }
  ForwardImage multiPassForward(const ViewLights&, glm::vec3, const SceneFeatures&, int,
                                const IndexLists&) override {
    unused();
  }
  ForwardImage singlePassForward(const ViewLights&, glm::vec3, const SceneFeatures&, int,
                                 const IndexLists&) override {
    unused();
  }

 private:
  const GBuffer& g_;
};

TEST(TiledMsaaKernels, ShiftedSamplesMatchThePerSampleReference) {
  SceneOptions options;
  options.lightSet = "few";
  const Scene scene = loadScene("builtin:street", options);
  const SceneFeatures features = analyzeScene(scene, nativeShadingModel(scene));
  for (GBufferFormat format : {GBufferFormat::FP32, GBufferFormat::FP16, GBufferFormat::PACKED}) {
    const PreparedFrame f = prepareFrame(scene, 1, 37, 21, format, features);
    ShiftedSamples forward(f.gbuffer);
    SampleGBuffers samples(forward, features);
    const ReferenceImage reference =
        shadeSampleAverage(samples.like(f.encoded), f.intrinsics, f.lights, f.ambient, 0,
                           ReferencePositions::FromDepth, nullptr);
    for (int lanes : {1, 16})
      for (const char* technique : {"tiled", "clustered"}) {
        SCOPED_TRACE(std::string(technique) + ", " + toString(format) + ", lanes " +
                     std::to_string(lanes));
        TechniqueConfig c;
        c.features = features;
        c.format = format;
        c.lanes = lanes;
        DeviceFrame frame =
            DeviceFrame::upload(test::context(), f.encoded, f.intrinsics, f.lights, f.ambient);
        frame.forward = &forward;
        frame.samples = &samples;
        FrameRequest request;
        request.wantAssignment = true;
        const FrameResult r =
            createTechnique(technique, test::context(), c)->render(frame, request);
        const ErrorStats e = compareToReference(r.image, reference, 1e-4 * reference.peak);
        EXPECT_LE(e.maxRelPeak, 1e-4);
        EXPECT_EQ(e.nonfinitePixels, 0u);
        ASSERT_TRUE(r.counters.sampleShading.has_value());
        EXPECT_GT(r.counters.sampleShading->pixelsShadedPerSample, 0u);
        EXPECT_LT(r.counters.sampleShading->pixelsShadedPerSample, r.image.size());
        ASSERT_TRUE(r.assignment.has_value());
        EXPECT_EQ(countMissedOverSamples(*r.assignment, samples.like(f.encoded), f.intrinsics,
                                         f.lights, 0),
                  0u);
      }
  }
}

}  // namespace
}  // namespace ts
