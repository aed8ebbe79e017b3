#pragma once
// Internal to src/scene/: the built-in scene generators behind makeBuiltinScene/loadScene.
// lightCount -1 = the light set's own count, else exactly that many lights by the set's rule.
#include <cstdint>
#include <string>
#include <vector>

#include "scene/scene.h"

namespace ts {

std::vector<std::string> streetLightSets();  // first = default
Scene makeStreetScene(const std::string& lightSet, uint32_t seed, int lightCount);

std::vector<std::string> atriumLightSets();  // first = default
Scene makeAtriumScene(const std::string& lightSet, uint32_t seed, int lightCount);

// `--variant glass` (glass_variant.cpp): BLEND panes and volumes where frame 0 looks; throws
// ts::Error for a scene other than the built-ins.
void addGlass(Scene& scene);

// HSV-ish hue to an RGB colour whose largest component is 1 (saturation in [0,1]).
glm::vec3 hueColor(float hue, float saturation);

}  // namespace ts
