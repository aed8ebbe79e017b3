#pragma once
// Internal to src/scene/: the glTF <-> tileshade mappings shared by the loader and the exporter
// (documented in scenes/README.md). The material terms of both shading models are mapped in
// scene/material_mapping.h.
#include <algorithm>
#include <cmath>

#include "scene/material_mapping.h"

namespace ts::gltf {

// Attenuation threshold for lights without a range (glTF: infinite): r = sqrt(peak / t).
constexpr float kLightThreshold = 5.0f / 256.0f;

// sRGB transfer function, 8-bit code or [0,1] value to linear, and back.
inline float srgbToLinear(float c) {
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}
inline float linearToSrgb(float c) {
  c = std::clamp(c, 0.0f, 1.0f);
  return c <= 0.0031308f ? c * 12.92f : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}

}  // namespace ts::gltf
