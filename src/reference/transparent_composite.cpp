#include "reference/transparent_composite.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <tuple>

#include "shading/shading_cpu.h"
#include "util/error.h"

namespace ts {
namespace {

bool nonZero(const glm::dvec3& v) { return v.x != 0.0 || v.y != 0.0 || v.z != 0.0; }

// Every light, punctual then directional, as shadeReference sums a pixel; counts the non-zero
// contributions.
glm::dvec3 shadeFragment(const SurfaceD& s, const ViewLights& lights, glm::dvec3 ambient, int model,
                         int shading, uint64_t& contributing) {
  const shading_d::ts_shading_point p = transparentShadingPoint(s, shading);
  glm::dvec3 sum(0.0);
  for (size_t i = 0; i < lights.size(); ++i) {
    const glm::dvec3 c = transparentPunctualLight(p, s, lights, i, model, shading);
    if (nonZero(c)) ++contributing;
    sum += c;
  }
  for (size_t i = 0; i < lights.directionalCount(); ++i) {
    const glm::dvec3 c = shading_d::ts_directional_light(
        &p, s.kd, s.ks, glm::dvec3(glm::vec3(lights.directionalDir[i])),
        glm::dvec3(glm::vec3(lights.directionalColor[i])), shading, 1);
    if (nonZero(c)) ++contributing;
    sum += c;
  }
  return sum + shading_d::ts_surface_base(s.ke, s.cDiff, ambient);
}

}  // namespace

shading_d::ts_shading_point transparentShadingPoint(const SurfaceD& s, int shading) {
  shading_d::ts_shading_point p = shading_d::ts_make_shading_point(s.P, s.N, s.V, s.gloss, shading);
  p.view_term = s.viewTerm;
  return p;
}

glm::dvec3 transparentPunctualLight(const shading_d::ts_shading_point& p, const SurfaceD& s,
                                    const ViewLights& lights, size_t i, int model, int shading) {
  return shading_d::ts_punctual_light(&p, s.kd, s.ks, glm::dvec4(lights.positionRange[i]),
                                      glm::dvec4(lights.color[i]), glm::dvec4(lights.spot[i]),
                                      model, shading, 1, 1);
}

SurfaceD transparentSurface(const TransparentFragment& f, const EncodedGBuffer& gbuffer) {
  SurfaceD s;
  s.P = glm::dvec3(f.position);
  s.V = -s.P / std::sqrt(glm::dot(s.P, s.P));  // beyond the near plane: never zero
  const glm::vec4 emissive = gbuffer.hasEmissive ? f.emissive : glm::vec4(0.0f);
  surfaceTerms(glm::vec4(f.normal, 0.0f), f.diffuse, f.specular, emissive, gbuffer.model,
               gbuffer.hasSpecularPlane(), s);
  return s;
}

void compositeTransparent(ReferenceImage& reference, const std::vector<TransparentFragment>& frags,
                          const ViewLights& lights, glm::vec3 ambient, int model,
                          const EncodedGBuffer& gbuffer) {
  if (frags.empty()) return;
  if (lights.hasShadows())
    throw Error("the transparent surfaces' reference shades no shadows, and a light casts one");
  for (const TransparentFragment& f : frags)
    if (f.x < 0 || f.y < 0 || f.x >= reference.width || f.y >= reference.height)
      throw Error("a captured transparent fragment at (" + std::to_string(f.x) + ", " +
                  std::to_string(f.y) + ") lies outside the " + std::to_string(reference.width) +
                  "x" + std::to_string(reference.height) + " image");
  // Per pixel in blend order: the draw's place, then the primitive within the draw (OpenGL
  // blends a draw's fragments in primitive order).
  std::vector<size_t> order(frags.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    const TransparentFragment &fa = frags[a], &fb = frags[b];
    return std::tie(fa.y, fa.x, fa.order, fa.primitive) <
           std::tie(fb.y, fb.x, fb.order, fb.primitive);
  });
  const glm::dvec3 a(ambient);
  for (size_t i : order) {
    const TransparentFragment& f = frags[i];
    const SurfaceD s = transparentSurface(f, gbuffer);
    const glm::dvec3 shade =
        shadeFragment(s, lights, a, model, int(gbuffer.model), reference.contributing);
    glm::dvec3& c = reference.rgb[size_t(f.y) * size_t(reference.width) + size_t(f.x)];
    const double alpha = double(f.alpha);
    c = alpha * shade + (1.0 - alpha) * c;
  }
  reference.peak = 0.0;
  for (const glm::dvec3& c : reference.rgb)
    reference.peak = std::max({reference.peak, c.x, c.y, c.z});
}

}  // namespace ts
