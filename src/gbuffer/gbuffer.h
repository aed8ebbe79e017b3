#pragma once
// The G-buffer as the rasterizers produce it (full float precision, view space) and the camera
// intrinsics that tie pixels to view rays (the kernels' camera). The rasterizers' entry points
// are in src/raster/ (rasterizer.h, gl_rasterizer.h); the stored layouts in gbuffer_layout.h.
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "scene/scene.h"

namespace ts {

// What the kernels need to turn (pixel, depth) into a view-space position; see
// ts_view_position in kernels/shading.h.
struct CameraIntrinsics {
  int width = 0;
  int height = 0;
  float tanHalfFovX = 1.0f;
  float tanHalfFovY = 1.0f;
  float znear = 0.1f;
  float zfar = 1000.0f;

  static CameraIntrinsics from(const SceneCamera& camera, int width, int height);
  // The camera uniform of the kernels: (tan x, tan y, width, height).
  glm::vec4 kernelCamera() const { return {tanHalfFovX, tanHalfFovY, float(width), float(height)}; }
  // OpenGL-style projection consistent with the above (for the rasterizer).
  glm::mat4 projection() const;
};

// The material planes hold the terms of the shading model the frame is rasterized for:
//   model       diffuse                      specular
//   BlinnPhong  kd rgb, w unused (1)         ks rgb, shininess s in w
//   MetallicR.  base colour rgb, metallic w  roughness in x (y, z, w unused: 0)
struct GBuffer {
  int width = 0;
  int height = 0;
  ShadingModel model = ShadingModel::BlinnPhong;
  std::vector<float> depth;         // linear view depth (-z_view); 0 = background
  std::vector<glm::vec4> normal;    // view-space unit normal, w = 0
  std::vector<glm::vec4> diffuse;   // see above
  std::vector<glm::vec4> specular;  // see above
  std::vector<glm::vec4> emissive;  // ke rgb, a unused (0)
  // Instrumentation, filled only when RasterOptions (src/raster/rasterizer.h) asks for it (empty
  // otherwise):
  std::vector<int32_t> triangleId;      // visible triangle (index into Scene), -1 = background
  std::vector<uint32_t> fragmentCount;  // fragments passing the coverage/fill-rule test, counted
                                        // before the depth and far-plane tests (overdraw)

  void resize(int w, int h);  // zeroes the five planes, clears the instrumentation planes
  size_t pixelCount() const { return size_t(width) * size_t(height); }
  size_t geometryPixels() const;
};

}  // namespace ts
