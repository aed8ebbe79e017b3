#include "techniques/device_frame.h"

namespace ts {

ViewLights toViewSpace(const std::vector<PointLight>& lights, const glm::mat4& viewFromWorld) {
  ViewLights out;
  out.positionRange.reserve(lights.size());
  out.color.reserve(lights.size());
  for (const auto& l : lights) {
    glm::vec3 p = glm::vec3(viewFromWorld * glm::vec4(l.position, 1.0f));
    out.positionRange.emplace_back(p, l.range);
    out.color.emplace_back(l.color, 0.0f);
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
