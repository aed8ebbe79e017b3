#include "scene/shading_range.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "reference/shading_cpu.h"
#include "util/error.h"

namespace ts {
namespace {

double maxOf(glm::vec3 v) { return std::max({double(v.x), double(v.y), double(v.z)}); }

}  // namespace

double shadingRangeBound(const Scene& scene) {
  double material = 0.0, emission = 0.0, diffuse = 0.0;
  for (const auto& m : scene.materials) {
    // The terms of both models a material carries (scene.h): the larger is what a pixel may hold.
    double kd = std::max(maxOf(glm::abs(m.diffuse)), maxOf(glm::abs(m.baseColor)));
    material = std::max(material, kd + maxOf(glm::abs(m.specular)));
    emission = std::max(emission, maxOf(glm::abs(m.emissive)));
    diffuse = std::max(diffuse, kd);
    if (!std::isfinite(kd + maxOf(m.specular) + maxOf(m.emissive))) return HUGE_VAL;
  }
  double lights = 0.0;
  for (const auto& l : scene.lights) lights += maxOf(glm::abs(l.color));
  // A light inside a pixel's dmin gives 1/dmin^2 (kernels/shading.h); the sum is over all lights,
  // as if every one reached the same pixel from as close as that.
  double bound = emission + maxOf(glm::abs(scene.ambient)) * diffuse +
                 lights / (TS_DMIN * TS_DMIN) * std::max(material, 1.0);
  return std::isfinite(bound) ? bound : HUGE_VAL;
}

void checkShadingRange(const Scene& scene) {
  double bound = shadingRangeBound(scene);
  if (bound <= kShadingRangeLimit) return;
  std::ostringstream s;
  s << "scene '" << scene.name << "': its light colours and material values can shade a pixel to ";
  if (std::isfinite(bound)) s << bound;
  else s << "a value that is not finite";
  s << ", beyond what fp32 shading holds (" << kShadingRangeLimit
    << "); scale the lights' intensities or the materials down";
  throw Error(s.str());
}

}  // namespace ts
