#include "raster/draw_batches.h"

#include <algorithm>
#include <cfloat>
#include <cmath>

namespace ts {

std::vector<DrawBatch> drawBatches(const Scene& scene) {
  static const Material kDefaultMaterial;
  auto materialOf = [&](size_t t) -> const Material* {
    if (scene.triangleMaterial.empty())
      return scene.materials.empty() ? &kDefaultMaterial : &scene.materials[0];
    return &scene.materials[scene.triangleMaterial[t]];
  };
  std::vector<DrawBatch> batches;
  const size_t n = scene.triangleCount();
  for (size_t t = 0; t < n; ++t) {
    const Material* m = materialOf(t);
    if (batches.empty() || batches.back().material != m ||
        batches.back().triangles == kBatchTriangles)
      batches.push_back({uint32_t(t), 0, m, Bounds{}});
    DrawBatch& b = batches.back();
    ++b.triangles;
    for (int k = 0; k < 3; ++k) b.bounds.extend(scene.vertices[scene.indices[3 * t + k]].position);
  }
  return batches;
}

ViewBox viewBox(const Bounds& world, const glm::dmat4& viewFromWorld) {
  glm::dvec3 lo(DBL_MAX), hi(-DBL_MAX);
  for (int corner = 0; corner < 8; ++corner) {
    const glm::dvec3 p((corner & 1) ? world.max.x : world.min.x,
                       (corner & 2) ? world.max.y : world.min.y,
                       (corner & 4) ? world.max.z : world.min.z);
    const glm::dvec3 v = glm::dvec3(viewFromWorld * glm::dvec4(p, 1.0));
    lo = glm::min(lo, v);
    hi = glm::max(hi, v);
  }
  // The shader's float transform: each view coordinate is a sum of products of float matrix
  // entries (|R| <= 1) and float world coordinates, plus the float translation; its error is a
  // few ulps of the largest of those magnitudes. 1e-5 of them is ~80 float ulps: generous, and
  // still far below any light's range in the scenes.
  const double worldMagnitude =
      std::max({std::abs(double(world.min.x)), std::abs(double(world.min.y)),
                std::abs(double(world.min.z)), std::abs(double(world.max.x)),
                std::abs(double(world.max.y)), std::abs(double(world.max.z))});
  const double translation = glm::length(glm::dvec3(viewFromWorld[3]));
  const double margin = 1e-5 * (3.0 * worldMagnitude + translation);
  ViewBox box;
  box.min = glm::vec3(lo - margin);
  box.max = glm::vec3(hi + margin);
  // The double -> float rounding could move a bound inwards: one more float step outwards.
  for (int k = 0; k < 3; ++k) {
    box.min[k] = std::nextafter(box.min[k], -FLT_MAX);
    box.max[k] = std::nextafter(box.max[k], FLT_MAX);
  }
  return box;
}

}  // namespace ts
