#include "scene/scene_features.h"

#include <sstream>
#include <vector>

#include "util/error.h"
#include "util/short_text.h"
#include "util/option_values.h"

namespace ts {
namespace {

bool nonZero(glm::vec3 v) { return v.x != 0.0f || v.y != 0.0f || v.z != 0.0f; }

// Which materials some triangle uses (an unused material needs nothing).
std::vector<bool> usedMaterials(const Scene& scene) {
  std::vector<bool> used(scene.materials.size(), false);
  if (scene.triangleMaterial.empty()) {
    if (!used.empty() && scene.triangleCount() > 0) used[0] = true;
  } else {
    for (uint32_t m : scene.triangleMaterial)
      if (m < used.size()) used[m] = true;
  }
  return used;
}

struct Flag {
  const char* name;
  bool SceneFeatures::*member;
};
const Flag kFlags[] = {{"specular", &SceneFeatures::specular},
                       {"emissive", &SceneFeatures::emissive},
                       {"textures", &SceneFeatures::textures},
                       {"point", &SceneFeatures::point},
                       {"spot", &SceneFeatures::spot},
                       {"directional", &SceneFeatures::directional},
                       {"normal_maps", &SceneFeatures::normalMaps},
                       {"shadows", &SceneFeatures::shadows}};

std::string flagNames() {
  std::string s;
  for (const Flag& f : kFlags) s += (s.empty() ? "" : ", ") + std::string(f.name);
  return s;
}

}  // namespace

SceneFeatures SceneFeatures::general(ShadingModel model) {
  SceneFeatures f;
  f.model = model;
  for (const Flag& flag : kFlags) f.*flag.member = true;
  f.shadows = false;  // without shadow maps a build with shadows has nothing to sample
  return f;
}

std::string SceneFeatures::describe() const {
  std::string s = toString(model);
  for (const Flag& f : kFlags)
    if (this->*f.member) s += std::string(" ") + f.name;
  return s;
}

std::string SceneFeatures::kernelDefines() const {
  std::ostringstream o;
  o << "-DTS_SHADING=" << int(model) << " -DTS_HAS_SPECULAR=" << int(specular)
    << " -DTS_HAS_EMISSIVE=" << int(emissive) << " -DTS_HAS_SPOT=" << int(spot)
    << " -DTS_HAS_DIRECTIONAL=" << int(directional);
  if (shadows) o << " -DTS_HAS_SHADOWS";  // only then: no cost, the same kernels without
  return o.str();
}

bool SceneFeatures::covers(const SceneFeatures& need) const {
  if (model != need.model) return false;
  for (const Flag& f : kFlags)
    if (need.*f.member && !(this->*f.member)) return false;
  return true;
}

bool SceneFeatures::operator==(const SceneFeatures& o) const {
  if (model != o.model) return false;
  for (const Flag& f : kFlags)
    if (this->*f.member != o.*f.member) return false;
  return true;
}

ShadingModel nativeShadingModel(const Scene& scene) {
  std::vector<bool> used = usedMaterials(scene);
  for (size_t i = 0; i < used.size(); ++i)
    if (used[i] && scene.materials[i].model == ShadingModel::MetallicRoughness)
      return ShadingModel::MetallicRoughness;
  return ShadingModel::BlinnPhong;
}

SceneFeatures analyzeScene(const Scene& scene, ShadingModel model) {
  SceneFeatures f;
  f.model = model;
  f.specular = f.emissive = f.textures = false;
  f.point = f.spot = f.directional = f.normalMaps = false;
  std::vector<bool> used = usedMaterials(scene);
  for (size_t i = 0; i < used.size(); ++i) {
    if (!used[i]) continue;
    const Material& m = scene.materials[i];
    if (model == ShadingModel::MetallicRoughness) {
      f.specular = true;  // GGX is part of every metallic-roughness material (F0 >= 0.04)
      f.textures |= m.baseColorTexture >= 0 || m.metallicRoughnessTexture >= 0;
    } else {
      f.specular |= nonZero(m.specular);
      f.textures |= m.diffuseTexture >= 0;
    }
    // A normal map needs the scene's tangents (the loaders give them with the map).
    const bool normalMap = m.normalTexture >= 0 && !scene.tangents.empty();
    f.normalMaps |= normalMap;
    f.textures |= normalMap;
    f.emissive |= nonZero(m.emissive);
    f.textures |= nonZero(m.emissive) && m.emissiveTexture >= 0;
  }
  for (const SceneLight& l : scene.lights) {
    f.point |= l.type == SceneLightType::Point;
    f.spot |= l.type == SceneLightType::Spot;
    f.directional |= l.type == SceneLightType::Directional;
    f.shadows |= l.castsShadow;
  }
  return f;
}

SceneFeatures chooseFeatures(const std::string& spec, const SceneFeatures& need) {
  if (spec.empty() || spec == "auto") return need;
  if (spec == "general") {
    SceneFeatures f = SceneFeatures::general(need.model);
    f.shadows = need.shadows;
    return f;
  }
  SceneFeatures f;
  f.model = need.model;
  for (const Flag& flag : kFlags) f.*flag.member = false;
  for (const std::string& item : splitList(spec)) {
    const Flag* found = nullptr;
    for (const Flag& flag : kFlags)
      if (item == flag.name) found = &flag;
    if (!found)
      throw Error("unknown feature '" + shortText(item) + "' in '" + shortText(spec) +
                  "' (known: auto, general, or a "
                  "comma list of " +
                  flagNames() + ")");
    f.*found->member = true;
  }
  std::string missing;
  for (const Flag& flag : kFlags)
    if (need.*flag.member && !(f.*flag.member))
      missing += (missing.empty() ? "" : ", ") + std::string(flag.name);
  if (!missing.empty())
    throw Error("features '" + shortText(spec) + "' leave out what the scene needs: " + missing +
                " (a pipeline without them would render it wrong; the scene needs: " +
                need.describe() + ")");
  return f;
}

}  // namespace ts
