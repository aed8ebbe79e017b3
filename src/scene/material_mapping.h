#pragma once
// The mappings between the two shading models' material terms (documented in scenes/README.md,
// "Materials in both models"). A material keeps the terms of the model it was written in and gets
// the other model's from these, so any scene can be shaded with either model.
#include <algorithm>
#include <cmath>

#include "scene/scene.h"

namespace ts {

// Blinn-Phong exponent from glTF roughness: alpha = roughness^2, s = 2/alpha^2 - 2, in [1, 2048].
inline float shininessFromRoughness(float roughness) {
  float alpha = std::max(roughness, 0.0f) * std::max(roughness, 0.0f);
  if (alpha <= 0.0f) return 2048.0f;
  return std::clamp(2.0f / (alpha * alpha) - 2.0f, 1.0f, 2048.0f);
}

// The inverse: roughness = sqrt(alpha), alpha = sqrt(2 / (s + 2)).
inline float roughnessFromShininess(float shininess) {
  float s = std::clamp(shininess, 0.0f, 2048.0f);
  return std::sqrt(std::sqrt(2.0f / (s + 2.0f)));
}

// Blinn-Phong terms of a metallic-roughness material: kd = base (1 - metallic) (with the base
// colour texture), ks = mix(F0, base, metallic) with the dielectric reflectance F0 (0.04, or
// KHR_materials_specular's), s from roughness. The metallic-roughness texture has no Blinn-Phong
// counterpart and is left out.
inline void fillBlinnPhongTerms(Material& m, glm::vec3 dielectricF0 = glm::vec3(0.04f)) {
  m.diffuse = m.baseColor * (1.0f - m.metallic);
  m.diffuseTexture = m.baseColorTexture;
  m.specular = glm::mix(dielectricF0, m.baseColor, m.metallic);
  m.shininess = shininessFromRoughness(m.roughness);
}

// Metallic-roughness terms of a Blinn-Phong material. A strong specular colour (max ks >= 0.5)
// reads as a metal: metallic 1, base = ks tinted by the diffuse hue (kd / max kd); anything else
// as a dielectric: metallic 0, base = kd (and its texture). Roughness from the shininess.
inline void fillMetallicRoughnessTerms(Material& m) {
  float ksMax = std::max({m.specular.x, m.specular.y, m.specular.z});
  float kdMax = std::max({m.diffuse.x, m.diffuse.y, m.diffuse.z});
  if (ksMax >= 0.5f) {
    glm::vec3 hue = kdMax > 0.0f ? m.diffuse / kdMax : glm::vec3(1.0f);
    m.baseColor = glm::clamp(ksMax * hue, 0.0f, 1.0f);
    m.metallic = 1.0f;
    m.baseColorTexture = -1;
  } else {
    m.baseColor = m.diffuse;
    m.metallic = 0.0f;
    m.baseColorTexture = m.diffuseTexture;
  }
  m.roughness = roughnessFromShininess(m.shininess);
  m.metallicRoughnessTexture = -1;
}

}  // namespace ts
