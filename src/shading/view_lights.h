#pragma once
// The lights of one frame as the kernels read them: shading data below the techniques and the
// reference, which both take it (a technique's DeviceFrame uploads it, the reference shades it).
#include <cstddef>
#include <memory>
#include <vector>

#include <glm/glm.hpp>

namespace ts {

// Lights transformed to view space, in the kernels' layout (kernels/shading.h, "Lights").
// Point and spot lights are the culled ones, indexed 0..size()-1; directional lights apply to
// every pixel and are kept apart.
struct ViewLights {
  std::vector<glm::vec4> positionRange;     // xyz view-space position, w = range
  std::vector<glm::vec4> color;             // rgb (intensity included), w = spot angle scale
                                            // 1/max(1e-3, cos inner - cos outer) (point: 1)
  std::vector<glm::vec4> spot;              // xyz unit spot axis (point: 0), w = cos of the outer
                                            // cone angle (point: -1, "every direction")
  std::vector<glm::vec4> directionalDir;    // xyz unit vector towards the light, w unused
  std::vector<glm::vec4> directionalColor;  // rgb, w unused
  // Shadows (kernels/shadows.h; docs/shadows.md): per light its first face in shadowFaces, -1
  // for a light that casts none (every light until a shadow atlas is attached: attachShadowMaps
  // in raster/shadow_maps.h).
  std::vector<int> shadow;             // point and spot lights, in their order
  std::vector<int> directionalShadow;  // directional lights, in their order
  std::vector<glm::vec4> shadowFaces;  // kShadowFaceRecords float4s per face (shadows.h)
  std::shared_ptr<const std::vector<float>> shadowAtlas;  // its texels; null without shadows
  int shadowAtlasWidth = 0;
  bool hasShadows() const { return !shadowFaces.empty(); }
  // The first faces, -1 past the end of `shadow` (lights appended without the add* functions).
  int shadowOf(size_t i) const { return i < shadow.size() ? shadow[i] : -1; }
  int directionalShadowOf(size_t i) const {
    return i < directionalShadow.size() ? directionalShadow[i] : -1;
  }
  size_t size() const { return positionRange.size(); }
  size_t directionalCount() const { return directionalDir.size(); }
  // The kernels' own test (culling.h: a point light's cos_outer is -1, a spot light's >= 0).
  bool isSpot(size_t i) const { return spot[i].w > -1.0f; }

  // Appends a light in view space, in the layout above (the only way the entries are written, so
  // the three arrays stay in step and a point light's spot entry makes its cone term exactly 1).
  void addPoint(glm::vec3 position, float range, glm::vec3 color);
  void addSpot(glm::vec3 position, float range, glm::vec3 color, glm::vec3 axis,
               float innerConeAngle, float outerConeAngle);
  void addDirectional(glm::vec3 towardsLight, glm::vec3 color);
};

}  // namespace ts
