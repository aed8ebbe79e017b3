#include "reference/transparent_missed.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "reference/transparent_composite.h"
#include "util/error.h"

namespace ts {
namespace {

bool nonZero(const glm::dvec3& v) { return v.x != 0.0 || v.y != 0.0 || v.z != 0.0; }

// The fragment's slice as the shader (shaders/tiled_forward.frag) and clustered-forward's opaque
// assignment find it, in float from its own view depth. Where float rounding of log could put a
// fragment one slice off, both slices' bounds hold it (clustered-forward widens them), so a
// correct grid lists its lights in either.
int fragmentSlice(const FragmentLists& lists, const TransparentFragment& f) {
  const float z = -f.position.z;
  return int(
      std::clamp(std::log(z / lists.sliceNear) * lists.sliceScale, 0.0f, float(lists.slices - 1)));
}

std::string where(const TransparentFragment& f) {
  return "transparent fragment at (" + std::to_string(f.x) + ", " + std::to_string(f.y) + ")";
}

}  // namespace

size_t transparentFragmentBin(const FragmentLists& lists, const TransparentFragment& f) {
  size_t bin = 0;
  if (lists.byBatch) {
    if (f.batch < 0) throw Error("the " + where(f) + " records no draw batch");
    bin = size_t(f.batch);
  } else {
    if (lists.tileW < 1 || lists.tileH < 1 || lists.tilesX < 1 || lists.slices < 1)
      throw Error("the transparent fragments' lists have no tiles");
    if (f.x < 0 || f.y < 0 || f.x / lists.tileW >= lists.tilesX)
      throw Error("the " + where(f) + " lies outside the tiles");
    const size_t tile =
        size_t(f.y / lists.tileH) * size_t(lists.tilesX) + size_t(f.x / lists.tileW);
    bin = tile * size_t(lists.slices) + size_t(lists.slices > 1 ? fragmentSlice(lists, f) : 0);
  }
  if (bin >= lists.binCount.size() || bin >= lists.binOffset.size())
    throw Error("the " + where(f) + " falls in list " + std::to_string(bin) + " of " +
                std::to_string(lists.binCount.size()));
  return bin;
}

uint64_t countMissedTransparent(const FragmentLists& lists,
                                const std::vector<TransparentFragment>& frags,
                                const ViewLights& lights, int model,
                                const EncodedGBuffer& gbuffer) {
  // Each list sorted once for a binary search (as countMissedContributions does).
  std::vector<std::vector<uint32_t>> listed(lists.binCount.size());
  for (size_t b = 0; b < listed.size(); ++b) {
    const size_t first = lists.binOffset.at(b), count = lists.binCount[b];
    if (first + count > lists.binLights.size())
      throw Error("the transparent fragments' list " + std::to_string(b) + " runs past its lights");
    listed[b].assign(lists.binLights.begin() + long(first),
                     lists.binLights.begin() + long(first + count));
    std::sort(listed[b].begin(), listed[b].end());
  }
  uint64_t misses = 0;
  const int shading = int(gbuffer.model);
  for (const TransparentFragment& f : frags) {
    const std::vector<uint32_t>& list = listed[transparentFragmentBin(lists, f)];
    const SurfaceD s = transparentSurface(f, gbuffer);
    const shading_d::ts_shading_point p = transparentShadingPoint(s, shading);
    for (size_t i = 0; i < lights.size(); ++i)
      if (nonZero(transparentPunctualLight(p, s, lights, i, model, shading)) &&
          !std::binary_search(list.begin(), list.end(), uint32_t(i)))
        ++misses;
  }
  return misses;
}

}  // namespace ts
