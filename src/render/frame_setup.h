#pragma once
// Host-side preparation of one frame: camera, rasterized and encoded G-buffer, view-space lights.
// Shared by `render`, `bench` and the tests.
#include <string>

#include "gbuffer/gbuffer.h"
#include "gbuffer/gbuffer_layout.h"
#include "raster/raster_backend.h"
#include "scene/scene.h"
#include "scene/scene_features.h"
#include "techniques/device_frame.h"

namespace ts {

struct PreparedFrame {
  int frame = 0;
  SceneCamera camera;
  CameraIntrinsics intrinsics;
  GBuffer gbuffer;         // full precision, as rasterized
  EncodedGBuffer encoded;  // what the kernels read
  ViewLights lights;       // view space
  glm::vec3 ambient{0.0f};
  SceneFeatures features;  // what the G-buffer and the kernels model
  double rasterMs = 0.0;
  RasterBackend raster = RasterBackend::Software;  // which rasterizer made the G-buffer

  DeviceFrame upload(ClContext& cl) const {
    return DeviceFrame::upload(cl, encoded, intrinsics, lights, ambient);
  }
};

// Rasterizes for `features.model` (the material terms the G-buffer planes hold) and stores the
// planes `features` needs.
PreparedFrame prepareFrame(const Scene& scene, int frame, int width, int height,
                           GBufferFormat format, const SceneFeatures& features);
// The same through `rasterizer` (software or OpenGL; its scene).
PreparedFrame prepareFrame(SceneRasterizer& rasterizer, int frame, int width, int height,
                           GBufferFormat format, const SceneFeatures& features);
// The general Blinn-Phong pipeline's frame (every plane): what a default TechniqueConfig reads.
PreparedFrame prepareFrame(const Scene& scene, int frame, int width, int height,
                           GBufferFormat format);

// The features of a run: the shading model ("auto": the scene's own, nativeShadingModel; or
// "blinn-phong", "metallic-roughness"), then the analysis of the scene for it, overridden by
// `features` ("auto", "general" or a list; chooseFeatures). Throws ts::Error on bad input.
SceneFeatures resolveFeatures(const Scene& scene, const std::string& shadingModel,
                              const std::string& features);

}  // namespace ts
