#include "raster/scene_validation.h"

#include <string>

#include "util/error.h"

namespace ts {

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
}

}  // namespace ts
