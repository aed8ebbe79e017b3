#include "raster/per_light_shadows.h"

#include <algorithm>

#include "raster/scene_validation.h"
#include "shading/shading_cpu.h"
#include "util/error.h"

namespace ts {
namespace {

// A pass's faces side by side from the left: the strip is as wide as their sizes together and
// as tall as the largest (every face of one light has one size, so a light's strip is exactly
// its faces' texels).
ShadowAtlasLayout stripLayout(const ShadowAtlasLayout& atlas, const std::vector<size_t>& faces) {
  ShadowAtlasLayout strip;
  for (size_t f : faces) {
    ShadowFace face = atlas.faces[f];
    face.x = strip.width;
    face.y = 0;
    strip.width += face.size;
    strip.height = std::max(strip.height, face.size);
    strip.faces.push_back(face);
  }
  return strip;
}

}  // namespace

PerLightShadowMaps::PerLightShadowMaps(const Scene& scene, const ShadowAtlasLayout& atlas)
    : scene_(scene), passOfFace_(atlas.faces.size(), -1) {
  if (atlas.faces.empty()) return;
  validateForRaster(scene);
  batches_ = drawBatches(scene);
  std::vector<size_t> directional;
  for (size_t f = 0; f < atlas.faces.size(); ++f) {
    const uint32_t light = atlas.faces[f].light;
    if (scene.lights.at(light).type == SceneLightType::Directional) {
      directional.push_back(f);
      continue;
    }
    // A light's faces are consecutive in the layout (attachShadowMaps relies on it too).
    if (f == 0 || atlas.faces[f - 1].light != light) passes_.emplace_back();
    passes_.back().faces.push_back(f);
    passOfFace_[f] = int(passes_.size() - 1);
  }
  if (!directional.empty()) {
    directional_ = int(passes_.size());
    passes_.push_back({directional, {}});
    for (size_t f : directional) passOfFace_[f] = directional_;
  }
  for (ShadowPass& p : passes_) p.layout = stripLayout(atlas, p.faces);
}

const ShadowPass& PerLightShadowMaps::passOf(int firstFace) const {
  const int p = firstFace >= 0 && size_t(firstFace) < passOfFace_.size()
                    ? passOfFace_[size_t(firstFace)]
                    : -1;
  if (p < 0 || p == directional_ || passes_[size_t(p)].faces.front() != size_t(firstFace))
    throw Error("shadow face " + std::to_string(firstFace) +
                " starts no point or spot light's maps");
  return passes_[size_t(p)];
}

const ShadowPass* PerLightShadowMaps::directionalPass() const {
  return directional_ < 0 ? nullptr : &passes_[size_t(directional_)];
}

std::vector<glm::vec4> PerLightShadowMaps::passFaceTable(
    const std::vector<glm::vec4>& atlasTable) const {
  if (atlasTable.size() != passOfFace_.size() * TS_SHADOW_FACE_RECORDS)
    throw Error("shadow face table out of step with the per-light passes");
  std::vector<glm::vec4> table = atlasTable;
  for (const ShadowPass& p : passes_)
    for (size_t k = 0; k < p.faces.size(); ++k) {
      const ShadowFace& face = p.layout.faces[k];
      table[p.faces[k] * TS_SHADOW_FACE_RECORDS + 4] =
          glm::vec4(float(face.x), float(face.y), float(face.size), float(p.layout.width));
    }
  return table;
}

ShadowAtlas PerLightShadowMaps::draw(const ShadowPass& pass, int threads) const {
  return drawShadowAtlas(scene_, batches_, pass.layout, threads);
}

uint64_t PerLightShadowMaps::residentBytes() const {
  uint64_t bytes = 0;
  for (const ShadowPass& p : passes_) bytes = std::max(bytes, p.layout.bytes());
  return bytes;
}

}  // namespace ts
