#include "render/receiver_rounding.h"

#include <algorithm>
#include <cmath>

namespace ts {

ReceiverRounding receiverRounding(const Scene& scene, const glm::dmat4& viewFromWorld) {
  double vertices = 0.0;
  for (const Vertex& v : scene.vertices)
    for (int c = 0; c < 3; ++c) vertices = std::max(vertices, std::abs(double(v.position[c])));
  const glm::dvec3 t(viewFromWorld[3]);
  ReceiverRounding r;
  r.worldMagnitude = vertices + std::max({std::abs(t.x), std::abs(t.y), std::abs(t.z)});
  return r;
}

}  // namespace ts
