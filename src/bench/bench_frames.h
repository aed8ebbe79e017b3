#pragma once
// Where the benchmark's frames come from, per scene definition (a configuration's scene, lights
// and seed): a scene rasterized by the configuration's rasterizer (`raster` dimension: software
// or gl; one rasterizer per kind, the OpenGL one uploads the scene once), or a G-buffer imported
// from files (`scene` value gbuffer:DIR, see bench/README.md).
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bench/bench_config.h"
#include "raster/raster_backend.h"
#include "raster/shadow_maps.h"
#include "render/frame_setup.h"
#include "render/imported_frame.h"

namespace ts {

// "gbuffer:DIR" (a folder written by render --dump, or a descriptor .json): DIR; else "".
std::string importedGBufferPath(const std::string& sceneSpec);

class BenchScene {
 public:
  // Loads the scene or reads the G-buffer files, and makes the configuration's rasterizer, so
  // that a bad scene, file or rasterizer fails before anything is timed (ts::Error). An imported
  // G-buffer must have the configuration's resolution and takes no light options or rasterizer.
  explicit BenchScene(const BenchConfig& config);
  BenchScene(const BenchScene&) = delete;  // its rasterizers refer to its scene
  BenchScene& operator=(const BenchScene&) = delete;
  // Checks another configuration of the same scene definition (its resolution, rasterizer).
  void check(const BenchConfig& config);

  int pathLength() const;  // frames of the camera path (1 for an imported G-buffer)
  // The features `config` runs with: the scene's analysis for its shading model, overridden by
  // its `features` (resolveFeatures); for an imported G-buffer, its files'. ts::Error on bad input.
  SceneFeatures features(const BenchConfig& config) const;
  // Frame `frame` for `config` (resolution, rasterizer, shading model), encoded in fp32 with every
  // plane (the general layout: the error reference's input; configurations encode their own
  // layout from its gbuffer); raster_ms inside.
  PreparedFrame prepare(const BenchConfig& config, int frame);
  // The shadow maps of `frame` (prepare's, for `config`: its --shadow-* options), drawn and
  // attached to frame.lights (FrameShadows, as `render` draws them, by the configuration's
  // rasterizer); null when no light casts one or for an imported G-buffer. Their drawing time is
  // the atlas's drawMs.
  std::shared_ptr<const ShadowAtlas> drawShadows(const BenchConfig& config, PreparedFrame& frame);
  // The scene to draw at `frame`'s camera for the forward techniques (DeviceFrame::forward):
  // from the configuration's OpenGL rasterizer; null for the software one or an imported G-buffer.
  std::unique_ptr<ForwardScene> forwardScene(const BenchConfig& config, const PreparedFrame& frame);
  // The lights with the scene's own ranges (before light_threshold), in the frame's view space:
  // the error reference of every configuration of the scene; with frame.lights' shadow maps.
  ViewLights ownRangeLights(const PreparedFrame& frame) const;
  // The scene drawn (shadow maps per light); empty for an imported G-buffer.
  const Scene& scene() const { return scene_; }

 private:
  Scene scene_;
  std::vector<SceneLight> ownRangeLights_;
  std::optional<ImportedFrame> imported_;
  std::map<RasterBackend, std::unique_ptr<SceneRasterizer>> rasterizers_;
};

}  // namespace ts
