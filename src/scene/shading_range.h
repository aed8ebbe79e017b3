#pragma once
// Whether fp32 shading can represent a scene's pixels: light colours and material terms that are
// each finite can still multiply past float's range in the kernels (a colour of 1e37 times the
// falloff's 1/dmin^2 = 100 and a diffuse of 10 is 1e40: inf, then NaN). Such a scene is refused
// with one clear error rather than rendered as inf/NaN (issue #12; docs/hard-cases.md).
#include <string>

#include "scene/scene.h"

namespace ts {

// The largest pixel value fp32 shading may have to hold, 1e37: float's largest is 3.4e38, and the
// kernels' intermediate products (C * falloff before * kd) and running sums need headroom.
constexpr double kShadingRangeLimit = 1e37;

// The largest magnitudes that bound a pixel's value, from a scene's materials and lights or from
// an imported G-buffer's planes and lights.json: one range check, whichever way values come in.
struct ShadingRangeTerms {
  double material = 0.0;  // largest kd + ks of one surface (kd: diffuse or base colour)
  double diffuse = 0.0;   // largest kd
  double emission = 0.0;  // largest emissive component
  double lights = 0.0;    // sum over lights of their largest colour component
  double ambient = 0.0;   // largest ambient component
  // Adds one surface's values (any component not finite makes the bound not finite).
  void addSurface(glm::vec3 kd, glm::vec3 ks, glm::vec3 emissive);
  void addLight(glm::vec3 color);
};
ShadingRangeTerms shadingRangeTerms(const Scene& scene);

// An upper bound of any pixel's value for `scene`: emission + ambient * diffuse + the sum over
// lights of max(C) / dmin^2 * the largest material's (kd + ks), with falloff <= 1/dmin^2, N.l <= 1
// and (N.h)^s <= 1 (textures taken as <= 1). Not finite when an input is not.
double shadingRangeBound(const ShadingRangeTerms& terms);
double shadingRangeBound(const Scene& scene);

// Throws ts::Error naming `what` (e.g. "scene 'x'" or a G-buffer file), the bound and the limit
// when the bound is not finite or exceeds kShadingRangeLimit.
void checkShadingRange(const ShadingRangeTerms& terms, const std::string& what);
void checkShadingRange(const Scene& scene);

}  // namespace ts
