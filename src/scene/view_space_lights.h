#pragma once
// The scene's lights in a camera's view space, as the kernels read them (ViewLights).
#include <vector>

#include <glm/glm.hpp>

#include "scene/scene.h"
#include "shading/view_lights.h"

namespace ts {

// In double (Camera): a light far from the origin keeps its position relative to the camera.
// (Here, not beside ViewLights: it reads the scene's lights, and scene sits above shading.)
ViewLights toViewSpace(const std::vector<SceneLight>& lights, const glm::dmat4& viewFromWorld);

}  // namespace ts
