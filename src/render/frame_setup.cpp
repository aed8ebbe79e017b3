#include "render/frame_setup.h"

#include <chrono>

#include "scene/shading_range.h"
#include "util/error.h"

namespace ts {

PreparedFrame prepareFrame(const Scene& scene, int frame, int width, int height,
                           GBufferFormat format) {
  return prepareFrame(scene, frame, width, height, format,
                      analyzeScene(scene, ShadingModel::BlinnPhong));
}

PreparedFrame prepareFrame(const Scene& scene, int frame, int width, int height,
                           GBufferFormat format, const SceneFeatures& features) {
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
  f.gbuffer = rasterize(scene, f.camera, width, height, raster);
  f.rasterMs =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  f.encoded = encode(f.gbuffer, format);
  f.lights = toViewSpace(scene.lights, f.camera.viewFromWorld);
  f.ambient = scene.ambient;
  return f;
}

}  // namespace ts
