#pragma once
// Which lights cast shadows (`--shadows`): the first piece of shadows (issue #18). The choice is
// recorded in the scene's lights (SceneLight::castsShadow) and in stats.json; their maps are
// drawn (raster/shadow_maps.h) and sampled in shading (kernels/shadows.h).
#include <string>
#include <vector>

#include "scene/scene.h"

namespace ts {

// Applies `spec` to the lights' castsShadow:
//   ""      the scene's own marks (glTF extras "castsShadow"; the built-ins mark none)
//   "none"  no light casts a shadow
//   "all"   every light does
//   "N"     the N lights of largest range (directional lights first: their range is unbounded;
//           ties: the lower index), the thesis's "big lights have shadows enabled"
// Throws ts::Error (one line) for anything else or N beyond the light count.
void chooseShadowCasters(std::vector<SceneLight>& lights, const std::string& spec);

// How many lights cast a shadow.
size_t shadowCasterCount(const std::vector<SceneLight>& lights);

}  // namespace ts
