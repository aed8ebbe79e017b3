#pragma once
// Where a frame comes from: a scene rasterized by the software or the OpenGL rasterizer
// (--raster), or a G-buffer imported from files (--gbuffer-in). The API's Frame::fromScene and
// Frame::fromFiles (src/api/) are these.
#include <memory>
#include <optional>
#include <string>

#include "raster/forward_scene.h"
#include "raster/raster_backend.h"
#include "raster/shadow_maps.h"
#include "render/frame_setup.h"
#include "render/pipeline_options.h"

namespace ts {

struct RenderInput {
  PreparedFrame frame;
  std::string sceneName;       // the scene's name, or the descriptor's "scene" (else its folder)
  size_t triangles = 0;        // 0 for an imported G-buffer
  std::string raster;          // "software", "gl" or "import"
  std::string rasterDetail;    // "software", "gl: <GL_RENDERER>", or the descriptor's path
  double rasterSetupMs = 0.0;  // one-time cost before the frame (OpenGL context, upload)
  std::string lightSummary;    // "924 lights" or "12 lights: 6 point, 5 spot, 1 directional"
  size_t shadowCasters = 0;    // lights marked to cast a shadow
  // Their shadow maps (a scene with shadowCasters > 0; drawn by the frame's rasterizer, --raster
  // software or gl), else null; frame.lights samples them (attachShadowMaps).
  std::shared_ptr<const ShadowAtlas> shadowAtlas;
  // The scene and its rasterizer, kept for the forward techniques, which draw the scene
  // (DeviceFrame::forward): `forward` is set for a scene rasterized with --raster gl, null for
  // the software rasterizer and an imported G-buffer (no scene).
  std::unique_ptr<Scene> scene;
  std::unique_ptr<SceneRasterizer> rasterizer;
  std::unique_ptr<ForwardScene> forward;
};

// The shadow maps of a frame, as `render` and `bench` draw them: the options' atlas size, budget
// and sampling (--shadow-map-size, --shadow-budget, --shadow-filter, --shadow-bias), checked on
// construction (ts::Error, one line, casters or not).
struct FrameShadows {
  explicit FrameShadows(const PipelineOptions& o);
  // Plans the atlas of the rasterizer's scene's shadow-casting lights for `frame` (its camera and
  // G-buffer), draws it with that rasterizer (software or OpenGL) and attaches it to
  // frame.lights; null (and nothing drawn) when no light casts one.
  std::shared_ptr<const ShadowAtlas> draw(SceneRasterizer& rasterizer, PreparedFrame& frame) const;

  ShadowAtlasOptions options;
  ShadowSampling sampling;
};

// Frame `frame` of the scene `o` describes, rasterized; its features are the scene's
// (--shading-model, --features; resolveFeatures), with the shadow maps of its shadow-casting
// lights. Throws ts::Error for a bad scene, rasterizer or shadow-map option or budget.
RenderInput loadSceneInput(const PipelineOptions& o, int frame);
// The G-buffer files at `path` (importGBuffer) encoded in `format` (default: the files' own
// layout); its features those of its files, overridden by `features` (chooseFeatures). Throws
// ts::Error for a bad G-buffer file (one line).
RenderInput loadImportedInput(const std::string& path, std::optional<GBufferFormat> format,
                              const std::string& features);

}  // namespace ts
