#include "bench/bench_frames.h"

#include "render/render_input.h"

#include "scene/light_range.h"
#include "scene/scene_features.h"
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
    // What only a scene's geometry gives: the files hold the surfaces and the shadow maps.
    const PipelineOptions scene;
    if (!c.shadows.empty() || c.shadowMapSize != scene.shadowMapSize ||
        c.shadowBudgetMB != scene.shadowBudgetMB || c.shadowFilter != scene.shadowFilter ||
        c.shadowBias != scene.shadowBias || c.blend != scene.blend)
      throw Error("--scene " + c.scene +
                  " is an imported G-buffer: its files hold the surfaces and any shadow maps "
                  "(no --shadows, --shadow-map-size, --shadow-budget, --shadow-filter, "
                  "--shadow-bias or --blend)");
    features(c);  // a bad --features fails before anything is timed
    if (findTechnique(c.technique).drawsScene)
      throw Error(c.technique + " draws the scene: an imported G-buffer has none (--raster gl)");
    return;
  }
  features(c);  // a bad --shading-model or --features fails before anything is timed
  static_cast<void>(
      FrameShadows(c));  // a bad --shadow-map-size, --shadow-filter or --shadow-bias fails here
  if (findTechnique(c.technique).drawsScene && backend != RasterBackend::Gl)
    throw Error(c.technique + " draws the scene: bench needs --raster gl for it");
  checkMsaa(c.msaa, backend);
  if (c.msaa > 1 && !findTechnique(c.technique).multisamples)
    throw Error(msaaRefusal(c.technique, c.msaa));
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

std::shared_ptr<const ShadowAtlas> BenchScene::drawShadows(const BenchConfig& c,
                                                           PreparedFrame& frame) {
  if (imported_) return nullptr;
  return FrameShadows(c).draw(*rasterizers_.at(c.raster), frame);
}

std::unique_ptr<ForwardScene> BenchScene::forwardScene(const BenchConfig& c,
                                                       const PreparedFrame& frame) {
  if (imported_) return nullptr;
  return rasterizers_.at(c.raster)->forwardScene(frame.camera, c.width, c.height, c.msaa);
}

ViewLights BenchScene::ownRangeLights(const PreparedFrame& frame) const {
  if (imported_) return imported_->frame.lights;
  ViewLights own = toViewSpace(ownRangeLights_, frame.camera.viewFromWorld);
  // The same maps, sampled the same way: the lights' order and so their faces are the frame's.
  own.shadow = frame.lights.shadow;
  own.directionalShadow = frame.lights.directionalShadow;
  own.shadowFaces = frame.lights.shadowFaces;
  own.shadowAtlas = frame.lights.shadowAtlas;
  own.shadowAtlasWidth = frame.lights.shadowAtlasWidth;
  return own;
}

}  // namespace ts
