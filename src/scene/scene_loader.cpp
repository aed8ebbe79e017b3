// Scene spec dispatch ("builtin:NAME" or a .gltf/.glb path) and the light-count/range options.
#include "scene/scene_loader.h"
#include "scene/shadow_casters.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <iostream>

#include "scene/builtin_scenes.h"
#include "scene/material_mapping.h"
#include "scene/mesh_builder.h"
#include "util/error.h"
#include "util/short_text.h"
#include "util/option_values.h"
#include "util/pi.h"

namespace ts {

namespace {

std::string joined(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

bool endsWith(std::string s, const std::string& suffix) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

Scene makeBuiltin(const std::string& name, const std::string& lightSet, uint32_t seed,
                  int lightCount) {
  if (name == "street") return makeStreetScene(lightSet, seed, lightCount);
  if (name == "atrium") return makeAtriumScene(lightSet, seed, lightCount);
  throw Error("unknown built-in scene '" + shortText(name) +
              "' (known: " + joined(builtinSceneNames()) + ")");
}

// Every second point light becomes a spot light at the same place, with the same colour and
// range, pointing down within 30 degrees of the vertical, outer cone 25..50 degrees, inner cone
// 60 % of it.
void makeSpots(Scene& scene, uint32_t seed) {
  SceneRandom rnd(seed * 2246822519u + 3266489917u);
  constexpr float kDeg = kPi / 180.0f;
  int k = 0;
  for (SceneLight& l : scene.lights) {
    if (l.type != SceneLightType::Point || k++ % 2 == 0) continue;
    float tilt = rnd.uniform(0.0f, 30.0f) * kDeg, azimuth = rnd.uniform(0.0f, 360.0f) * kDeg;
    glm::vec3 dir(std::sin(tilt) * std::cos(azimuth), -std::cos(tilt),
                  std::sin(tilt) * std::sin(azimuth));
    float outer = rnd.uniform(25.0f, 50.0f) * kDeg;
    l = SceneLight::spot(l.position, glm::normalize(dir), l.color, l.range, 0.6f * outer, outer);
  }
}

}  // namespace

std::vector<std::string> builtinVariants() {
  return {"diffuse", "no-emission", "metallic-roughness", "spot", "sun", "glass"};
}

void applyVariants(Scene& scene, const std::string& variants, uint32_t seed) {
  for (const std::string& v : splitList(variants)) {
    if (v == "diffuse" || v == "no-emission") {
      for (Material& m : scene.materials) {
        m.emissive = glm::vec3(0.0f);
        m.emissiveTexture = -1;
        if (v == "diffuse") m.specular = glm::vec3(0.0f);
      }
    } else if (v == "metallic-roughness") {
      // Now written for glTF's model: its terms are the author's, Blinn-Phong's follow from them.
      for (Material& m : scene.materials) {
        if (m.model == ShadingModel::BlinnPhong) fillMetallicRoughnessTerms(m);
        m.model = ShadingModel::MetallicRoughness;
        fillBlinnPhongTerms(m);
      }
    } else if (v == "spot") {
      makeSpots(scene, seed);
    } else if (v == "sun") {
      // Low in the sky, warm; about as bright as the brighter lit pixels of the built-ins.
      scene.lights.push_back(SceneLight::directional(glm::normalize(glm::vec3(0.45f, -0.6f, 0.35f)),
                                                     glm::vec3(0.32f, 0.29f, 0.24f)));
    } else if (v == "glass") {
      addGlass(scene);
    } else {
      throw Error("unknown scene variant '" + shortText(v) +
                  "' (known: " + joined(builtinVariants()) + ")");
    }
  }
  // Materials written for Blinn-Phong also carry metallic-roughness terms (and the other way
  // round), so every scene can be shaded with either model.
  for (Material& m : scene.materials)
    if (m.model == ShadingModel::BlinnPhong) fillMetallicRoughnessTerms(m);
}

glm::vec3 hueColor(float hue, float saturation) {
  // Hue in [0,1) around the colour wheel; value 1; saturation 0 = white.
  float h = (hue - std::floor(hue)) * 6.0f;
  glm::vec3 rgb(glm::clamp(std::fabs(h - 3.0f) - 1.0f, 0.0f, 1.0f),
                glm::clamp(2.0f - std::fabs(h - 2.0f), 0.0f, 1.0f),
                glm::clamp(2.0f - std::fabs(h - 4.0f), 0.0f, 1.0f));
  return glm::mix(glm::vec3(1.0f), rgb, glm::clamp(saturation, 0.0f, 1.0f));
}

std::vector<std::string> builtinSceneNames() { return {"street", "atrium"}; }

void printSceneWarnings(const std::string& name, const std::vector<std::string>& warnings) {
  for (const auto& w : warnings) std::cerr << "tileshade: warning: " << name << ": " << w << "\n";
}

std::vector<std::string> builtinLightSets(const std::string& scene) {
  if (scene == "street") return streetLightSets();
  if (scene == "atrium") return atriumLightSets();
  throw Error("unknown built-in scene '" + shortText(scene) +
              "' (known: " + joined(builtinSceneNames()) + ")");
}

Scene makeBuiltinScene(const std::string& name, const std::string& lightSet, uint32_t seed) {
  return makeBuiltin(name, lightSet, seed, -1);
}

std::vector<std::string> thesisLightSets() {
  return {"thesis-small", "thesis-big", "thesis-big-shadows", "thesis-mixed"};
}

std::vector<SceneLight> placeThesisLights(const Bounds& bounds, const std::string& set,
                                          uint32_t seed, int count) {
  const auto known = thesisLightSets();
  if (std::find(known.begin(), known.end(), set) == known.end())
    throw Error("unknown thesis light set '" + shortText(set) + "' (valid: " + joined(known) + ")");
  if (!(bounds.min.x <= bounds.max.x))
    throw Error("light set " + set + " is placed from the scene's geometry, and it has none");
  const bool mixed = set == "thesis-mixed", allBig = set != "thesis-small" && !mixed;
  const bool bigCast = set != "thesis-small" && set != "thesis-big";
  if (count < 0) count = set == "thesis-small" || mixed ? 128 : 16;
  const float diagonal = glm::length(bounds.extent());
  const glm::vec3 lo = bounds.min + 0.05f * bounds.extent(),
                  hi = bounds.max - 0.05f * bounds.extent();
  SceneRandom rnd(seed * 2654435761u + 40503u);
  std::vector<SceneLight> lights;
  lights.reserve(size_t(count));
  for (int k = 0; k < count; ++k) {
    const bool big = allBig || (mixed && k % 32 == 0);
    SceneLight l;
    const float x = rnd.uniform(lo.x, hi.x);  // one draw a statement (SceneRandom)
    const float y = rnd.uniform(lo.y, hi.y);
    const float z = rnd.uniform(lo.z, hi.z);
    l.position = {x, y, z};
    const float range = big ? rnd.uniform(0.2f, 0.5f) : rnd.uniform(0.0125f, 0.05f);
    l.range = range * diagonal;
    const float saturation = big ? rnd.uniform(0.1f, 0.4f) : rnd.uniform(0.4f, 0.9f);
    const float hue = rnd.uniform();
    // The atrium's k (0.02 big, 0.6 small per m^-2 at its 40 m diagonal), scaled to the bounds.
    const float k2 = (big ? 0.02f : 0.6f) * (40.0f / diagonal) * (40.0f / diagonal);
    l.color = k2 * l.range * l.range * hueColor(hue, saturation);
    l.castsShadow = bigCast && big;
    lights.push_back(l);
  }
  return lights;
}

Scene loadScene(const std::string& spec, const SceneOptions& options) {
  if (options.lightCount < -1)
    throw Error("light count must be >= 0 (or -1 for the light set's own), got " +
                std::to_string(options.lightCount));
  if (!(options.lightRange >= 0.0f) || !std::isfinite(options.lightRange))
    throw Error("light range must be finite and > 0 (or 0 to keep each light's own), got " +
                std::to_string(options.lightRange));

  Scene scene;
  const std::string prefix = "builtin:";
  if (spec.compare(0, prefix.size(), prefix) == 0) {
    scene =
        makeBuiltin(spec.substr(prefix.size()), options.lightSet, options.seed, options.lightCount);
    applyVariants(scene, options.variant, options.seed);
  } else if (endsWith(spec, ".gltf") || endsWith(spec, ".glb")) {
    const auto thesis = thesisLightSets();
    const bool placed = std::find(thesis.begin(), thesis.end(), options.lightSet) != thesis.end();
    if (!options.lightSet.empty() && options.lightSet != "file" && !placed)
      throw Error("light set '" + shortText(options.lightSet) + "' does not apply to glTF scene " +
                  spec + " (valid: file, its own KHR_lights_punctual lights; " + joined(thesis) +
                  ", placed from its bounds)");
    if (!options.variant.empty())
      throw Error("scene variants apply to built-in scenes only, not to " + spec);
    std::vector<std::string> warnings;
    scene = loadGltf(spec, &warnings);
    if (placed) {
      scene.lights =
          placeThesisLights(scene.bounds(), options.lightSet, options.seed, options.lightCount);
    } else if (options.lightCount >= 0) {
      if (size_t(options.lightCount) > scene.lights.size())
        throw Error("light count " + std::to_string(options.lightCount) + " is more than the " +
                    std::to_string(scene.lights.size()) + " light(s) in " + spec);
      scene.lights.resize(size_t(options.lightCount));
    }
    printSceneWarnings(spec, warnings);  // after the last error about the file
  } else {
    throw Error("unknown scene spec '" + shortText(spec) + "': use builtin:NAME (" +
                joined(builtinSceneNames()) + ") or a .gltf/.glb file");
  }
  if (options.lightRange > 0.0f)
    for (auto& l : scene.lights)
      if (l.hasRange()) l.range = options.lightRange;
  chooseShadowCasters(scene.lights, options.shadows);
  if (!options.normalMaps) {
    for (Material& m : scene.materials) m.normalTexture = -1;
    scene.tangents.clear();
  }
  applyBlendPolicy(scene, options.blend);
  return scene;
}

const EnumNames<BlendPolicy>& blendPolicyNames() {
  static const EnumNames<BlendPolicy> names(
      "blend policy",
      {{BlendPolicy::Refuse, "refuse",
        "a scene with alphaMode BLEND materials is refused (--blend blend composites them)"},
       {BlendPolicy::AsOpaque, "as-opaque", "BLEND materials drawn opaque"},
       {BlendPolicy::AsMask, "as-mask", "BLEND materials drawn as MASK with their alphaCutoff"},
       {BlendPolicy::Blend, "blend",
        "BLEND materials composited over the opaque scene, back to front, by the forward "
        "techniques and tiled's hybrid (--raster gl); the other G-buffer techniques refuse such "
        "a frame"}});
  return names;
}

std::string toString(BlendPolicy policy) { return blendPolicyNames().name(policy); }

void applyBlendPolicy(Scene& scene, BlendPolicy policy) {
  scene.blendComposited = policy == BlendPolicy::Blend;
  if (policy == BlendPolicy::Refuse || policy == BlendPolicy::Blend) return;
  for (Material& m : scene.materials)
    if (m.alphaMode == AlphaMode::Blend)
      m.alphaMode = policy == BlendPolicy::AsMask ? AlphaMode::Mask : AlphaMode::Opaque;
}

}  // namespace ts
