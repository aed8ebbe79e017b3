#include "scene/shading_range.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "shading/shading_cpu.h"
#include "util/error.h"

namespace ts {
namespace {

double maxOf(glm::vec3 v) { return std::max({double(v.x), double(v.y), double(v.z)}); }

}  // namespace

void ShadingRangeTerms::addSurface(glm::vec3 kd, glm::vec3 ks, glm::vec3 emissive) {
  const double d = maxOf(glm::abs(kd));
  material = std::max(material, d + maxOf(glm::abs(ks)));
  diffuse = std::max(diffuse, d);
  emission = std::max(emission, maxOf(glm::abs(emissive)));
  if (!std::isfinite(d + maxOf(ks) + maxOf(emissive))) material = HUGE_VAL;
}

void ShadingRangeTerms::addLight(glm::vec3 color) { lights += maxOf(glm::abs(color)); }

ShadingRangeTerms shadingRangeTerms(const Scene& scene) {
  ShadingRangeTerms t;
  // The terms of both models a material carries (scene.h): the larger is what a pixel may hold.
  for (const auto& m : scene.materials)
    t.addSurface(glm::max(glm::abs(m.diffuse), glm::abs(m.baseColor)), m.specular, m.emissive);
  for (const auto& l : scene.lights) t.addLight(l.color);
  t.ambient = maxOf(glm::abs(scene.ambient));
  return t;
}

double shadingRangeBound(const ShadingRangeTerms& t) {
  // A light inside a pixel's dmin gives 1/dmin^2 (kernels/shading.h); the sum is over all lights,
  // as if every one reached the same pixel from as close as that.
  double bound = t.emission + t.ambient * t.diffuse +
                 t.lights / (TS_DMIN * TS_DMIN) * std::max(t.material, 1.0);
  return std::isfinite(bound) ? bound : HUGE_VAL;
}

double shadingRangeBound(const Scene& scene) { return shadingRangeBound(shadingRangeTerms(scene)); }

void checkShadingRange(const ShadingRangeTerms& terms, const std::string& what) {
  double bound = shadingRangeBound(terms);
  if (bound <= kShadingRangeLimit) return;
  std::ostringstream s;
  s << what << ": its light colours and material values can shade a pixel to ";
  if (std::isfinite(bound)) s << bound;
  else s << "a value that is not finite";
  s << ", beyond what fp32 shading holds (" << kShadingRangeLimit
    << "); scale the lights' intensities or the materials down";
  throw Error(s.str());
}

void checkShadingRange(const Scene& scene) {
  checkShadingRange(shadingRangeTerms(scene), "scene '" + scene.name + "'");
}

}  // namespace ts
