#pragma once
// A G-buffer shaded by OpenGL: a full-screen fragment pass (shaders/shade_gbuffer.frag) over the
// encoded fp32 planes, every light in shader storage buffers, each pixel shaded by
// kernels/shading.h compiled as GLSL (through shaders/opencl_as_glsl.h), the very file the OpenCL
// kernels and the double reference use. It is the `brute` technique in a fragment shader: the
// check that the GLSL build of the shading function agrees with the other two, and the forward
// techniques' shading in the same language.
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "gbuffer/gbuffer.h"
#include "gbuffer/gbuffer_layout.h"
#include "scene/scene_features.h"
#include "shading/view_lights.h"

namespace ts {

class GlGBufferShading {
 public:
  // Builds the program in the shared headless context (raster/egl_context.h). Throws ts::Error:
  // no OpenGL context, a shader that does not compile or link (its log), any OpenGL error.
  GlGBufferShading();
  ~GlGBufferShading();
  GlGBufferShading(const GlGBufferShading&) = delete;
  GlGBufferShading& operator=(const GlGBufferShading&) = delete;

  // The image (rgb, a = 0; row-major, row 0 at the top) of `gbuffer` (fp32 layout only: ts::Error
  // otherwise) lit by `lights` with the features' terms and `model` (TS_MODEL_*), as the brute
  // kernel shades it.
  std::vector<glm::vec4> shade(const EncodedGBuffer& gbuffer, const CameraIntrinsics& camera,
                               const ViewLights& lights, glm::vec3 ambient,
                               const SceneFeatures& features, int model);

  // The fragment shader's source as compiled (its includes inlined): tests check that it holds
  // kernels/shading.h from the kernel folder byte for byte.
  static std::string fragmentSource();

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace ts
