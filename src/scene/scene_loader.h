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
};

Scene loadScene(const std::string& spec, const SceneOptions& options);

// Built-in scenes (src/scene/builtin_*.cpp).
std::vector<std::string> builtinSceneNames();
std::vector<std::string> builtinLightSets(const std::string& scene);  // first = default
Scene makeBuiltinScene(const std::string& name, const std::string& lightSet, uint32_t seed);

// glTF 2.0 (src/scene/gltf_*.cpp).
Scene loadGltf(const std::string& path);
void exportGltf(const Scene& scene, const std::string& path);

}  // namespace ts
