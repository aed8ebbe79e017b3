#pragma once
// The OpenGL rasterizer (`--raster gl`): the same G-buffer as ts::rasterize (raster/rasterizer.h)
// drawn by a real OpenGL implementation through a headless EGL context (src/raster/egl_context.h):
// vertex + fragment shaders (shaders/gbuffer.*) write the planes into float render targets of a
// framebuffer object, which are read back into a ts::GBuffer, so encode() and every technique
// work on it unchanged.
//
// How it matches the software rasterizer, and where it cannot: docs/opengl.md and the design
// notes at the top of gl_rasterizer.cpp.
#include <memory>
#include <string>

#include "raster/rasterizer.h"
#include "scene/scene.h"

namespace ts {

class GlRasterizer {
 public:
  // Uploads the scene (vertices, indices, textures as RGBA32F) and builds the shaders; the scene
  // must outlive the rasterizer. Throws ts::Error: no OpenGL context (one line naming what is
  // missing), a shader that does not compile or link (its log), a scene with out-of-range
  // indices, or any OpenGL error.
  explicit GlRasterizer(const Scene& scene);
  ~GlRasterizer();
  GlRasterizer(const GlRasterizer&) = delete;
  GlRasterizer& operator=(const GlRasterizer&) = delete;

  // One frame, as ts::rasterize (same sizes accepted up to the implementation's limits: larger
  // ones throw ts::Error naming the limit). RasterOptions::threads is ignored (the driver's
  // own); fragmentCounts is refused (ts::Error): overdraw counts come from the software
  // rasterizer only.
  GBuffer rasterize(const SceneCamera& camera, int width, int height,
                    const RasterOptions& options = {});

  std::string renderer() const;  // GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"
  double setupMs() const { return setupMs_; }  // context (first use) + upload + shader build

 private:
  struct State;
  std::unique_ptr<State> state_;
  double setupMs_ = 0.0;
};

}  // namespace ts
