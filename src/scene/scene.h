#pragma once
// The scene model every stage shares: world-space triangles with materials, lights and a
// camera path. Loaders (glTF, built-in generators) produce it; the rasterizer consumes it.
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "util/enum_names.h"

namespace ts {

// How a texture coordinate outside [0, 1] maps into the texture: glTF's (and OpenGL's) wrap modes.
enum class TextureWrap { Repeat = 0, ClampToEdge = 1, MirroredRepeat = 2 };

// Linear-RGB texture, sampled with its sampler's wrap modes and magnification filter (glTF's
// defaults: REPEAT, bilinear), at one level (no mipmaps).
struct Texture {
  int width = 0;
  int height = 0;
  std::vector<glm::vec4> texels;  // row-major, row 0 = top (v = 0), linear RGBA
  bool srgb = true;               // colour (base colour, emissive: sRGB-encoded in files) or data
                                  // (metallic-roughness: stored as is)
  TextureWrap wrapS = TextureWrap::Repeat;  // along u
  TextureWrap wrapT = TextureWrap::Repeat;  // along v
  bool nearest = false;  // filter NEAREST (the texel under uv), else LINEAR (bilinear)
  glm::vec4 sample(glm::vec2 uv) const;
};

// The two shading models a material can be written for (kernels/shading.h):
//  BlinnPhong         the papers' model: Lambert diffuse kd + Blinn-Phong specular ks, shininess s
//  MetallicRoughness  glTF's: base colour, metallic, roughness; Lambert + GGX/Smith/Schlick
enum class ShadingModel { BlinnPhong = 0, MetallicRoughness = 1 };
const EnumNames<ShadingModel>& shadingModelNames();
std::string toString(ShadingModel model);              // "blinn-phong" | "metallic-roughness"
ShadingModel parseShadingModel(const std::string& s);  // throws ts::Error otherwise

// glTF's alphaMode: how a material's alpha (Material::opacity times its base colour texture's
// alpha, ts_material_alpha in shaders/material_planes.h) covers what lies behind it.
//  Opaque  alpha ignored
//  Mask    a fragment whose alpha is below alphaCutoff is not drawn (both rasterizers)
//  Blend   blended over what lies behind: the rasterizers refuse a scene that draws one unless
//          it is composited (Scene::blendComposited, --blend blend: the forward techniques) or
//          drawn opaque or masked (--blend as-opaque / as-mask; docs/features.md)
enum class AlphaMode { Opaque = 0, Mask = 1, Blend = 2 };
std::string toString(AlphaMode mode);  // glTF's names: "OPAQUE" | "MASK" | "BLEND"

// A material carries the terms of both models, so a scene can be shaded with either: the model it
// was authored in (`model`) holds the author's values, the other model's terms are filled in by
// the documented mapping of src/scene/material_mapping.h (scenes/README.md).
struct Material {
  std::string name;
  ShadingModel model = ShadingModel::BlinnPhong;  // the model the author wrote it for
  // Blinn-Phong
  glm::vec3 diffuse{0.8f};    // kd, multiplied by diffuseTexture when present
  int diffuseTexture = -1;    // index into Scene::textures, -1 = none
  glm::vec3 specular{0.04f};  // ks
  float shininess = 32.0f;    // s
  // glTF metallic-roughness
  glm::vec3 baseColor{0.8f};  // multiplied by baseColorTexture when present
  int baseColorTexture = -1;
  float metallic = 0.0f;   // multiplied by metallicRoughnessTexture's blue channel
  float roughness = 0.5f;  // multiplied by metallicRoughnessTexture's green channel
  int metallicRoughnessTexture = -1;
  // Both
  glm::vec3 emissive{0.0f};  // ke, multiplied by emissiveTexture when present
  int emissiveTexture = -1;
  // glTF normalTexture: a tangent-space normal map (linear data) perturbing the shading normal
  // through the vertices' tangent frames (Scene::tangents; shaders/normal_mapping.h), its x and y
  // scaled by normalScale.
  int normalTexture = -1;
  float normalScale = 1.0f;
  bool doubleSided = false;  // normals of back faces are flipped towards the viewer
  // Coverage (glTF alphaMode, alphaCutoff, baseColorFactor's alpha): the alpha of a point is
  // opacity times the alpha of the base colour texture of `model` (baseColorTexture, or
  // diffuseTexture for Blinn-Phong), ts_material_alpha in shaders/material_planes.h.
  AlphaMode alphaMode = AlphaMode::Opaque;
  float alphaCutoff = 0.5f;  // Mask: drawn where alpha >= alphaCutoff, in [0, 1]
  float opacity = 1.0f;      // in [0, 1]
};

struct Vertex {
  glm::vec3 position{0.0f};  // world space
  glm::vec3 normal{0.0f, 1.0f, 0.0f};
  glm::vec2 uv{0.0f};
};

// glTF KHR_lights_punctual's three light types.
enum class SceneLightType { Point = 0, Spot = 1, Directional = 2 };
std::string toString(SceneLightType type);  // "point" | "spot" | "directional"

// A light; colour includes intensity. Point and spot lights have a position and a finite range;
// a spot light shines along `direction` within `outerConeAngle` of it, fading between the inner
// and the outer cone (glTF's smooth angular falloff, docs/shading.md); a directional light (a sun)
// lights every surface from `direction`'s opposite, with no position and no range.
struct SceneLight {
  SceneLightType type = SceneLightType::Point;
  glm::dvec3 position{0.0};                // world space (point, spot); double until the view
                                           // transform, as the camera (docs/hard-cases.md)
  glm::vec3 direction{0.0f, 0.0f, -1.0f};  // world space, unit, where the light travels (spot,
                                           // directional): a node's -Z in glTF
  glm::vec3 color{1.0f};
  float range = 1.0f;                    // point, spot: > 0
  float innerConeAngle = 0.0f;           // spot, radians: 0 <= inner < outer <= pi/2 (a float
                                         // of pi/2 is 4.4e-8 above it: taken as pi/2)
  float outerConeAngle = 0.7853981634f;  // spot, radians (glTF's default pi/4)
  // Marked to cast a shadow (glTF extras "castsShadow", or --shadows). Its shadow maps are
  // drawn (raster/shadow_maps.h) and sampled by every deferred technique (kernels/shadows.h).
  bool castsShadow = false;

  static SceneLight point(glm::dvec3 position, glm::vec3 color, float range);
  static SceneLight spot(glm::dvec3 position, glm::vec3 direction, glm::vec3 color, float range,
                         float innerConeAngle, float outerConeAngle);
  static SceneLight directional(glm::vec3 direction, glm::vec3 color);
  bool hasRange() const { return type != SceneLightType::Directional; }
};

// "924 lights", or with several types "12 lights: 6 point, 5 spot, 1 directional".
std::string describeLights(const std::vector<SceneLight>& lights);

// A pinhole camera. Aspect ratio comes from the image being rendered, not from the camera.
// The view transform is double: far from the origin (1e5..1e6 units) a float matrix's rounding
// (its translation -R*eye, and R's entries times the eye's distance) moves view-space positions by
// more than the scene's own float quantisation; in double, a scene far from the origin renders as
// the same scene at the origin, up to that quantisation (docs/hard-cases.md).
struct SceneCamera {
  glm::dmat4 viewFromWorld{1.0};  // camera at the origin looking down -Z, +Y up
  float yfov = 1.0f;              // vertical field of view, radians
  float znear = 0.1f;
  float zfar = 1000.0f;

  static SceneCamera lookAt(glm::dvec3 eye, glm::dvec3 target, glm::dvec3 up, float yfov,
                            float znear, float zfar);
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
  // Per vertex, only for scenes with normal maps (else empty): the world-space unit tangent
  // (xyz, along +u) and the bitangent's sign w (bitangent = cross(normal, tangent) * w, glTF's
  // TANGENT); (0, 0, 0, 0) where a vertex has no tangent frame (its normal map is not applied).
  std::vector<glm::vec4> tangents;
  std::vector<Material> materials;
  std::vector<Texture> textures;
  std::vector<SceneLight> lights;       // every type; see Light
  std::vector<SceneCamera> cameraPath;  // frame k uses cameraPath[k % size]
  glm::vec3 ambient{0.02f};             // global ambient term a
  // --blend blend: alphaMode BLEND materials are drawn blended, back to front after the opaque
  // surfaces, by the forward techniques; the G-buffer and the shadow maps leave them out.
  bool blendComposited = false;

  size_t triangleCount() const { return indices.size() / 3; }
  Bounds bounds() const;
  const SceneCamera& camera(int frame) const;
};

}  // namespace ts
