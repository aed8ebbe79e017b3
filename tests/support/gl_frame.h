#pragma once
// A frame rasterized by OpenGL together with its scene to draw (DeviceFrame::forward), as render
// and bench hand one to the forward techniques: the fixture of the tests of those techniques.
#include <memory>
#include <string>

#include "raster/forward_scene.h"
#include "raster/raster_backend.h"
#include "render/frame_setup.h"
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

  // The scene's own features (analyzeScene), or the ones given.
  GlFrame(const Scene& scene, int frame, int w, int h)
      : GlFrame(scene, frame, w, h, analyzeScene(scene, nativeShadingModel(scene))) {}
  GlFrame(const Scene& scene, int frame, int w, int h, const SceneFeatures& f)
      : rasterizer(scene, RasterBackend::Gl),
        features(f),
        prepared(prepareFrame(rasterizer, frame, w, h, GBufferFormat::FP32, features)),
        forward(rasterizer.forwardScene(prepared.camera, w, h)) {}

  // The frame on the device with `lights`, its scene to draw attached.
  DeviceFrame upload(const ViewLights& lights) const {
    DeviceFrame frame = DeviceFrame::upload(context(), prepared.encoded, prepared.intrinsics,
                                            lights, prepared.ambient);
    frame.forward = forward.get();
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

}  // namespace ts::test
