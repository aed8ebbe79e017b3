#include "raster/batch_lights.h"

#include <algorithm>

namespace ts {

uint32_t IndexLists::longest() const {
  return counts.empty() ? 0 : *std::max_element(counts.begin(), counts.end());
}

bool sphereTouchesBox(glm::vec4 positionRange, const ViewBox& box) {
  double d2 = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double c = positionRange[k];
    const double nearest = std::clamp(c, double(box.min[k]), double(box.max[k]));
    d2 += (c - nearest) * (c - nearest);
  }
  const double r = positionRange.w;
  return d2 <= r * r * (1.0 + 1e-6);
}

IndexLists batchLightLists(const std::vector<ViewBox>& boxes, const ViewLights& lights) {
  IndexLists lists;
  lists.offsets.reserve(boxes.size());
  lists.counts.reserve(boxes.size());
  for (const ViewBox& box : boxes) {
    lists.offsets.push_back(uint32_t(lists.items.size()));
    for (size_t i = 0; i < lights.size(); ++i)
      if (sphereTouchesBox(lights.positionRange[i], box)) lists.items.push_back(uint32_t(i));
    lists.counts.push_back(uint32_t(lists.items.size()) - lists.offsets.back());
  }
  return lists;
}

IndexLists transposeLists(const IndexLists& lists, size_t targets) {
  IndexLists out;
  out.counts.assign(targets, 0);
  for (uint32_t item : lists.items) ++out.counts[item];
  out.offsets.resize(targets);
  uint32_t at = 0;
  for (size_t t = 0; t < targets; ++t) {
    out.offsets[t] = at;
    at += out.counts[t];
  }
  out.items.resize(at);
  std::vector<uint32_t> cursor = out.offsets;
  // Owners in increasing order, so each target's list is too.
  for (size_t o = 0; o < lists.size(); ++o)
    for (uint32_t k = 0; k < lists.counts[o]; ++k)
      out.items[cursor[lists.items[lists.offsets[o] + k]]++] = uint32_t(o);
  return out;
}

}  // namespace ts
