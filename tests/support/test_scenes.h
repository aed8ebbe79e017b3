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

// The shadow suites' scene: the floor (addFloor, half 10) and a closed box floating over it at
// y in [1, 2], seen from above and in front, without lights (each suite adds its own).
inline Scene floorAndBox(glm::vec3 ambient = Scene{}.ambient) {
  Scene s;
  s.name = "floor-and-box";
  s.ambient = ambient;
  MeshBuilder b(s);
  const uint32_t m = b.addMaterial(Material{});
  addFloor(b, 10.0f, m);
  b.box({-1.0f, 1.0f, -1.0f}, {1.0f, 2.0f, 1.0f}, m, true);
  s.cameraPath.push_back(
      SceneCamera::lookAt({0.0, 6.0, 9.0}, {0.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, 1.2f, 0.1f, 100.0f));
  return s;
}

// `l` made to cast a shadow (or not).
inline SceneLight casting(SceneLight l, bool casts = true) {
  l.castsShadow = casts;
  return l;
}

}  // namespace ts::test
