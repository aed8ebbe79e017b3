#include "raster/scene_validation.h"

#include <algorithm>
#include <string>
#include <vector>

#include "util/error.h"
#include "util/short_text.h"

namespace ts {
namespace {

// Per material, whether some triangle is drawn with it (without a per-triangle list: the first).
std::vector<bool> usedMaterialFlags(const Scene& s) {
  std::vector<bool> used(s.materials.size(), false);
  if (s.triangleMaterial.empty()) {
    if (!used.empty() && s.triangleCount() > 0) used[0] = true;
  } else {
    for (uint32_t m : s.triangleMaterial)
      if (m < used.size()) used[m] = true;
  }
  return used;
}

std::vector<Material> usedMaterials(const Scene& s) {
  const std::vector<bool> used = usedMaterialFlags(s);
  std::vector<Material> out;
  for (size_t i = 0; i < s.materials.size(); ++i)
    if (used[i]) out.push_back(s.materials[i]);
  return out;
}

}  // namespace

void validateForRaster(const Scene& s) {
  if (s.indices.size() % 3 != 0)
    throw Error("scene '" + s.name + "': index count " + std::to_string(s.indices.size()) +
                " is not a multiple of 3");
  for (uint32_t i : s.indices)
    if (i >= s.vertices.size())
      throw Error("scene '" + s.name + "': vertex index " + std::to_string(i) + " out of range (" +
                  std::to_string(s.vertices.size()) + " vertices)");
  if (!s.triangleMaterial.empty() && s.triangleMaterial.size() != s.triangleCount())
    throw Error("scene '" + s.name + "': " + std::to_string(s.triangleMaterial.size()) +
                " triangle materials for " + std::to_string(s.triangleCount()) + " triangles");
  for (uint32_t m : s.triangleMaterial)
    if (m >= s.materials.size())
      throw Error("scene '" + s.name + "': material index " + std::to_string(m) +
                  " out of range (" + std::to_string(s.materials.size()) + " materials)");
  if (!s.tangents.empty() && s.tangents.size() != s.vertices.size())
    throw Error("scene '" + s.name + "': " + std::to_string(s.tangents.size()) + " tangents for " +
                std::to_string(s.vertices.size()) + " vertices");
  for (const Material& m : s.materials)
    for (int t : {m.diffuseTexture, m.baseColorTexture, m.metallicRoughnessTexture,
                  m.emissiveTexture, m.normalTexture})
      if (t >= int(s.textures.size()))
        throw Error("scene '" + s.name + "': material '" + m.name + "' uses texture " +
                    std::to_string(t) + " of " + std::to_string(s.textures.size()));
  if (!s.blendComposited) refuseBlendedMaterials(s);
}

bool drawsBlendedMaterials(const Scene& s) {
  for (const Material& m : usedMaterials(s))
    if (m.alphaMode == AlphaMode::Blend) return true;
  return false;
}

void refuseBlendedMaterials(const Scene& s) {
  const std::vector<bool> used = usedMaterialFlags(s);
  std::vector<std::string> names;
  for (size_t i = 0; i < s.materials.size(); ++i)
    if (used[i] && s.materials[i].alphaMode == AlphaMode::Blend)
      names.push_back(s.materials[i].name.empty() ? "#" + std::to_string(i)
                                                  : "'" + shortText(s.materials[i].name) + "'");
  if (names.empty()) return;
  std::string list;
  const size_t shown = std::min<size_t>(names.size(), 3);
  for (size_t i = 0; i < shown; ++i) list += (i ? ", " : "") + names[i];
  if (names.size() > shown) list += " and " + std::to_string(names.size() - shown) + " more";
  throw Error("scene '" + s.name + "': " + (names.size() == 1 ? "material " : "materials ") + list +
              (names.size() == 1 ? " is" : " are") +
              " alphaMode BLEND: --blend blend composites it (forward techniques, --raster gl), "
              "--blend as-opaque draws it opaque, --blend as-mask as MASK");
}

}  // namespace ts
