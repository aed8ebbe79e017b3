#pragma once
// Internal to src/scene/: the glTF <-> tileshade mappings shared by the loader and the exporter
// (documented in scenes/README.md).
#include <algorithm>
#include <cmath>

namespace ts::gltf {

// Attenuation threshold for lights without a range (glTF: infinite): r = sqrt(peak / t).
constexpr float kLightThreshold = 5.0f / 256.0f;

// Blinn-Phong exponent from glTF roughness: alpha = roughness^2, s = 2/alpha^2 - 2, in [1, 2048].
inline float shininessFromRoughness(float roughness) {
  float alpha = std::max(roughness, 0.0f) * std::max(roughness, 0.0f);
  if (alpha <= 0.0f) return 2048.0f;
  return std::clamp(2.0f / (alpha * alpha) - 2.0f, 1.0f, 2048.0f);
}

// The inverse, used on export: roughness = sqrt(alpha), alpha = sqrt(2 / (s + 2)).
inline float roughnessFromShininess(float shininess) {
  float s = std::clamp(shininess, 0.0f, 2048.0f);
  return std::sqrt(std::sqrt(2.0f / (s + 2.0f)));
}

// sRGB transfer function, 8-bit code or [0,1] value to linear, and back.
inline float srgbToLinear(float c) {
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}
inline float linearToSrgb(float c) {
  c = std::clamp(c, 0.0f, 1.0f);
  return c <= 0.0031308f ? c * 12.92f : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}

}  // namespace ts::gltf
