#pragma once
// A frame rasterized by OpenGL together with its scene to draw (DeviceFrame::forward), as render
// and bench hand one to the forward techniques: the fixture of the tests of those techniques.
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "raster/forward_scene.h"
#include "raster/raster_backend.h"
#include "raster/sample_gbuffers.h"
#include "reference/error_metrics.h"
#include "reference/reference.h"
#include "render/frame_setup.h"
#include "render/receiver_rounding.h"
#include "scene/scene_features.h"
#include "techniques/technique.h"
#include "test_support.h"

namespace ts::test {

// Lives as long as its parts (the rasterizer's context holds the scene's geometry).
struct GlFrame {
  SceneRasterizer rasterizer;
  SceneFeatures features;
  PreparedFrame prepared;
  std::unique_ptr<ForwardScene> forward;
  std::unique_ptr<SampleGBuffers> sampleGBuffers;  // --msaa (samples > 1) only

  // The scene's own features (analyzeScene), or the ones given.
  GlFrame(const Scene& scene, int frame, int w, int h)
      : GlFrame(scene, frame, w, h, analyzeScene(scene, nativeShadingModel(scene))) {}
  // samples: --msaa's (the forward passes' targets, tiled's per-sample G-buffer); format: the
  // G-buffer's layout.
  GlFrame(const Scene& scene, int frame, int w, int h, const SceneFeatures& f, int samples = 1,
          GBufferFormat format = GBufferFormat::FP32)
      : rasterizer(scene, RasterBackend::Gl),
        features(f),
        prepared(prepareFrame(rasterizer, frame, w, h, format, features)),
        forward(rasterizer.forwardScene(prepared.camera, w, h, samples)) {
    if (samples > 1) sampleGBuffers = std::make_unique<SampleGBuffers>(*forward, features);
  }

  // The frame on the device with `lights`, its scene to draw attached.
  DeviceFrame upload(const ViewLights& lights) const {
    DeviceFrame frame = DeviceFrame::upload(context(), prepared.encoded, prepared.intrinsics,
                                            lights, prepared.ambient);
    frame.forward = forward.get();
    frame.samples = sampleGBuffers.get();
    return frame;
  }
  TechniqueConfig config() const {
    TechniqueConfig c;
    c.features = features;
    return c;
  }
  // One frame of `t` (kept, so a test can render it again), its light lists kept
  // (FrameResult::assignment).
  FrameResult render(Technique& t, const ViewLights& lights) const {
    DeviceFrame frame = upload(lights);
    FrameRequest request;
    request.wantAssignment = true;
    return t.render(frame, request);
  }
  FrameResult render(Technique& t) const { return render(t, prepared.lights); }
  // `technique` built for these features.
  FrameResult render(const std::string& technique, const ViewLights& lights) const {
    return render(*createTechnique(technique, context(), config()), lights);
  }
  FrameResult render(const std::string& technique) const {
    return render(technique, prepared.lights);
  }
};

// A forward frame `r` of g against the double reference of g's own G-buffer (the same surfaces):
// max error <= `bound` of the peak, no NaN, no missed light contribution. Returns the error.
inline ErrorStats expectMatchesReference(const GlFrame& g, const FrameResult& r, double bound) {
  const PreparedFrame& f = g.prepared;
  const ReceiverRounding rounding = receiverRounding(g.rasterizer.scene(), f.camera.viewFromWorld);
  const ReferenceImage ref = shadeReference(f.encoded, f.intrinsics, f.lights, f.ambient, 0, 0, {},
                                            ReferencePositions::FromDepth, nullptr, &rounding);
  EXPECT_GT(ref.peak, 0.0);
  const ErrorStats e = compareToReference(r.image, ref, bound * ref.peak, ReceiverSlack::Allow);
  EXPECT_LE(e.maxRelPeak, bound);
  EXPECT_EQ(e.nonfinitePixels, 0u);
  EXPECT_TRUE(r.assignment.has_value());
  if (r.assignment) {
    EXPECT_EQ(countMissedContributions(*r.assignment, f.encoded, f.intrinsics, f.lights, 0), 0u);
  }
  return e;
}

}  // namespace ts::test
