#pragma once
// `render --exact-visibility`: the exact visibility of every (pixel, shadow-casting light) pair
// of the frame (visibility/exact_visibility.h), its image and its stats.json record.
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "reference/reference.h"
#include "tileshade/tileshade.h"

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

// Throws ts::Error (one line) for a frame without the scene's triangles (an imported G-buffer)
// or without a shadow-casting light.
ExactVisibilityResult exactVisibility(const Frame& frame);

}  // namespace ts
