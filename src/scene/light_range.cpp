#include "scene/light_range.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "shading/shading_cpu.h"
#include "util/error.h"

namespace ts {

float rangeFromThreshold(glm::vec3 color, float threshold) {
  if (!(threshold > 0.0f) || !std::isfinite(threshold))
    throw Error("light threshold must be finite and > 0, got " + std::to_string(threshold));
  double peak = std::max({double(color.x), double(color.y), double(color.z), 0.0});
  double r = std::sqrt(peak / double(threshold));
  return float(std::clamp(r, double(TS_DMIN), double(std::numeric_limits<float>::max())));
}

void applyThresholdRanges(std::vector<SceneLight>& lights, float threshold) {
  for (auto& l : lights)
    if (l.hasRange()) l.range = rangeFromThreshold(l.color, threshold);
}

}  // namespace ts
