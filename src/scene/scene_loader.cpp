// Scene spec dispatch ("builtin:NAME" or a .gltf/.glb path) and the light-count/range options.
#include "scene/scene_loader.h"

#include <algorithm>
#include <cctype>
#include <cmath>

#include "scene/builtin_scenes.h"
#include "util/error.h"

namespace ts {

namespace {

std::string joined(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

bool endsWith(std::string s, const std::string& suffix) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

Scene makeBuiltin(const std::string& name, const std::string& lightSet, uint32_t seed,
                  int lightCount) {
  if (name == "street") return makeStreetScene(lightSet, seed, lightCount);
  if (name == "atrium") return makeAtriumScene(lightSet, seed, lightCount);
  throw Error("unknown built-in scene '" + name + "' (known: " + joined(builtinSceneNames()) + ")");
}

}  // namespace

glm::vec3 hueColor(float hue, float saturation) {
  // Hue in [0,1) around the colour wheel; value 1; saturation 0 = white.
  float h = (hue - std::floor(hue)) * 6.0f;
  glm::vec3 rgb(glm::clamp(std::fabs(h - 3.0f) - 1.0f, 0.0f, 1.0f),
                glm::clamp(2.0f - std::fabs(h - 2.0f), 0.0f, 1.0f),
                glm::clamp(2.0f - std::fabs(h - 4.0f), 0.0f, 1.0f));
  return glm::mix(glm::vec3(1.0f), rgb, glm::clamp(saturation, 0.0f, 1.0f));
}

std::vector<std::string> builtinSceneNames() { return {"street", "atrium"}; }

std::vector<std::string> builtinLightSets(const std::string& scene) {
  if (scene == "street") return streetLightSets();
  if (scene == "atrium") return atriumLightSets();
  throw Error("unknown built-in scene '" + scene + "' (known: " + joined(builtinSceneNames()) + ")");
}

Scene makeBuiltinScene(const std::string& name, const std::string& lightSet, uint32_t seed) {
  return makeBuiltin(name, lightSet, seed, -1);
}

Scene loadScene(const std::string& spec, const SceneOptions& options) {
  if (options.lightCount < -1)
    throw Error("light count must be >= 0 (or -1 for the light set's own), got " +
                std::to_string(options.lightCount));
  if (!(options.lightRange >= 0.0f) || !std::isfinite(options.lightRange))
    throw Error("light range must be > 0 (or 0 to keep each light's own), got " +
                std::to_string(options.lightRange));

  Scene scene;
  const std::string prefix = "builtin:";
  if (spec.compare(0, prefix.size(), prefix) == 0) {
    scene = makeBuiltin(spec.substr(prefix.size()), options.lightSet, options.seed,
                        options.lightCount);
  } else if (endsWith(spec, ".gltf") || endsWith(spec, ".glb")) {
    if (!options.lightSet.empty() && options.lightSet != "file")
      throw Error("light set '" + options.lightSet + "' does not apply to glTF scene " + spec +
                  " (valid: file, its own KHR_lights_punctual point lights)");
    scene = loadGltf(spec);
    if (options.lightCount >= 0) {
      if (size_t(options.lightCount) > scene.lights.size())
        throw Error("light count " + std::to_string(options.lightCount) + " is more than the " +
                    std::to_string(scene.lights.size()) + " point light(s) in " + spec);
      scene.lights.resize(size_t(options.lightCount));
    }
  } else {
    throw Error("unknown scene spec '" + spec + "': use builtin:NAME (" +
                joined(builtinSceneNames()) + ") or a .gltf/.glb file");
  }
  if (options.lightRange > 0.0f)
    for (auto& l : scene.lights) l.range = options.lightRange;
  return scene;
}

}  // namespace ts
