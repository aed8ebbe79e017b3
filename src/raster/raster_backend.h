#pragma once
// Which rasterizer makes the G-buffer (`--raster software|gl`), behind one interface: a
// SceneRasterizer is made once per scene (the OpenGL one uploads the scene then) and rasterizes
// any number of frames of it.
#include <memory>
#include <string>

#include "raster/forward_scene.h"
#include "raster/rasterizer.h"
#include "raster/shadow_maps.h"
#include "scene/scene.h"
#include "util/enum_names.h"

namespace ts {

enum class RasterBackend { Software, Gl };
const EnumNames<RasterBackend>& rasterBackendNames();
std::string toString(RasterBackend backend);  // "software" | "gl"
// "software" | "gl"; throws ts::Error naming both otherwise.
RasterBackend parseRasterBackend(const std::string& name);

class GlRasterizer;

class SceneRasterizer {
 public:
  // The scene must outlive the rasterizer. Gl: throws ts::Error when no OpenGL context can be
  // made (one line naming what is missing) or the build has no OpenGL (TILESHADE_WITH_GL=OFF).
  SceneRasterizer(const Scene& scene, RasterBackend backend);
  ~SceneRasterizer();
  SceneRasterizer(SceneRasterizer&&) noexcept;
  SceneRasterizer& operator=(SceneRasterizer&&) = delete;

  // ts::rasterize or GlRasterizer::rasterize.
  GBuffer rasterize(const SceneCamera& camera, int width, int height, const RasterOptions& options);

  // The shadow maps of `layout` (planned for this scene's lights) drawn by this rasterizer: the
  // software's drawShadowAtlas (every thread) or OpenGL's (GlRasterizer::drawShadowAtlas), the
  // same convention either way (raster/shadow_maps.h).
  ShadowAtlas drawShadowAtlas(ShadowAtlasLayout layout);

  // The scene for the forward techniques at `camera` (DeviceFrame::forward), drawn by this
  // rasterizer's OpenGL context with `samples` samples a pixel (--msaa); null for the software
  // rasterizer (it draws no forward passes). The rasterizer must outlive it. Throws ts::Error
  // (one line) for more samples than the OpenGL implementation renders, or samples > 1 with
  // transparent draws (not done).
  std::unique_ptr<ForwardScene> forwardScene(const SceneCamera& camera, int width, int height,
                                             int samples = 1);

  const Scene& scene() const { return scene_; }
  RasterBackend backend() const { return backend_; }
  // "software", or "gl: <GL_RENDERER>".
  std::string description() const;
  // One-time cost before the first frame: 0 for software; OpenGL context (first use in the
  // process), scene upload and shader build for gl.
  double setupMs() const { return setupMs_; }

 private:
  const Scene& scene_;
  RasterBackend backend_;
  std::unique_ptr<GlRasterizer> gl_;
  double setupMs_ = 0.0;
};

}  // namespace ts
