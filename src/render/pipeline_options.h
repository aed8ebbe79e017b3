#pragma once
// One description of a pipeline configuration, shared by `render` (RenderOptions) and `bench`
// (BenchConfig, one point of a sweep): the scene and its lights, the features, the G-buffer
// layout, the rasterizer, the device, and the technique's knobs. What a technique and a scene are
// made from comes out of it in one place (techniqueConfig, sceneOptions). A new knob = one field
// here (its name table beside its enum, technique_knobs.h), one line in techniqueConfig(), one
// option of `render` (main.cpp) and one bench dimension (bench_config.cpp).
#include <cstdint>
#include <string>

#include "gbuffer/gbuffer_layout.h"
#include "raster/raster_backend.h"
#include "raster/shadow_atlas.h"
#include "scene/scene_features.h"
#include "scene/scene_loader.h"
#include "techniques/technique.h"

namespace ts {

struct PipelineOptions {
  std::string device;  // "" = default (see ClContext)
  std::string scene = "builtin:street";
  std::string lightSet;         // "" = the scene's default / the file's own lights
  int lightCount = -1;          // -1 = the light set's own count
  float lightRange = 0.0f;      // > 0 overrides every light's range
  float lightThreshold = 0.0f;  // > 0: ranges from the attenuation threshold (light_range.h)
  std::string variant;          // built-in scene variants, a comma list (scene_loader.h);
                                // "" = none
  bool normalMaps = true;       // the scene's normal maps applied (--normal-maps)
  std::string shadows;          // shadow-casting lights (--shadows; shadow_casters.h)
  int shadowMapSize = kDefaultShadowMapSize;           // --shadow-map-size (shadow_atlas.h)
  double shadowBudgetMB = kDefaultShadowBudgetMB;      // --shadow-budget, MiB
  std::string shadowFilter = "none";                   // --shadow-filter (shadow_maps.h)
  std::string shadowBias = "1.5,1.5";                  // --shadow-bias CONSTANT,SLOPE
  ShadowStorage shadowStorage = ShadowStorage::Atlas;  // --shadow-storage (technique_knobs.h)
  BlendPolicy blend = BlendPolicy::Refuse;  // alphaMode BLEND materials (--blend; scene_loader.h)
  std::string shadingModel = "auto";        // auto (the scene's own) or a shadingModelNames() name
  std::string features = "auto";            // auto (the scene's needs), general, or a list
                                            // (chooseFeatures, scene_features.h)
  uint32_t seed = 1;                        // of the built-in scenes
  int width = 1280, height = 720;
  GBufferFormat format = GBufferFormat::FP32;
  RasterBackend raster = RasterBackend::Software;  // rasterizer of the G-buffer
  int msaa = 1;  // --msaa: samples a pixel of the forward techniques' targets (checkMsaa)
  // The technique's knobs (TechniqueConfig has their meaning).
  int tileWidth = 16, tileHeight = 16;
  int clusterSlices = 16;
  CullTest culling = CullTest::Rect;
  SpotCulling spotCulling = SpotCulling::Cone;
  bool depthSplit = false;
  MathMode math = MathMode::Precise;
  int lanes = 0;  // 0 = auto

  // The technique configuration for a frame with `features` (the scene's, resolved per frame).
  TechniqueConfig techniqueConfig(const SceneFeatures& features) const;
  // What loadScene builds the scene with (the threshold ranges are applied after loading).
  SceneOptions sceneOptions() const;
};

// --msaa N: 1, 2, 4 or 8, and above 1 only with --raster gl (the forward passes are OpenGL's);
// throws ts::Error (one line) otherwise. The OpenGL implementation's limit is checked where its
// context is (SceneRasterizer::forwardScene).
void checkMsaa(int samples, RasterBackend raster);

}  // namespace ts
