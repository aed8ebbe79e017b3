#pragma once
// The attenuation-threshold method: a light's range is where its peak intensity, falling off as
// I/d^2, drops to a threshold t (e.g. 5/256: the last step an 8-bit display shows). A smaller
// range culls more and is less exact — a speed/error knob measured by the benchmark.
#include <vector>

#include "scene/scene.h"

namespace ts {

// sqrt(max(C.r, C.g, C.b) / t), at least TS_DMIN (kernels/shading.h), at most the largest float
// (computed in double: a tiny t or a huge C would overflow float; every range beyond ~1e19 shades
// alike, as an infinite one). t must be finite and > 0.
float rangeFromThreshold(glm::vec3 color, float threshold);

// Replaces the range of every light that has one (point, spot) with
// rangeFromThreshold(color, threshold).
void applyThresholdRanges(std::vector<SceneLight>& lights, float threshold);

}  // namespace ts
