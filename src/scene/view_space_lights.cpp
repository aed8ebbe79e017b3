#include "scene/view_space_lights.h"

namespace ts {

ViewLights toViewSpace(const std::vector<SceneLight>& lights, const glm::dmat4& viewFromWorld) {
  ViewLights out;
  const glm::mat3 rotation{glm::dmat3(viewFromWorld)};
  for (const auto& l : lights) {
    if (l.type == SceneLightType::Directional) {
      out.addDirectional(-(rotation * l.direction), l.color);
      continue;
    }
    glm::vec3 p = glm::vec3(viewFromWorld * glm::dvec4(l.position, 1.0));
    if (l.type == SceneLightType::Spot)
      out.addSpot(p, l.range, l.color, rotation * l.direction, l.innerConeAngle, l.outerConeAngle);
    else out.addPoint(p, l.range, l.color);
  }
  return out;
}

}  // namespace ts
