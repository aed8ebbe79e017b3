#pragma once
// The scene's geometry for the forward techniques, which draw it instead of reading a G-buffer:
// one frame's camera in a rasterizer's context. SceneRasterizer::forwardScene (raster_backend.h)
// makes one for a frame it rasterized with OpenGL (`--raster gl`), which render and bench hand to
// the techniques through DeviceFrame::forward; a frame from the software rasterizer or an
// imported G-buffer has none, and a forward technique refuses it in one line.
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "gbuffer/gbuffer.h"
#include "raster/batch_lights.h"
#include "raster/draw_batches.h"
#include "raster/rasterizer.h"
#include "scene/scene_features.h"
#include "shading/forward_grid.h"
#include "shading/transparent_fragments.h"
#include "shading/view_lights.h"

namespace ts {

// The capture's default bound: 4 Mi fragments (96 bytes each, 384 MiB), about 18 layers of a
// 640x360 frame.
constexpr size_t kCaptureBound = size_t(1) << 22;

class ForwardScene {
 public:
  virtual ~ForwardScene() = default;
  // --msaa: the samples a pixel of every pass's targets (1: single-sampled). The passes shade
  // per fragment and return the image resolved by OpenGL; ForwardImage::pixelBatch and
  // depthPrepass hold one plane per sample.
  virtual int samples() const = 0;
  // The frame's G-buffer per sample (GlRasterizer::rasterizeSamples): what the reference shades
  // each sample of an MSAA frame from; {the one G-buffer} for samples() = 1.
  virtual std::vector<GBuffer> sampleGBuffers(const RasterOptions& options) = 0;
  // A depth-only pass of the frame: the linear view depth per pixel (0 = background; the
  // G-buffer's depth plane) for the depth-bounds kernel, one plane per sample (sample-major),
  // and the depth buffer the next tiledForward(.., depthEqual = true) tests against. ms: its
  // time (wall clock, glFinish on both sides; see ForwardImage::drawMs).
  virtual std::vector<float> depthPrepass(double& ms) = 0;
  // The scene drawn once, each fragment shading the lights of its tile in `grid` with
  // kernels/shading.h (the terms of `features`, range model `rangeModel`); then the transparent
  // draws back to front, blended, with transparentGrid's lists (null: grid's).
  virtual ForwardImage tiledForward(const ViewLights& lights, glm::vec3 ambient,
                                    const SceneFeatures& features, int rangeModel,
                                    const ForwardLightGrid& grid, bool depthEqual,
                                    const ForwardLightGrid* transparentGrid) = 0;
  // The hybrid of the G-buffer techniques (Olsson & Assarsson's tiled deferred with a tiled
  // forward pass for the glass): `opaque`, the image a technique shaded from this frame's
  // G-buffer (row 0 at the top), as the background over the G-buffer pass's depth, then the
  // transparent draws back to front, blended, each fragment shading its tile's lights in `grid`.
  virtual ForwardImage transparentOver(const std::vector<glm::vec4>& opaque,
                                       const ViewLights& lights, glm::vec3 ambient,
                                       const SceneFeatures& features, int rangeModel,
                                       const ForwardLightGrid& grid) = 0;
  // The draws with an alphaMode BLEND material (--blend blend): every forward pass draws them
  // after the opaque ones, back to front, blended "over" (GlRasterizer::tiledForward); a frame
  // with any is refused by the techniques that shade a G-buffer.
  virtual size_t transparentDraws() const = 0;
  // Every transparent fragment the forward passes blend, for the reference's composite
  // (GlRasterizer::captureTransparent); features: the material planes' model and normal maps.
  virtual std::vector<TransparentFragment> captureTransparent(const SceneFeatures& features,
                                                              size_t maxFragments) = 0;
  // The scene's draw batches (raster/draw_batches.h) as view-space boxes at this frame's camera,
  // in draw order: what the forward techniques test the lights against.
  virtual std::vector<ViewBox> batchBoxes() = 0;
  // `forward`: a base pass, then one additive pass per light over the batches of its list in
  // lightBatches (one list per light), depth test EQUAL (GlRasterizer::multiPassForward).
  virtual ForwardImage multiPassForward(const ViewLights& lights, glm::vec3 ambient,
                                        const SceneFeatures& features, int rangeModel,
                                        const IndexLists& lightBatches) = 0;
  // `forward-single`: the scene drawn once, each batch shading its list in batchLights (one list
  // per batch; GlRasterizer::singlePassForward).
  virtual ForwardImage singlePassForward(const ViewLights& lights, glm::vec3 ambient,
                                         const SceneFeatures& features, int rangeModel,
                                         const IndexLists& batchLights) = 0;
};

}  // namespace ts
