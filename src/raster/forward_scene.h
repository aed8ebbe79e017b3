#pragma once
// The scene's geometry for the forward techniques, which draw it instead of reading a G-buffer:
// one frame's camera in a rasterizer's context. SceneRasterizer::forwardScene (raster_backend.h)
// makes one for a frame it rasterized with OpenGL (`--raster gl`), which render and bench hand to
// the techniques through DeviceFrame::forward; a frame from the software rasterizer or an
// imported G-buffer has none, and a forward technique refuses it in one line.
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "scene/scene_features.h"
#include "shading/forward_grid.h"
#include "shading/view_lights.h"

namespace ts {

class ForwardScene {
 public:
  virtual ~ForwardScene() = default;
  // A depth-only pass of the frame: the linear view depth per pixel (0 = background; the
  // G-buffer's depth plane) for the depth-bounds kernel, and the depth buffer the next
  // tiledForward(.., depthEqual = true) tests against. ms: its time (wall clock, glFinish on
  // both sides; see ForwardImage::drawMs).
  virtual std::vector<float> depthPrepass(double& ms) = 0;
  // The scene drawn once, each fragment shading the lights of its tile in `grid` with
  // kernels/shading.h (the terms of `features`, range model `rangeModel`).
  virtual ForwardImage tiledForward(const ViewLights& lights, glm::vec3 ambient,
                                    const SceneFeatures& features, int rangeModel,
                                    const ForwardLightGrid& grid, bool depthEqual) = 0;
};

}  // namespace ts
