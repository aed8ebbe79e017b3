#include "gbuffer/gbuffer_checks.h"

#include <cmath>
#include <iomanip>
#include <sstream>

#include "util/error.h"

namespace ts {

std::string fullPrecision(double v) {
  std::ostringstream s;
  s << std::setprecision(9) << v;
  return s.str();
}

std::string pixelText(int x, int y) {
  return "pixel (" + std::to_string(x) + ", " + std::to_string(y) + ")";
}

void checkFiniteValue(const std::string& where, const std::string& what, float v, int x, int y) {
  if (std::isfinite(v)) return;
  throw Error(where + ": " + what + " is " + (std::isnan(v) ? "NaN" : "infinite") + " at " +
              pixelText(x, y));
}

void checkNotNegative(const std::string& where, const std::string& what, float v, int x, int y) {
  if (v >= 0.0f) return;
  throw Error(where + ": " + what + " is " + fullPrecision(v) + " at " + pixelText(x, y) +
              ", below 0");
}

namespace {
constexpr float kNormalLengthMin = 0.5f, kNormalLengthMax = 2.0f;
}  // namespace

void checkNormalLength(const std::string& where, glm::vec3 n, int x, int y) {
  const double length = glm::length(glm::dvec3(n));
  if (length >= kNormalLengthMin && length <= kNormalLengthMax) return;
  throw Error(where + ": the normal (\"normal\") at " + pixelText(x, y) + " is " +
              (length == 0.0 ? std::string("zero") : "of length " + fullPrecision(length)) +
              ", not a unit vector (lengths 0.5 to 2 are accepted and renormalised)");
}

ShadingRangeTerms checkGBufferValues(const GBuffer& g, float znear, const std::string& where) {
  static const char* const kPlaneNames[] = {"normal", "diffuse", "specular", "emissive"};
  const std::vector<glm::vec4>* planes[] = {&g.normal, &g.diffuse, &g.specular, &g.emissive};
  ShadingRangeTerms range;
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      const size_t i = size_t(y) * size_t(g.width) + size_t(x);
      const float depth = g.depth[i];
      checkFiniteValue(where, "depth", depth, x, y);
      if (depth == 0.0f) continue;  // background: its other planes are never read
      if (depth < 0.0f)
        throw Error(where + ": depth " + fullPrecision(depth) + " at " + pixelText(x, y) +
                    " is negative (linear view depth is > 0 in front of the camera, 0 background)");
      if (inFrontOfNearPlane(depth, znear))
        throw Error(where + ": depth " + fullPrecision(depth) + " at " + pixelText(x, y) +
                    " is in front of the camera's near plane " + fullPrecision(znear) +
                    "; nothing nearer than the near plane is drawn, and the culling would drop "
                    "lights there");
      for (int p = 0; p < 4; ++p)
        for (int c = 0; c < 4; ++c) {
          const std::string what =
              std::string("plane '") + kPlaneNames[p] + "' component " + std::to_string(c);
          const float v = (*planes[p])[i][c];
          checkFiniteValue(where, what, v, x, y);
          if (p != int(GBufferPlane::Normal)) checkNotNegative(where, what, v, x, y);
        }
      checkNormalLength(where, glm::vec3(g.normal[i]), x, y);
      range.addSurface(glm::vec3(g.diffuse[i]),
                       g.model == ShadingModel::BlinnPhong ? glm::vec3(g.specular[i])
                                                           : glm::vec3(0.0f),  // ks.R: roughness
                       glm::vec3(g.emissive[i]));
    }
  return range;
}

}  // namespace ts
