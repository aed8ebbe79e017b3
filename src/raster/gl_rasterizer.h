#pragma once
// The OpenGL rasterizer (`--raster gl`): the same G-buffer as ts::rasterize (raster/rasterizer.h)
// drawn by a real OpenGL implementation through a headless EGL context (src/raster/egl_context.h):
// vertex + fragment shaders (shaders/gbuffer.*) write the planes into float render targets of a
// framebuffer object, which are read back into a ts::GBuffer, so encode() and every technique
// work on it unchanged.
//
// How it matches the software rasterizer, and where it cannot: docs/opengl.md and the design
// notes at the top of gl_rasterizer.cpp.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "raster/batch_lights.h"
#include "raster/draw_batches.h"
#include "raster/rasterizer.h"
#include "raster/shadow_maps.h"
#include "scene/scene.h"
#include "scene/scene_features.h"
#include "shading/forward_grid.h"
#include "shading/transparent_fragments.h"
#include "shading/view_lights.h"

namespace ts {

// What a forward pass shades with, as the kernels get it.
struct ForwardLighting {
  const ViewLights* lights = nullptr;  // view space; with shadow maps where some light casts
                                       // one (sampled by kernels/shadows.h as GLSL)
  glm::vec3 ambient{0.0f};
  SceneFeatures features;  // features.model: the materials' terms (RasterOptions::model)
  int rangeModel = 0;      // TS_MODEL_* (kernels/shading.h)
  // --msaa: samples a pixel of the pass's colour and depth targets (1: single-sampled). Shaded
  // per fragment, the image resolved by OpenGL (glBlitFramebuffer) before its read-back.
  int samples = 1;
};

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
  // --msaa's per-sample G-buffers: the G-buffer program drawn into `samples`-sample targets (one
  // fragment shader run a pixel and triangle, as the forward passes shade: each sample holds the
  // surface of the triangle covering it, interpolated where its fragment is), then each sample
  // fetched into the single-sample targets and read back: element k is sample k's G-buffer
  // (the layout of rasterize's). samples = 1: {rasterize(..)}. Throws ts::Error beyond
  // maxSamples().
  std::vector<GBuffer> rasterizeSamples(const SceneCamera& camera, int width, int height,
                                        int samples, const RasterOptions& options = {});
  // The most samples a pixel every target of a pass can have (GL_MAX_SAMPLES and the colour and
  // integer texture limits); checkSamples throws ts::Error (one line) for more.
  int maxSamples() const;
  void checkSamples(int samples) const;

  // Tiled forward shading (shaders/tiled_forward.frag): the scene drawn once, each fragment
  // shading its tile's lights with kernels/shading.h. depthEqual: after depthPrepass() of the same
  // camera and size, with the depth test EQUAL (each pixel shaded once); else the depth test of
  // the G-buffer pass (every fragment that passes it at its time is shaded). Needs OpenGL 4.3.
  // The scene's transparent draws (--blend blend) come after the opaque ones, back to front,
  // blended over them (drawn with transparentGrid's lists where given, else grid's).
  ForwardImage tiledForward(const SceneCamera& camera, int width, int height,
                            const ForwardLighting& lighting, const ForwardLightGrid& grid,
                            bool depthEqual, const ForwardLightGrid* transparentGrid);
  // The hybrid's transparent pass (ForwardScene::transparentOver): `opaque` (width x height, row 0
  // at the top) into the forward image target, the opaque depth of the G-buffer pass of this
  // camera and size copied into its depth buffer (drawn again by the depth program where the
  // last G-buffer pass was another frame's: the same draws and vertex shader, the same depth),
  // then the transparent draws as tiledForward draws them, with `grid`'s lists.
  ForwardImage transparentOver(const SceneCamera& camera, int width, int height,
                               const ForwardLighting& lighting,
                               const std::vector<glm::vec4>& opaque, const ForwardLightGrid& grid);
  // Multi-pass forward shading (`forward`, the thesis's): a base pass of every draw batch
  // (ambient, emission, directional lights; the G-buffer pass's depth test), then for each light
  // with a non-empty list in lightBatches (one list per light: the batches its volume touches,
  // raster/batch_lights.h) one pass that draws those batches with depth test EQUAL and additive
  // blending (ONE, ONE), shading that light alone. ForwardImage::baseMs is the base pass, drawMs
  // the light passes together.
  ForwardImage multiPassForward(const SceneCamera& camera, int width, int height,
                                const ForwardLighting& lighting, const IndexLists& lightBatches);
  // Single-pass forward shading (`forward-single`): the scene drawn once (the G-buffer pass's
  // depth test), batch b's fragments shading the lights of batchLights' list b (one list per
  // draw batch, in a shader storage buffer: no cap on a list's length) and the directional ones.
  ForwardImage singlePassForward(const SceneCamera& camera, int width, int height,
                                 const ForwardLighting& lighting, const IndexLists& batchLights);
  // The view-space boxes of the draw batches at `camera`, in draw order (raster/draw_batches.h).
  std::vector<ViewBox> batchBoxes(const SceneCamera& camera) const;
  size_t batchCount() const;
  // Draw batches with an alphaMode BLEND material (a scene with Scene::blendComposited).
  size_t transparentDraws() const;
  // The reference's capture of the transparent draws (shading/transparent_fragments.h): an
  // opaque depth pass, then the transparent draws in the forward passes' back-to-front order with
  // the forward shader's TS_CAPTURE build, which records every fragment that passes the depth
  // test into a shader storage buffer (an atomic counter; grown and redrawn when it overflows).
  // Throws ts::Error when more than maxFragments pass (kCaptureBound by default).
  std::vector<TransparentFragment> captureTransparent(const SceneCamera& camera, int width,
                                                      int height, const SceneFeatures& features,
                                                      size_t maxFragments);

  // A depth-only pass: fills the depth buffer the next tiledForward(.., true) tests against and
  // returns the linear view depth per pixel (0 = background), the G-buffer's depth plane; with
  // samples > 1 (--msaa) one such plane per sample, sample-major (samples x width x height).
  // ms: the draw's wall-clock time (ForwardImage::drawMs).
  std::vector<float> depthPrepass(const SceneCamera& camera, int width, int height, int samples,
                                  double& ms);

  // The shadow maps of `layout` (planned for this scene's lights), drawn by OpenGL into one R32F
  // atlas target with a depth buffer, each face in its rectangle (viewport and scissor) with the
  // draw batches whose boxes touch its frustum (touchesFace, as the software maps), and read
  // back: the software maps' convention (raster/shadow_maps.h; docs/shadows.md). drawMs: the
  // pass's wall clock, glFinish to glFinish; readMs the read-back. Throws ts::Error (one line)
  // for an atlas above the implementation's size limit, or any OpenGL error.
  ShadowAtlas drawShadowAtlas(ShadowAtlasLayout layout);

  std::string renderer() const;  // GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"
  double setupMs() const { return setupMs_; }  // context (first use) + upload + shader build

 private:
  void warmUpShadows();  // builds the shadow-map program on first use, then a first small face
  // Builds the forward programs on first use (the TS_HAS_SHADOWS variant on the first frame with
  // shadows), then first small frames of each pass (warmUpPasses, with `none`'s shadow tables).
  void warmUpForward(bool shadows);
  void warmUpPasses(const ViewLights& none);
  struct State;
  // What rasterize and rasterizeSamples refuse before drawing (one line each): fragment counts,
  // a size beyond the implementation's limit.
  void checkTarget(int width, int height, const RasterOptions& options) const;
  // The checks and setup every forward pass starts with (size limit, context, warm-up), and the
  // program variant for a frame with or without shadow-casting lights.
  State& beginForward(int width, int height, bool shadows);
  std::unique_ptr<State> state_;
  double setupMs_ = 0.0;
};

}  // namespace ts
