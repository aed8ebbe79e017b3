#include "scene/shadow_casters.h"

#include <algorithm>
#include <numeric>

#include "util/error.h"
#include "util/short_text.h"

namespace ts {

void chooseShadowCasters(std::vector<SceneLight>& lights, const std::string& spec) {
  if (spec.empty()) return;
  if (spec == "none" || spec == "all") {
    for (SceneLight& l : lights) l.castsShadow = spec == "all";
    return;
  }
  const bool digits = spec.size() <= 9 && std::all_of(spec.begin(), spec.end(),
                                                      [](char c) { return c >= '0' && c <= '9'; });
  if (!digits)
    throw Error("--shadows: '" + shortText(spec) +
                "' is none of none, all or a light count N (the N lights of largest range)");
  const size_t n = size_t(std::stoul(spec));
  if (n > lights.size())
    throw Error("--shadows " + spec + ": the scene has only " + std::to_string(lights.size()) +
                " light(s)");
  std::vector<size_t> order(lights.size());
  std::iota(order.begin(), order.end(), size_t(0));
  auto reach = [&](size_t i) { return lights[i].hasRange() ? double(lights[i].range) : 1e300; };
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return reach(a) > reach(b); });
  for (SceneLight& l : lights) l.castsShadow = false;
  for (size_t k = 0; k < n; ++k) lights[order[k]].castsShadow = true;
}

size_t shadowCasterCount(const std::vector<SceneLight>& lights) {
  return size_t(std::count_if(lights.begin(), lights.end(),
                              [](const SceneLight& l) { return l.castsShadow; }));
}

}  // namespace ts
