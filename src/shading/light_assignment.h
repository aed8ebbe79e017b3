#pragma once
// What a technique's culling produced, in a form the reference can check without knowing the
// technique (countMissedContributions): data below both.
#include <cstdint>
#include <optional>
#include <vector>

#include <glm/glm.hpp>

namespace ts {

// Which lights a pixel considers, for conservativeness tests: either bins (tiles/clusters) that
// pixels map to, or per-light screen rectangles (traditional deferred), or both.
// --blend blend: the lists a technique's transparent fragments shaded, and the rule by which a
// fragment finds its own, as the fragment shader does (countMissedTransparent,
// reference/transparent_missed.h): its draw batch's list (forward, forward-single: bins =
// batches), or its tile's (tileW x tileH pixels, tilesX per row) and, with slices > 1, the slice
// of its own view depth z: int(clamp(log(z / sliceNear) * sliceScale, 0, slices - 1)), bin =
// tile * slices + slice (clustered-forward, shading/forward_grid.h).
struct FragmentLists {
  std::vector<uint32_t> binOffset, binCount, binLights;  // per bin: a range of binLights
  bool byBatch = false;
  int tileW = 0, tileH = 0, tilesX = 0;
  int slices = 1;
  float sliceNear = 1.0f, sliceScale = 0.0f;
};

struct LightAssignment {
  std::vector<uint32_t> binOffset, binCount, binLights;  // per bin: a range of binLights
  std::vector<int32_t> pixelBin;                         // per pixel; -1 = shades no light
  std::vector<glm::ivec4> lightRect;  // per light: x0, y0, x1, y1 (exclusive); empty = unused
  // Set by every technique that drew transparent surfaces; unset otherwise.
  std::optional<FragmentLists> transparent;
};

}  // namespace ts
