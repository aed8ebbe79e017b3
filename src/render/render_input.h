#pragma once
// Where `render` gets its frame: a scene rasterized by the software or the OpenGL rasterizer
// (--raster), or a G-buffer imported from files (--gbuffer-in).
#include <memory>
#include <string>

#include "raster/forward_scene.h"
#include "raster/raster_backend.h"
#include "render/frame_setup.h"
#include "render/render_job.h"

namespace ts {

struct RenderInput {
  PreparedFrame frame;
  std::string sceneName;       // the scene's name, or the descriptor's "scene" (else its folder)
  size_t triangles = 0;        // 0 for an imported G-buffer
  std::string raster;          // "software", "gl" or "import"
  std::string rasterDetail;    // "software", "gl: <GL_RENDERER>", or the descriptor's path
  double rasterSetupMs = 0.0;  // one-time cost before the frame (OpenGL context, upload)
  std::string lightSummary;    // "924 lights" or "12 lights: 6 point, 5 spot, 1 directional"
  // The scene and its rasterizer, kept for the forward techniques, which draw the scene
  // (DeviceFrame::forward): `forward` is set for a scene rasterized with --raster gl, null for
  // the software rasterizer and an imported G-buffer (no scene).
  std::unique_ptr<Scene> scene;
  std::unique_ptr<SceneRasterizer> rasterizer;
  std::unique_ptr<ForwardScene> forward;
};

// The frame's features are the scene's (--shading-model, --features; resolveFeatures) or, for an
// imported G-buffer, those of its files. Throws ts::Error for a bad scene, rasterizer or
// G-buffer file (one line).
RenderInput loadRenderInput(const RenderOptions& options);

}  // namespace ts
