#pragma once
// The shadow maps of a frame against exact visibility (issue #18; docs/shadows.md, "The maps
// against exact visibility"): every (pixel, shadow-casting light) pair's exact answer
// (exact_visibility.h), the double reference shaded with the maps and with exact visibility in
// their place, the wrong pairs and the image error. `render --exact-visibility` and `bench
// --shadow-error` both measure with this.
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "reference/reference.h"
#include "render/frame_setup.h"
#include "scene/scene.h"

namespace ts {

// The most lights visibility_exact.exr holds a channel of (stats.json counts every light).
constexpr size_t kExactVisibilityChannels = 16;
// The most memory the per-pair planes may take (a visibility byte and a map factor double per
// pixel and shadow-casting light): `--shadows all` on a big frame asks for gigabytes, refused in
// one line before any ray is cast rather than left to the allocator.
constexpr uint64_t kExactVisibilityMaxPairBytes = uint64_t(2) << 30;

struct ExactVisibilityResult {
  int width = 0;
  int height = 0;
  std::vector<std::string> channels;  // "light<index>", one per light of the image
  std::vector<float> image;           // interleaved: the kVisibility* codes 0, 1, 2 as floats
  nlohmann::json stats;               // stats.json's exact_visibility
  std::string summary;                // the lines `render` prints
  // The double reference shaded with exact visibility in place of the maps (the "perfect
  // shadow"), and per pixel its largest channel difference from the map-shaded one.
  ReferenceImage exactReference;
  std::vector<float> shadowError;
  std::vector<float> wrongPairs;  // per pixel: its wrong (false shadow + light leak) pairs
};

// `frame` of `scene` (its G-buffer, camera and lights with their maps attached), shaded from
// `planes`. Throws ts::Error (one line) without a shadow-casting light or beyond the pair planes'
// memory limit.
ExactVisibilityResult measureAgainstExactVisibility(const Scene& scene, const PreparedFrame& frame,
                                                    const EncodedGBuffer& planes);

}  // namespace ts
