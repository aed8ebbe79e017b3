#pragma once
// Pieces of the hand-made test scenes that several suites build (shadow maps, shading, exact
// visibility, G-buffers), so each is written once.
#include <cstdint>

#include <glm/glm.hpp>

#include "scene/mesh_builder.h"
#include "scene/scene.h"

namespace ts::test {

// The floor quad at y = 0 spanning [-half, half] in x and z (normal +y), moved by `offset`.
inline void addFloor(MeshBuilder& b, float half, uint32_t material,
                     glm::vec3 offset = glm::vec3(0.0f)) {
  b.quad(offset + glm::vec3(-half, 0.0f, half), offset + glm::vec3(half, 0.0f, half),
         offset + glm::vec3(half, 0.0f, -half), offset + glm::vec3(-half, 0.0f, -half), material);
}

// The alpha-tested texture of the MASK tests: 2x1 texels, NEAREST, clamped, alpha 0.2 on the
// left texel (u < 0.5: cut out at the default cutoff 0.5) and 1 on the right, so a quad whose u
// runs along an axis is covered over exactly one half.
inline Texture halfCutOutTexture() {
  Texture t;
  t.width = 2;
  t.height = 1;
  t.texels = {glm::vec4(1.0f, 1.0f, 1.0f, 0.2f), glm::vec4(1.0f)};
  t.nearest = true;
  t.wrapS = t.wrapT = TextureWrap::ClampToEdge;
  return t;
}

}  // namespace ts::test
