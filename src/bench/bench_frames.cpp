#include "bench/bench_frames.h"

#include "scene/light_range.h"
#include "scene/scene_features.h"
#include "scene/shadow_casters.h"
#include "scene/scene_loader.h"
#include "scene/view_space_lights.h"
#include "techniques/technique.h"
#include "util/error.h"

namespace ts {

std::string importedGBufferPath(const std::string& sceneSpec) {
  const std::string prefix = "gbuffer:";
  return sceneSpec.rfind(prefix, 0) == 0 ? sceneSpec.substr(prefix.size()) : std::string();
}

BenchScene::BenchScene(const BenchConfig& c) {
  const std::string path = importedGBufferPath(c.scene);
  if (!path.empty()) {
    imported_ = importGBuffer(path, GBufferFormat::FP32);
  } else {
    scene_ = loadScene(c.scene, c.sceneOptions());
    ownRangeLights_ = scene_.lights;
    if (c.lightThreshold > 0.0f) applyThresholdRanges(scene_.lights, c.lightThreshold);
  }
  check(c);
}

void BenchScene::check(const BenchConfig& c) {
  const RasterBackend backend = c.raster;
  if (imported_) {
    const PreparedFrame& f = imported_->frame;
    if (c.width != f.intrinsics.width || c.height != f.intrinsics.height)
      throw Error("--scene " + c.scene + " is " + std::to_string(f.intrinsics.width) + "x" +
                  std::to_string(f.intrinsics.height) + ": give --resolution " +
                  std::to_string(f.intrinsics.width) + "x" + std::to_string(f.intrinsics.height));
    if (backend != RasterBackend::Software)
      throw Error("--scene " + c.scene +
                  " is an imported G-buffer: it is not rasterized (leave "
                  "--raster at software)");
    if (!c.lightSet.empty() || c.lightCount >= 0 || c.lightRange > 0.0f || c.lightThreshold > 0.0f)
      throw Error("--scene " + c.scene +
                  " brings its own lights: no --lights, --light-count, "
                  "--light-range or --light-threshold");
    if (!c.variant.empty() || c.shadingModel != "auto")
      throw Error("--scene " + c.scene +
                  " is an imported G-buffer: its files decide the shading "
                  "model (no --variant or --shading-model)");
    features(c);  // a bad --features fails before anything is timed
    if (findTechnique(c.technique).drawsScene)
      throw Error(c.technique + " draws the scene: an imported G-buffer has none (--raster gl)");
    return;
  }
  features(c);  // a bad --shading-model or --features fails before anything is timed
  // bench draws no shadow maps yet: its runs would shade a shadow-casting light unshadowed.
  if (const size_t casters = shadowCasterCount(scene_.lights))
    throw Error("--scene " + c.scene + ": " + std::to_string(casters) +
                " light(s) cast a shadow (extras castsShadow), and bench draws no shadow maps "
                "yet (render does: docs/shadows.md)");
  if (findTechnique(c.technique).drawsScene && backend != RasterBackend::Gl)
    throw Error(c.technique + " draws the scene: bench needs --raster gl for it");
  auto& r = rasterizers_[backend];
  if (!r) r = std::make_unique<SceneRasterizer>(scene_, backend);
}

int BenchScene::pathLength() const { return imported_ ? 1 : int(scene_.cameraPath.size()); }

SceneFeatures BenchScene::features(const BenchConfig& c) const {
  if (imported_) return chooseFeatures(c.features, imported_->frame.features);
  return resolveFeatures(scene_, c.shadingModel, c.features);
}

PreparedFrame BenchScene::prepare(const BenchConfig& c, int frame) {
  if (imported_) return imported_->frame;  // fp32, as read
  SceneRasterizer& r = *rasterizers_.at(c.raster);
  return prepareFrame(r, frame, c.width, c.height, GBufferFormat::FP32,
                      SceneFeatures::general(features(c).model));
}

std::unique_ptr<ForwardScene> BenchScene::forwardScene(const BenchConfig& c,
                                                       const PreparedFrame& frame) {
  if (imported_) return nullptr;
  return rasterizers_.at(c.raster)->forwardScene(frame.camera, c.width, c.height);
}

ViewLights BenchScene::ownRangeLights(const PreparedFrame& frame) const {
  if (imported_) return imported_->frame.lights;
  return toViewSpace(ownRangeLights_, frame.camera.viewFromWorld);
}

}  // namespace ts
