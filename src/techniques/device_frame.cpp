#include "techniques/device_frame.h"

#include <algorithm>
#include <cmath>

namespace ts {

ViewLights toViewSpace(const std::vector<Light>& lights, const glm::dmat4& viewFromWorld) {
  ViewLights out;
  const glm::mat3 rotation{glm::dmat3(viewFromWorld)};
  for (const auto& l : lights) {
    glm::vec3 dir = l.type == LightType::Point ? glm::vec3(0.0f)
                                                : glm::normalize(rotation * l.direction);
    if (l.type == LightType::Directional) {
      out.directionalDir.emplace_back(-dir, 0.0f);
      out.directionalColor.emplace_back(l.color, 0.0f);
      continue;
    }
    glm::vec3 p = glm::vec3(viewFromWorld * glm::dvec4(glm::dvec3(l.position), 1.0));
    out.positionRange.emplace_back(p, l.range);
    if (l.type == LightType::Spot) {
      float cosInner = std::cos(l.innerConeAngle), cosOuter = std::cos(l.outerConeAngle);
      out.color.emplace_back(l.color, 1.0f / std::max(1e-3f, cosInner - cosOuter));
      out.spot.emplace_back(dir, cosOuter);
    } else {
      out.color.emplace_back(l.color, 1.0f);
      out.spot.emplace_back(glm::vec3(0.0f), -1.0f);
    }
  }
  return out;
}

namespace {

template <typename T>
cl::Buffer readOnlyBuffer(ClContext& cl, const std::vector<T>& data) {
  // OpenCL refuses zero-sized buffers; an empty light list still gets one (unused) element.
  size_t bytes = std::max<size_t>(data.size() * sizeof(T), sizeof(T));
  cl::Buffer buffer(cl.context(), CL_MEM_READ_ONLY, bytes);
  if (!data.empty())
    cl.queue().enqueueWriteBuffer(buffer, CL_TRUE, 0, data.size() * sizeof(T), data.data());
  return buffer;
}

}  // namespace

void DeviceFrame::setGBufferArgs(cl::Kernel& kernel, cl_uint first) const {
  kernel.setArg(first + 0, depth);
  kernel.setArg(first + 1, normal);
  kernel.setArg(first + 2, diffuse);
  kernel.setArg(first + 3, specular);
  kernel.setArg(first + 4, emissive);
}

DeviceFrame DeviceFrame::upload(ClContext& cl, const EncodedGBuffer& gbuffer,
                                const CameraIntrinsics& camera, const ViewLights& lights,
                                glm::vec3 ambient) {
  DeviceFrame f;
  f.gbuffer = &gbuffer;
  f.lights = &lights;
  f.camera = camera;
  f.ambient = ambient;
  f.depth = readOnlyBuffer(cl, gbuffer.depth);
  f.normal = readOnlyBuffer(cl, gbuffer.normal);
  f.diffuse = readOnlyBuffer(cl, gbuffer.diffuse);
  f.specular = readOnlyBuffer(cl, gbuffer.specular);
  f.emissive = readOnlyBuffer(cl, gbuffer.emissive);
  f.lightPositionRange = readOnlyBuffer(cl, lights.positionRange);
  f.lightColor = readOnlyBuffer(cl, lights.color);
  return f;
}

}  // namespace ts
