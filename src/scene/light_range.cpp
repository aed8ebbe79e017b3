#include "scene/light_range.h"

#include <algorithm>
#include <cmath>

#include "reference/shading_cpu.h"
#include "util/error.h"

namespace ts {

float rangeFromThreshold(glm::vec3 color, float threshold) {
  if (!(threshold > 0.0f)) throw Error("light threshold must be > 0");
  float peak = std::max({color.x, color.y, color.z});
  return std::max(std::sqrt(std::max(peak, 0.0f) / threshold), float(TS_DMIN));
}

void applyThresholdRanges(std::vector<Light>& lights, float threshold) {
  for (auto& l : lights)
    if (l.hasRange()) l.range = rangeFromThreshold(l.color, threshold);
}

}  // namespace ts
