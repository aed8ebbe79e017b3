#include "scene/scene.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "util/error.h"
#include "util/short_text.h"

namespace ts {

namespace {

// A texture coordinate in texels (n of them), first brought into one period of the wrap mode, so
// that a far-off coordinate (u = 1e10) cannot overflow the integer texel index: REPEAT's period
// is 1, MIRRORED_REPEAT's 2; CLAMP_TO_EDGE clamps every index beyond [-1, 2] to the same texel.
float texelCoordinate(float s, int n, TextureWrap wrap) {
  switch (wrap) {
    case TextureWrap::ClampToEdge: return std::clamp(s, -1.0f, 2.0f) * float(n);
    case TextureWrap::MirroredRepeat: return (s - 2.0f * std::floor(0.5f * s)) * float(n);
    case TextureWrap::Repeat: break;
  }
  return (s - std::floor(s)) * float(n);
}

// Texel index i of an axis of n texels, wrapped as OpenGL does (its wrap(i)).
int wrapIndex(int i, int n, TextureWrap wrap) {
  switch (wrap) {
    case TextureWrap::ClampToEdge: return std::clamp(i, 0, n - 1);
    case TextureWrap::MirroredRepeat: {
      const int m = ((i % (2 * n)) + 2 * n) % (2 * n) - n;
      return (n - 1) - (m >= 0 ? m : -(1 + m));
    }
    case TextureWrap::Repeat: break;
  }
  return ((i % n) + n) % n;
}

}  // namespace

glm::vec4 Texture::sample(glm::vec2 uv) const {
  if (width <= 0 || height <= 0) return glm::vec4(1.0f);
  auto at = [&](int x, int y) { return texels[size_t(y) * size_t(width) + size_t(x)]; };
  const float u = texelCoordinate(uv.x, width, wrapS), v = texelCoordinate(uv.y, height, wrapT);
  if (nearest)
    return at(wrapIndex(int(std::floor(u)), width, wrapS),
              wrapIndex(int(std::floor(v)), height, wrapT));
  // Texel centres at half-integers.
  float fx = u - 0.5f, fy = v - 0.5f;
  float x0f = std::floor(fx), y0f = std::floor(fy);
  float tx = fx - x0f, ty = fy - y0f;
  int x0 = wrapIndex(int(x0f), width, wrapS), x1 = wrapIndex(int(x0f) + 1, width, wrapS);
  int y0 = wrapIndex(int(y0f), height, wrapT), y1 = wrapIndex(int(y0f) + 1, height, wrapT);
  glm::vec4 top = glm::mix(at(x0, y0), at(x1, y0), tx);
  glm::vec4 bottom = glm::mix(at(x0, y1), at(x1, y1), tx);
  return glm::mix(top, bottom, ty);
}

const EnumNames<ShadingModel>& shadingModelNames() {
  static const EnumNames<ShadingModel> names(
      "shading model", {{ShadingModel::BlinnPhong, "blinn-phong"},
                        {ShadingModel::MetallicRoughness, "metallic-roughness"}});
  return names;
}

std::string toString(ShadingModel model) { return shadingModelNames().name(model); }

ShadingModel parseShadingModel(const std::string& s) { return shadingModelNames().parse(s); }

std::string toString(AlphaMode mode) {
  switch (mode) {
    case AlphaMode::Opaque: return "OPAQUE";
    case AlphaMode::Mask: return "MASK";
    case AlphaMode::Blend: return "BLEND";
  }
  return "?";
}

std::string toString(SceneLightType type) {
  switch (type) {
    case SceneLightType::Point: return "point";
    case SceneLightType::Spot: return "spot";
    case SceneLightType::Directional: return "directional";
  }
  return "?";
}

std::string describeLights(const std::vector<SceneLight>& lights) {
  size_t count[3] = {0, 0, 0};
  for (const SceneLight& l : lights) ++count[int(l.type)];
  std::string s = std::to_string(lights.size()) + " lights";
  if (count[0] == lights.size()) return s;
  const char* names[3] = {"point", "spot", "directional"};
  std::string parts;
  for (int t = 0; t < 3; ++t)
    if (count[t]) parts += (parts.empty() ? "" : ", ") + std::to_string(count[t]) + " " + names[t];
  return s + ": " + parts;
}

SceneLight SceneLight::point(glm::dvec3 position, glm::vec3 color, float range) {
  SceneLight l;
  l.position = position;
  l.color = color;
  l.range = range;
  return l;
}

SceneLight SceneLight::spot(glm::dvec3 position, glm::vec3 direction, glm::vec3 color, float range,
                            float innerConeAngle, float outerConeAngle) {
  SceneLight l = point(position, color, range);
  l.type = SceneLightType::Spot;
  l.direction = direction;
  l.innerConeAngle = innerConeAngle;
  l.outerConeAngle = outerConeAngle;
  return l;
}

SceneLight SceneLight::directional(glm::vec3 direction, glm::vec3 color) {
  SceneLight l;
  l.type = SceneLightType::Directional;
  l.direction = direction;
  l.color = color;
  l.range = 0.0f;
  return l;
}

SceneCamera SceneCamera::lookAt(glm::dvec3 eye, glm::dvec3 target, glm::dvec3 up, float yfov,
                                float znear, float zfar) {
  SceneCamera c;
  c.viewFromWorld = glm::lookAt(eye, target, up);
  c.yfov = yfov;
  c.znear = znear;
  c.zfar = zfar;
  return c;
}

Bounds Scene::bounds() const {
  Bounds b;
  for (const auto& v : vertices) b.extend(v.position);
  return b;
}

const SceneCamera& Scene::camera(int frame) const {
  if (cameraPath.empty()) throw Error("scene '" + name + "' has no camera");
  if (frame < 0) throw Error("frame must be >= 0, got " + std::to_string(frame));
  return cameraPath[size_t(frame) % cameraPath.size()];
}

}  // namespace ts
