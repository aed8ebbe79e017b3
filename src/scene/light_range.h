#pragma once
// The attenuation-threshold method: a light's range is where its peak intensity, falling off as
// I/d^2, drops to a threshold t (e.g. 5/256: the last step an 8-bit display shows). A smaller
// range culls more and is less exact — a speed/error knob measured by the benchmark.
#include <vector>

#include "scene/scene.h"

namespace ts {

// sqrt(max(C.r, C.g, C.b) / t), at least TS_DMIN (kernels/shading.h). t must be > 0.
float rangeFromThreshold(glm::vec3 color, float threshold);

// Replaces the range of every light that has one (point, spot) with
// rangeFromThreshold(color, threshold).
void applyThresholdRanges(std::vector<Light>& lights, float threshold);

}  // namespace ts
