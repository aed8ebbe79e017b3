#include "shading/view_lights.h"

#include <algorithm>
#include <cmath>

namespace ts {

void ViewLights::addPoint(glm::vec3 position, float range, glm::vec3 color) {
  positionRange.emplace_back(position, range);
  this->color.emplace_back(color, 1.0f);
  spot.emplace_back(glm::vec3(0.0f), -1.0f);
  shadow.push_back(-1);
}

void ViewLights::addSpot(glm::vec3 position, float range, glm::vec3 color, glm::vec3 axis,
                         float innerConeAngle, float outerConeAngle) {
  // The cos of a float pi/2 (4.4e-8 above pi/2) is -4.4e-8: the cone is a half-space, cos 0.
  float cosInner = std::max(0.0f, std::cos(innerConeAngle));
  float cosOuter = std::max(0.0f, std::cos(outerConeAngle));
  positionRange.emplace_back(position, range);
  // glTF's recommended angle scale: 1 / max(0.001, cos inner - cos outer).
  this->color.emplace_back(color, 1.0f / std::max(1e-3f, cosInner - cosOuter));
  spot.emplace_back(glm::normalize(axis), cosOuter);
  shadow.push_back(-1);
}

void ViewLights::addDirectional(glm::vec3 towardsLight, glm::vec3 color) {
  directionalDir.emplace_back(glm::normalize(towardsLight), 0.0f);
  directionalColor.emplace_back(color, 0.0f);
  directionalShadow.push_back(-1);
}

}  // namespace ts
