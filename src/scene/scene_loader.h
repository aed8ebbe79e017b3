#pragma once
// Entry points that turn a --scene spec into a Scene: "builtin:NAME" or a .gltf/.glb path.
#include <string>
#include <vector>

#include "scene/scene.h"

namespace ts {

struct SceneOptions {
  std::string lightSet;  // "" = the scene's default (built-ins) or the file's own lights (glTF)
  uint32_t seed = 1;     // built-in scenes are deterministic for a seed
  int lightCount = -1;   // -1 = the light set's own count; else exactly N lights
  float lightRange = 0.0f;  // > 0 overrides every light's range
  // Built-in scenes only: a comma list of variants (applyVariants), "" = the scene as designed.
  std::string variant;
};

// The built-in scenes' variants, for measuring what a scene's needs cost (scenes/README.md):
//   diffuse             no specular and no emission in any material (Lambert only)
//   no-emission         no emission
//   metallic-roughness  materials written for glTF's model (from their Blinn-Phong terms)
//   spot                every second light is a spot light pointing down
//   sun                 one directional light (a sun) added
std::vector<std::string> builtinVariants();
// Applies a comma list of variants to a built-in scene; throws ts::Error for an unknown one.
void applyVariants(Scene& scene, const std::string& variants, uint32_t seed);

Scene loadScene(const std::string& spec, const SceneOptions& options);

// Built-in scenes (src/scene/builtin_*.cpp).
std::vector<std::string> builtinSceneNames();
std::vector<std::string> builtinLightSets(const std::string& scene);  // first = default
Scene makeBuiltinScene(const std::string& name, const std::string& lightSet, uint32_t seed);

// glTF 2.0 (src/scene/gltf_*.cpp).
Scene loadGltf(const std::string& path);
void exportGltf(const Scene& scene, const std::string& path);

}  // namespace ts
