#pragma once
// The rounding box of a forward fragment's position (reference.h, ReceiverRounding) for a scene
// drawn from a camera: W, the largest coordinate entering OpenGL's float view transform.
#include <glm/glm.hpp>

#include "reference/reference.h"
#include "scene/scene.h"

namespace ts {

// W = the largest |coordinate| of the scene's vertices plus the largest |translation| of the view
// (as the shadow-map cross-check's W, src/raster/shadow_map_compare.cpp).
ReceiverRounding receiverRounding(const Scene& scene, const glm::dmat4& viewFromWorld);

}  // namespace ts
