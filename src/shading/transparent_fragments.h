#pragma once
// The transparent fragments of a frame (--blend blend), as the OpenGL capture pass records them
// (GlRasterizer::captureTransparent, shaders/tiled_forward.frag with TS_CAPTURE): every fragment
// of a transparent draw that passes the opaque depth test, with what the double reference shades
// and composites it from (reference/transparent_composite.h). Data below both.
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace ts {

struct TransparentFragment {
  int x = 0, y = 0;       // pixel, row 0 at the top
  int order = 0;          // the draw's place in the back-to-front order (0 = drawn first)
  int primitive = 0;      // gl_PrimitiveID within the draw: the blend order inside it
  int batch = -1;         // the draw's batch (raster/draw_batches.h): forward's list for it
  glm::vec3 position{0};  // view space, as the forward pass interpolates it
  float alpha = 1.0f;     // ts_material_alpha
  glm::vec3 normal{0};    // the shading normal (normal map and double-sided flip applied)
  glm::vec4 diffuse{0}, specular{0}, emissive{0};  // the material planes (material_planes.h)
};

}  // namespace ts
