#pragma once
// What a technique's culling produced, in a form the reference can check without knowing the
// technique (countMissedContributions): data below both.
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace ts {

// Which lights a pixel considers, for conservativeness tests: either bins (tiles/clusters) that
// pixels map to, or per-light screen rectangles (traditional deferred), or both.
struct LightAssignment {
  std::vector<uint32_t> binOffset, binCount, binLights;  // per bin: a range of binLights
  std::vector<int32_t> pixelBin;                         // per pixel; -1 = shades no light
  std::vector<glm::ivec4> lightRect;  // per light: x0, y0, x1, y1 (exclusive); empty = unused
};

}  // namespace ts
