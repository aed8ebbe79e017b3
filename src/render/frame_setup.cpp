#include "render/frame_setup.h"

#include <chrono>

#include "scene/shading_range.h"
#include "scene/view_space_lights.h"
#include "util/error.h"

namespace ts {

PreparedFrame prepareFrame(const Scene& scene, int frame, int width, int height,
                           GBufferFormat format) {
  return prepareFrame(scene, frame, width, height, format,
                      SceneFeatures::general(ShadingModel::BlinnPhong));
}

SceneFeatures resolveFeatures(const Scene& scene, const std::string& shadingModel,
                              const std::string& features) {
  ShadingModel model = shadingModel.empty() || shadingModel == "auto"
                           ? nativeShadingModel(scene)
                           : parseShadingModel(shadingModel);
  return chooseFeatures(features, analyzeScene(scene, model));
}

PreparedFrame prepareFrame(const Scene& scene, int frame, int width, int height,
                           GBufferFormat format, const SceneFeatures& features) {
  SceneRasterizer software(scene, RasterBackend::Software);
  return prepareFrame(software, frame, width, height, format, features);
}

PreparedFrame prepareFrame(SceneRasterizer& rasterizer, int frame, int width, int height,
                           GBufferFormat format, const SceneFeatures& features) {
  const Scene& scene = rasterizer.scene();
  if (width < 1 || height < 1)
    throw Error("resolution must be at least 1x1, got " + std::to_string(width) + "x" +
                std::to_string(height));
  checkShadingRange(scene);
  PreparedFrame f;
  f.frame = frame;
  f.camera = scene.camera(frame);
  f.intrinsics = CameraIntrinsics::from(f.camera, width, height);
  auto t0 = std::chrono::steady_clock::now();
  f.features = features;
  RasterOptions raster;
  raster.model = features.model;
  raster.normalMaps = features.normalMaps;
  f.gbuffer = rasterizer.rasterize(f.camera, width, height, raster);
  f.raster = rasterizer.backend();
  f.rasterMs =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  f.encoded = encode(f.gbuffer, format, features);
  f.lights = toViewSpace(scene.lights, f.camera.viewFromWorld);
  f.ambient = scene.ambient;
  return f;
}

}  // namespace ts
