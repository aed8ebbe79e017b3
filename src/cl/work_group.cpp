#include "cl/work_group.h"

#include <algorithm>

#include "cl/cl_context.h"

namespace ts {

GroupLimit deviceGroupLimit(const ClContext& cl) {
  GroupLimit limit;
  limit.size = std::max<size_t>(cl.maxWorkGroupSize(), 1);
  const auto& items = cl.info().maxWorkItemSizes;
  for (size_t d = 0; d < 2; ++d)
    limit.items[d] = std::max<size_t>(d < items.size() ? items[d] : limit.size, 1);
  return limit;
}

GroupLimit groupLimit(const ClContext& cl, const cl::Kernel& kernel) {
  GroupLimit limit = deviceGroupLimit(cl);
  size_t kernelMax = kernel.getWorkGroupInfo<CL_KERNEL_WORK_GROUP_SIZE>(cl.device());
  if (kernelMax > 0) limit.size = std::min(limit.size, kernelMax);
  return limit;
}

cl::NDRange GroupShape::global(size_t width, size_t height) const {
  return cl::NDRange(roundUp(std::max<size_t>(width, 1), x),
                     roundUp(std::max<size_t>(height, 1), y));
}

size_t powerOfTwoGroup(size_t preferred, const GroupLimit& limit) {
  size_t cap = std::min({preferred, limit.size, limit.items[0]});
  size_t n = 1;
  while (n * 2 <= cap) n *= 2;
  return n;
}

GroupShape fitGroup(size_t preferredX, size_t preferredY, const GroupLimit& limit) {
  GroupShape g{std::max<size_t>(std::min(preferredX, limit.items[0]), 1),
               std::max<size_t>(std::min(preferredY, limit.items[1]), 1)};
  while (g.size() > limit.size) {
    size_t& side = g.x >= g.y ? g.x : g.y;
    side = (side + 1) / 2;
  }
  return g;
}

GroupShape tileDividingGroup(int tileW, int tileH, const GroupLimit& limit) {
  GroupShape best;
  for (size_t x = 1; x <= 16 && x <= size_t(tileW) && x <= limit.items[0]; ++x) {
    if (tileW % x) continue;
    for (size_t y = 1; y <= 16 && y <= size_t(tileH) && y <= limit.items[1]; ++y) {
      if (tileH % y || x * y > limit.size) continue;
      // Most work-items; of equal sizes the squarer (fewer rows of a tile per group).
      size_t gap = x > y ? x - y : y - x,
             bestGap = best.x > best.y ? best.x - best.y : best.y - best.x;
      if (x * y > best.size() || (x * y == best.size() && gap < bestGap)) best = {x, y};
    }
  }
  return best;
}

}  // namespace ts
