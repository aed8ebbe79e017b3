#pragma once
// `tileshade render`: one frame of a scene, one or more techniques, files in an output folder.
#include <string>
#include <vector>

#include "gbuffer/gbuffer_layout.h"

namespace ts {

struct RenderOptions {
  std::string scene = "builtin:street";
  std::string lightSet;                // "" = the scene's default / the file's own lights
  int lightCount = -1;                 // -1 = the light set's own count
  float lightRange = 0.0f;             // > 0 overrides every light's range
  float lightThreshold = 0.0f;         // > 0: ranges from the attenuation threshold (light_range.h)
  std::string variant;                 // built-in scene variants (scene_loader.h), "" = none
  std::string shadingModel = "auto";   // auto (the scene's own), blinn-phong, metallic-roughness
  std::string features = "auto";      // auto (the scene's needs), general, or a list
                                       // (chooseFeatures, scene_features.h)
  uint32_t seed = 1;
  std::vector<std::string> techniques{"tiled"};  // "all" expands to every registered technique
  int tileWidth = 16, tileHeight = 16;
  int clusterSlices = 16;
  std::string culling = "rect";        // per-tile test: rect, frustum, aabb
  std::string spotCulling = "cone";    // spot lights as: cone, bound-sphere, range-sphere
  bool depthSplit = false;             // tiles: split the depth range at its middle
  std::string math = "precise";        // shading arithmetic: precise, fast, native
  std::string lanes = "auto";          // pixels per vector in the light loop (TechniqueConfig)
  GBufferFormat format = GBufferFormat::FP32;
  int width = 1280, height = 720;
  int frame = 0;
  std::string device;                  // see ClContext
  std::string outDir = "out";
  bool check = false;                  // compare against the double reference
  bool dump = false;                   // write gbuffer.exr + lights.json
  bool heatmap = false;                // with check: error.png per technique
  float exposure = 1.0f;               // PNG tone mapping
  std::string raster = "software";     // rasterizer: software or gl (src/raster/raster_backend.h)
  std::string gbufferIn;               // "" = rasterize the scene; else G-buffer files to import
  bool keepInputLayout = false;        // with gbufferIn: encode in the files' layout, not `format`
};

// Throws ts::Error (one line naming the option) for any option that makes no sense: NaN, inf or
// negative numbers, zero or absurd sizes, --heatmap without --check, unknown names.
void validateRenderOptions(const RenderOptions& options);

// Runs the job, prints the table to stdout, writes the files. Throws ts::Error on bad input (every
// option is checked before any work) and when a file cannot be written.
void runRender(const RenderOptions& options);

}  // namespace ts
