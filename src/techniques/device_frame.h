#pragma once
// One frame's inputs on the device, uploaded once and shared by every technique of a run.
#include <tuple>
#include <vector>

#include <glm/glm.hpp>

#include "cl/cl_context.h"
#include "gbuffer/gbuffer_layout.h"
#include "scene/scene.h"

namespace ts {

// Lights transformed to view space, in the kernels' layout (kernels/shading.h, "Lights").
// Point and spot lights are the culled ones, indexed 0..size()-1; directional lights apply to
// every pixel and are kept apart.
struct ViewLights {
  std::vector<glm::vec4> positionRange;  // xyz view-space position, w = range
  std::vector<glm::vec4> color;          // rgb (intensity included), w = spot angle scale
                                         // 1/max(1e-3, cos inner - cos outer) (point: 1)
  std::vector<glm::vec4> spot;           // xyz unit spot axis (point: 0), w = cos of the outer
                                         // cone angle (point: -1, "every direction")
  std::vector<glm::vec4> directionalDir;    // xyz unit vector towards the light, w unused
  std::vector<glm::vec4> directionalColor;  // rgb, w unused
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

inline cl_float4 toCl(glm::vec4 v) { return {{v.x, v.y, v.z, v.w}}; }

// In double (Camera): a light far from the origin keeps its position relative to the camera.
ViewLights toViewSpace(const std::vector<Light>& lights, const glm::dmat4& viewFromWorld);

struct DeviceFrame {
  const EncodedGBuffer* gbuffer = nullptr;  // host copy of what was uploaded
  const ViewLights* lights = nullptr;       // host copy of what was uploaded
  CameraIntrinsics camera;
  glm::vec3 ambient{0.0f};

  cl::Buffer depth, normal, diffuse, specular, emissive;  // G-buffer planes (absent: 1 element)
  cl::Buffer lightPositionRange, lightColor, lightSpot;   // at least one element each
  cl::Buffer directionalDir, directionalColor;            // at least one element each

  int width() const { return camera.width; }
  int height() const { return camera.height; }
  int lightCount() const { return int(lights->size()); }  // point and spot lights
  int directionalCount() const { return int(lights->directionalCount()); }

  // Kernel argument groups for KernelArgs::add: the five G-buffer planes (kernels/gbuffer.h
  // order), TS_LIGHT_PARAMS (position+range, colour, spot) and TS_DIRECTIONAL_PARAMS (direction,
  // colour, count).
  auto gbufferArgs() const { return std::tie(depth, normal, diffuse, specular, emissive); }
  auto lightArgs() const { return std::tie(lightPositionRange, lightColor, lightSpot); }
  std::tuple<const cl::Buffer&, const cl::Buffer&, int> directionalArgs() const {
    return {directionalDir, directionalColor, directionalCount()};
  }

  // The caller keeps gbuffer and lights alive while the frame is used.
  static DeviceFrame upload(ClContext& cl, const EncodedGBuffer& gbuffer,
                            const CameraIntrinsics& camera, const ViewLights& lights,
                            glm::vec3 ambient);
};

}  // namespace ts
