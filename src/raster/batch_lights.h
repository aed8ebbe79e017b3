#pragma once
// Which lights touch which draw batches (raster/draw_batches.h), found on the host each frame:
// the per-batch light lists of `forward-single` ("the minimal set of lights for each batch",
// Olsson & Assarsson) and, transposed, the batches each of `forward`'s light passes draws.
// A point or spot light's volume is its range sphere (a spot's cone is not tested: the sphere
// contains it, so the lists are conservative, never short).
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "raster/draw_batches.h"
#include "shading/view_lights.h"

namespace ts {

// Lists of indices, one per owner, packed: owner o's list is items[offsets[o] .. offsets[o] +
// counts[o]), in increasing index order.
struct IndexLists {
  std::vector<uint32_t> offsets, counts, items;
  size_t size() const { return counts.size(); }
  uint32_t longest() const;
};

// Whether the sphere (xyz centre, w radius) reaches into the box: its centre's distance to the
// box below the radius (with a float ulp's slack: the shader's own cut is d^2 < r^2 in float).
bool sphereTouchesBox(glm::vec4 positionRange, const ViewBox& box);

// Per batch, the point and spot lights whose range sphere touches its view-space box.
IndexLists batchLightLists(const std::vector<ViewBox>& boxes, const ViewLights& lights);

// The same pairs listed the other way: per target (0 .. targets-1), the owners whose lists hold
// it, in increasing order (a light's batches from the batches' lights).
IndexLists transposeLists(const IndexLists& lists, size_t targets);

}  // namespace ts
