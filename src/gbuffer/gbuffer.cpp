#include "gbuffer/gbuffer.h"

#include <cmath>
#include <string>

#include "gbuffer/plane_alloc.h"
#include "util/error.h"

namespace ts {

CameraIntrinsics CameraIntrinsics::from(const SceneCamera& camera, int width, int height) {
  if (width < 1 || height < 1)
    throw Error("image size must be at least 1x1, got " + std::to_string(width) + "x" +
                std::to_string(height));
  if (!(camera.yfov > 0.0f && camera.yfov < 3.14159f))
    throw Error("camera yfov must be in (0, pi) radians, got " + std::to_string(camera.yfov));
  if (!(camera.znear > 0.0f && camera.zfar > camera.znear && std::isfinite(camera.zfar)))
    throw Error("camera needs 0 < znear < zfar, got znear " + std::to_string(camera.znear) +
                ", zfar " + std::to_string(camera.zfar));
  CameraIntrinsics c;
  c.width = width;
  c.height = height;
  // Float on purpose: these exact values travel to the kernels (kernelCamera) and the rasterizer
  // projects with them too, so rasterized depth and reconstructed positions agree.
  c.tanHalfFovY = std::tan(0.5f * camera.yfov);
  c.tanHalfFovX = c.tanHalfFovY * float(width) / float(height);
  c.znear = camera.znear;
  c.zfar = camera.zfar;
  return c;
}

glm::mat4 CameraIntrinsics::projection() const {
  // glm::perspective(yfov, width/height, znear, zfar) (right-handed, clip z in [-w, w]) written
  // with the stored tangents: clip x = X / tanHalfFovX, clip y = Y / tanHalfFovY, clip w = -Z.
  glm::mat4 p(0.0f);
  p[0][0] = 1.0f / tanHalfFovX;
  p[1][1] = 1.0f / tanHalfFovY;
  p[2][2] = -(zfar + znear) / (zfar - znear);
  p[2][3] = -1.0f;
  p[3][2] = -(2.0f * zfar * znear) / (zfar - znear);
  return p;
}

void GBuffer::resize(int w, int h) {
  if (w < 0 || h < 0)
    throw Error("G-buffer size must not be negative, got " + std::to_string(w) + "x" +
                std::to_string(h));
  width = w;
  height = h;
  size_t n = pixelCount();
  plane_alloc::assignZeroed(depth, n);
  plane_alloc::assignZeroed(normal, n);
  plane_alloc::assignZeroed(diffuse, n);
  plane_alloc::assignZeroed(specular, n);
  plane_alloc::assignZeroed(emissive, n);
  triangleId.clear();
  fragmentCount.clear();
}

size_t GBuffer::geometryPixels() const {
  size_t n = 0;
  for (float d : depth) n += d > 0.0f ? 1 : 0;
  return n;
}

}  // namespace ts
