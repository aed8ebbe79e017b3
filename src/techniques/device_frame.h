#pragma once
// One frame's inputs on the device, uploaded once and shared by every technique of a run.
#include <vector>

#include <glm/glm.hpp>

#include "cl/cl_context.h"
#include "raster/gbuffer_layout.h"
#include "scene/scene.h"

namespace ts {

// Lights transformed to view space, in the kernels' layout.
struct ViewLights {
  std::vector<glm::vec4> positionRange;  // xyz view-space position, w = range
  std::vector<glm::vec4> color;          // rgb (intensity included), w unused
  size_t size() const { return positionRange.size(); }
};

inline cl_float4 toCl(glm::vec4 v) { return {{v.x, v.y, v.z, v.w}}; }

ViewLights toViewSpace(const std::vector<PointLight>& lights, const glm::mat4& viewFromWorld);

struct DeviceFrame {
  const EncodedGBuffer* gbuffer = nullptr;  // host copy of what was uploaded
  const ViewLights* lights = nullptr;       // host copy of what was uploaded
  CameraIntrinsics camera;
  glm::vec3 ambient{0.0f};

  cl::Buffer depth, normal, diffuse, specular, emissive;  // G-buffer planes
  cl::Buffer lightPositionRange, lightColor;              // at least one element each

  int width() const { return camera.width; }
  int height() const { return camera.height; }
  int lightCount() const { return int(lights->size()); }

  // Sets the five G-buffer planes as kernel arguments first..first+4 (kernels/gbuffer.h order).
  void setGBufferArgs(cl::Kernel& kernel, cl_uint first) const;

  // The caller keeps gbuffer and lights alive while the frame is used.
  static DeviceFrame upload(ClContext& cl, const EncodedGBuffer& gbuffer,
                            const CameraIntrinsics& camera, const ViewLights& lights,
                            glm::vec3 ambient);
};

}  // namespace ts
