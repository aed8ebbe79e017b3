#pragma once
// The scene model every stage shares: world-space triangles with materials, point lights and a
// camera path. Loaders (glTF, built-in generators) produce it; the rasterizer consumes it.
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace ts {

// Linear-RGB texture, sampled bilinearly with wrap-around (glTF's default REPEAT sampler).
struct Texture {
  int width = 0;
  int height = 0;
  std::vector<glm::vec4> texels;  // row-major, row 0 = top (v = 0), linear RGBA
  glm::vec4 sample(glm::vec2 uv) const;
};

// The paper's material terms: Blinn-Phong diffuse/specular/shininess plus emission.
struct Material {
  std::string name;
  glm::vec3 diffuse{0.8f};       // multiplied by diffuseTexture when present
  int diffuseTexture = -1;       // index into Scene::textures, -1 = none
  glm::vec3 specular{0.04f};
  float shininess = 32.0f;
  glm::vec3 emissive{0.0f};
  bool doubleSided = false;      // normals of back faces are flipped towards the viewer
};

struct Vertex {
  glm::vec3 position{0.0f};  // world space
  glm::vec3 normal{0.0f, 1.0f, 0.0f};
  glm::vec2 uv{0.0f};
};

// Point light with a finite range (glTF KHR_lights_punctual "point"); colour includes intensity.
struct PointLight {
  glm::vec3 position{0.0f};  // world space
  glm::vec3 color{1.0f};
  float range = 1.0f;
};

// A pinhole camera. Aspect ratio comes from the image being rendered, not from the camera.
struct Camera {
  glm::mat4 viewFromWorld{1.0f};  // camera at the origin looking down -Z, +Y up
  float yfov = 1.0f;              // vertical field of view, radians
  float znear = 0.1f;
  float zfar = 1000.0f;

  static Camera lookAt(glm::vec3 eye, glm::vec3 target, glm::vec3 up, float yfov, float znear,
                       float zfar);
};

struct Bounds {
  glm::vec3 min{1e30f};
  glm::vec3 max{-1e30f};
  void extend(glm::vec3 p) {
    min = glm::min(min, p);
    max = glm::max(max, p);
  }
  glm::vec3 center() const { return 0.5f * (min + max); }
  glm::vec3 extent() const { return max - min; }
};

struct Scene {
  std::string name;
  std::vector<Vertex> vertices;
  std::vector<uint32_t> indices;           // three per triangle
  std::vector<uint32_t> triangleMaterial;  // one per triangle, index into materials
  std::vector<Material> materials;
  std::vector<Texture> textures;
  std::vector<PointLight> lights;
  std::vector<Camera> cameraPath;          // frame k uses cameraPath[k % size]
  glm::vec3 ambient{0.02f};                // global ambient term a

  size_t triangleCount() const { return indices.size() / 3; }
  Bounds bounds() const;
  const Camera& camera(int frame) const;
};

}  // namespace ts
