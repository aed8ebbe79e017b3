#pragma once
// Small helpers for the procedural built-in scenes: append boxes, cylinders, spheres, quads and
// arches (world space, flat or smooth normals, CCW front faces seen from outside) to a Scene, and a
// deterministic random source that gives identical floats with any standard library.
#include <cstdint>
#include <random>

#include <glm/glm.hpp>

#include "scene/scene.h"

namespace ts {

// std::mt19937 is fully specified by the standard; the float mapping is ours (not
// std::uniform_real_distribution, whose algorithm differs between libraries). Draw each number
// into a named local, one statement each: C++ leaves the order of a call's arguments (and of the
// operands of +) unspecified, so two draws in one expression give another scene on another
// compiler. Where the generators once had such expressions, the locals are drawn in the order
// g++ on x86-64 evaluated them (arguments right to left), which keeps the scenes as they were;
// BuiltinScenePins (tests/scene/scene_pins_test.cpp) holds values of each scene.
class SceneRandom {
 public:
  explicit SceneRandom(uint32_t seed) : rng_(seed) {}
  float uniform() { return float(rng_() >> 8) * (1.0f / 16777216.0f); }  // [0, 1)
  float uniform(float lo, float hi) { return lo + (hi - lo) * uniform(); }
  int index(int n) { return int(uniform() * float(n)) % n; }  // [0, n)
  bool chance(float p) { return uniform() < p; }

 private:
  std::mt19937 rng_;
};

class MeshBuilder {
 public:
  explicit MeshBuilder(Scene& scene) : s_(scene) {}

  uint32_t addMaterial(const Material& m);

  // Planar quad p0,p1,p2,p3 (counter-clockwise seen from the front); uv = corner * uvScale.
  void quad(glm::vec3 p0, glm::vec3 p1, glm::vec3 p2, glm::vec3 p3, uint32_t material,
            glm::vec2 uvScale = glm::vec2(1.0f));
  // Axis-aligned box [lo, hi]; `bottom` = false leaves out the face at lo.y (boxes standing on
  // the ground). UVs in world units so textures would tile per metre.
  void box(glm::vec3 lo, glm::vec3 hi, uint32_t material, bool bottom = true);
  // The unit cube [-0.5, 0.5]^3 transformed by `xf` (rotated/scaled boxes).
  void box(const glm::mat4& xf, uint32_t material);
  // Cylinder along +Y from `base`, smooth sides, flat caps.
  void cylinder(glm::vec3 base, float radius, float height, int segments, uint32_t material,
                bool caps = true);
  // Cone frustum along +Y (radius r0 at the base, r1 at the top).
  void frustum(glm::vec3 base, float r0, float r1, float height, int segments, uint32_t material,
               bool caps = true);
  // UV sphere / ellipsoid with smooth normals.
  void sphere(glm::vec3 center, glm::vec3 radii, int slices, int stacks, uint32_t material);
  void sphere(glm::vec3 center, float radius, int slices, int stacks, uint32_t material) {
    sphere(center, glm::vec3(radius), slices, stacks, material);
  }
  // Semicircular arch in a vertical plane: voussoirs (boxes) from the springing points
  // center ± radius·along, `thickness` radially (outwards), `depth` across the plane.
  void arch(glm::vec3 center, glm::vec3 along, float radius, float thickness, float depth,
            int segments, uint32_t material);
  // A hanging cloth: a vertical strip from `top` down by `height`, `width` along `along`, waving
  // with `amplitude` across the plane (smooth normals; use a double-sided material).
  void curtain(glm::vec3 topCenter, glm::vec3 along, float width, float height, float amplitude,
               float waves, int columns, uint32_t material);

 private:
  uint32_t vertex(glm::vec3 p, glm::vec3 n, glm::vec2 uv);
  void triangle(uint32_t a, uint32_t b, uint32_t c, uint32_t material);
  Scene& s_;
};

}  // namespace ts
