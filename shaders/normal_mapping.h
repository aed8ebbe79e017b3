/*
 * glTF normal mapping: ONE definition for both rasterizers, compiled as C++ by the software
 * rasterizer (src/raster/rasterizer.cpp, resolve()) and as GLSL by the OpenGL one
 * (shaders/gbuffer.frag, shaders/tiled_forward.frag), in the common subset (glm in C++), so the
 * two cannot drift.
 *
 * n: the unit shading normal before any back-face flip of a double-sided material (the caller
 * negates the result there, as glTF's sample viewer negates the whole frame); tangent: the
 * interpolated vertex tangent, xyz along +u, w the bitangent's sign (Scene::tangents); texel: the
 * normal map's linear RGB at the pixel; scale: the material's normalTexture.scale.
 * The tangent-space normal (2 rgb - 1) * (scale, scale, 1) is taken into view space through the
 * frame T (the tangent made orthogonal to n), B = cross(n, T) w, n and normalised. Where there is
 * no frame (a vertex without a tangent, or one parallel to n) or the result vanishes, n stays. A
 * texel that tilts nothing (x = y = 0 after scaling: (0.5, 0.5, z), or scale 0) returns n itself,
 * bit for bit, rather than n renormalised.
 */
#ifndef TS_NORMAL_MAPPING_H
#define TS_NORMAL_MAPPING_H

#ifdef __cplusplus
#include <cmath>

#include <glm/glm.hpp>
namespace ts {
namespace normal_mapping_glsl {
using glm::cross;
using glm::dot;
using glm::vec3;
using glm::vec4;
using std::sqrt;
#endif

vec3 ts_normal_mapped(vec3 n, vec4 tangent, vec3 texel, float scale) {
  vec3 tn = (2.0f * texel - vec3(1.0f)) * vec3(scale, scale, 1.0f);
  if (tn.x == 0.0f && tn.y == 0.0f) return n;
  vec3 t = vec3(tangent) - n * dot(n, vec3(tangent));
  float t2 = dot(t, t);
  if (!(t2 > 1e-20f)) return n;
  t = t / sqrt(t2);
  vec3 b = cross(n, t) * (tangent.w < 0.0f ? -1.0f : 1.0f);
  vec3 m = t * tn.x + b * tn.y + n * tn.z;
  float m2 = dot(m, m);
  return m2 > 1e-24f ? m / sqrt(m2) : n;
}

#ifdef __cplusplus
}  // namespace normal_mapping_glsl
using normal_mapping_glsl::ts_normal_mapped;
}  // namespace ts
#endif

#endif
