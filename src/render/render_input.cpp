#include "render/render_input.h"

#include <chrono>
#include <filesystem>

#include "render/imported_frame.h"
#include "scene/shadow_casters.h"
#include "scene/light_range.h"
#include "scene/scene_loader.h"

namespace ts {

RenderInput loadImportedInput(const std::string& path, std::optional<GBufferFormat> format,
                              const std::string& features) {
  RenderInput input;
  const auto t0 = std::chrono::steady_clock::now();
  ImportedFrame imported = importGBuffer(path, format);
  input.frame = std::move(imported.frame);
  input.frame.rasterMs =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  input.sceneName = imported.descriptor.scene.empty()
                        ? std::filesystem::path(imported.descriptor.path).parent_path().string()
                        : imported.descriptor.scene;
  input.raster = "import";
  input.rasterDetail = imported.descriptor.path;
  input.frame.features = chooseFeatures(features, input.frame.features);
  input.lightSummary =
      std::to_string(input.frame.lights.size() + input.frame.lights.directionalCount()) + " lights";
  // The files' shadow-casting lights (their maps come with them: shadow_atlas.json).
  for (int f : input.frame.lights.shadow) input.shadowCasters += f >= 0;
  for (int f : input.frame.lights.directionalShadow) input.shadowCasters += f >= 0;
  return input;
}

FrameShadows::FrameShadows(const PipelineOptions& o) : options{o.shadowMapSize, o.shadowBudgetMB} {
  checkShadowAtlasOptions(options);
  sampling.taps = parseShadowFilter(o.shadowFilter);
  parseShadowBias(o.shadowBias, sampling);
}

std::shared_ptr<const ShadowAtlas> FrameShadows::draw(SceneRasterizer& rasterizer,
                                                      PreparedFrame& frame) const {
  const Scene& scene = rasterizer.scene();
  if (shadowCasterCount(scene.lights) == 0) return nullptr;
  auto atlas = std::make_shared<const ShadowAtlas>(rasterizer.drawShadowAtlas(
      planShadowAtlas(scene.lights, scene.bounds(), frame.camera, options,
                      viewGeometryBounds(frame.gbuffer, frame.camera))));
  attachShadowMaps(atlas, scene.lights, frame.camera.viewFromWorld, sampling, frame.lights);
  return atlas;
}

RenderInput loadSceneInput(const PipelineOptions& o, int frame) {
  const FrameShadows shadows(o);  // its options checked before any work, casters or not
  RenderInput input;
  input.scene = std::make_unique<Scene>(loadScene(o.scene, o.sceneOptions()));
  Scene& scene = *input.scene;
  if (o.lightThreshold > 0.0f) applyThresholdRanges(scene.lights, o.lightThreshold);
  const SceneFeatures features = resolveFeatures(scene, o.shadingModel, o.features);
  input.rasterizer = std::make_unique<SceneRasterizer>(scene, o.raster);
  SceneRasterizer& rasterizer = *input.rasterizer;
  input.frame = prepareFrame(rasterizer, frame, o.width, o.height, o.format, features);
  checkMsaa(o.msaa, o.raster);
  input.forward = rasterizer.forwardScene(input.frame.camera, o.width, o.height, o.msaa);
  input.lightSummary = describeLights(scene.lights);
  input.shadowCasters = shadowCasterCount(scene.lights);
  input.shadowAtlas = shadows.draw(rasterizer, input.frame);
  input.sceneName = scene.name;
  input.triangles = scene.triangleCount();
  input.raster = toString(rasterizer.backend());
  input.rasterDetail = rasterizer.description();
  input.rasterSetupMs = rasterizer.setupMs();
  return input;
}

}  // namespace ts
