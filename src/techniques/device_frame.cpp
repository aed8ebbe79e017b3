#include "techniques/device_frame.h"

#include <algorithm>
#include <cmath>

namespace ts {

namespace {

template <typename T>
cl::Buffer readOnlyBuffer(ClContext& cl, const std::vector<T>& data) {
  // OpenCL refuses zero-sized buffers; an empty light list or an absent G-buffer plane still gets
  // one (unused) element.
  size_t bytes = std::max<size_t>(data.size() * sizeof(T), sizeof(T));
  cl::Buffer buffer(cl.context(), CL_MEM_READ_ONLY, bytes);
  if (!data.empty())
    cl.queue().enqueueWriteBuffer(buffer, CL_TRUE, 0, data.size() * sizeof(T), data.data());
  return buffer;
}

}  // namespace

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
  f.lightSpot = readOnlyBuffer(cl, lights.spot);
  f.directionalDir = readOnlyBuffer(cl, lights.directionalDir);
  f.directionalColor = readOnlyBuffer(cl, lights.directionalColor);
  std::vector<cl_int> shadow(lights.size()), directionalShadow(lights.directionalCount());
  for (size_t i = 0; i < shadow.size(); ++i) shadow[i] = lights.shadowOf(i);
  for (size_t i = 0; i < directionalShadow.size(); ++i)
    directionalShadow[i] = lights.directionalShadowOf(i);
  f.lightShadow = readOnlyBuffer(cl, shadow);
  f.directionalShadow = readOnlyBuffer(cl, directionalShadow);
  f.shadowFaces = readOnlyBuffer(cl, lights.shadowFaces);
  f.shadowAtlas =
      readOnlyBuffer(cl, lights.shadowAtlas ? *lights.shadowAtlas : std::vector<float>{});
  return f;
}

}  // namespace ts
