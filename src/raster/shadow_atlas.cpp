#include "raster/shadow_atlas.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include <glm/gtc/matrix_transform.hpp>

#include "util/error.h"
#include "util/float_limit.h"
#include "util/option_values.h"
#include "util/pi.h"

namespace ts {
namespace {

constexpr double kMaxSpotFov = 170.0 * kPiDouble / 180.0;  // a wider perspective map degenerates
constexpr double kNearFraction = 1e-3;                     // of the range: the maps' near plane
constexpr int kDirectionalFactor = 4;  // directional maps: the thesis's 2048 at the default 512
constexpr size_t kNoteLights = 8;      // lights named in the lost-resolution note

bool powerOfTwo(long long v) { return v > 0 && (v & (v - 1)) == 0; }

uint64_t nextPowerOfTwo(uint64_t v) {
  uint64_t p = 1;
  while (p < v) p <<= 1;
  return p;
}

// The atlas holds a power of two texels (W x W or W x W/2) at least the faces' area.
uint64_t atlasTexels(uint64_t area) { return nextPowerOfTwo(std::max<uint64_t>(area, 1)); }

std::string megabytes(uint64_t bytes) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", double(bytes) / double(1 << 20));
  return buf;
}

// Every second bit from bit `first`: one coordinate of a Morton (Z-order) index.
uint32_t deinterleave(uint64_t m, int first) {
  uint32_t v = 0;
  for (int b = 0; 2 * b + first < 64; ++b) v |= uint32_t((m >> (2 * b + first)) & 1u) << b;
  return v;
}

glm::dvec3 anyUp(const glm::dvec3& forward) {
  return std::abs(forward.y) < 0.999 ? glm::dvec3(0.0, 1.0, 0.0) : glm::dvec3(0.0, 0.0, 1.0);
}

ShadowFace perspectiveFace(uint32_t light, int face, const glm::dvec3& eye,
                           const glm::dvec3& forward, const glm::dvec3& up, double halfAngle,
                           double range) {
  ShadowFace f;
  f.light = light;
  f.face = face;
  f.view.viewFromWorld = glm::lookAt(eye, eye + forward, up);
  f.view.halfX = f.view.halfY = std::tan(halfAngle);
  f.view.znear = range * kNearFraction;
  f.view.zfar = range;
  f.mapFromWorld =
      glm::perspective(2.0 * halfAngle, 1.0, f.view.znear, f.view.zfar) * f.view.viewFromWorld;
  return f;
}

bool empty(const Bounds& b) {
  return !(b.min.x <= b.max.x && b.min.y <= b.max.y && b.min.z <= b.max.z);
}

glm::dvec3 corner(const Bounds& b, int c) {
  return {c & 1 ? b.max.x : b.min.x, c & 2 ? b.max.y : b.min.y, c & 4 ? b.max.z : b.min.z};
}

// An orthographic face along `direction`: across it around the receivers' eight corners, along it
// around the scene's (the casters: a caster shadows a receiver only where both project to one
// texel, so the receivers' extent across suffices).
ShadowFace directionalFace(uint32_t light, const glm::dvec3& direction, const Bounds& geometry,
                           const Bounds& receivers) {
  const glm::dvec3 lo(geometry.min), hi(geometry.max);
  const double radius = 0.5 * glm::length(hi - lo);
  const glm::dvec3 centre = 0.5 * (glm::dvec3(receivers.min) + glm::dvec3(receivers.max));
  // The eye beyond every caster so every depth is positive; a margin of rounding on every side.
  const double margin = 1e-3 * std::max(radius, 1e-3);
  const double reach = glm::length(centre - 0.5 * (lo + hi)) + radius;
  const glm::dvec3 eye = centre - direction * (reach + 2.0 * margin);
  ShadowFace f;
  f.light = light;
  f.view.viewFromWorld = glm::lookAt(eye, centre, anyUp(direction));
  f.view.orthographic = true;
  double half = 0.0, dmin = std::numeric_limits<double>::max(), dmax = 0.0;
  for (int c = 0; c < 8; ++c) {
    const glm::dvec3 r = glm::dvec3(f.view.viewFromWorld * glm::dvec4(corner(receivers, c), 1.0));
    half = std::max({half, std::abs(r.x), std::abs(r.y)});
    const glm::dvec3 v = glm::dvec3(f.view.viewFromWorld * glm::dvec4(corner(geometry, c), 1.0));
    dmin = std::min(dmin, -v.z);
    dmax = std::max(dmax, -v.z);
  }
  f.view.halfX = f.view.halfY = half + margin;
  f.view.znear = std::max(dmin - margin, margin);
  f.view.zfar = dmax + margin;
  f.mapFromWorld = glm::ortho(-f.view.halfX, f.view.halfX, -f.view.halfY, f.view.halfY,
                              f.view.znear, f.view.zfar) *
                   f.view.viewFromWorld;
  return f;
}

// The faces of one light, without sizes (in cube order for a point light).
std::vector<ShadowFace> facesOf(uint32_t index, const SceneLight& l, const Bounds& geometry,
                                const Bounds& receivers, std::vector<std::string>& notes) {
  std::vector<ShadowFace> faces;
  const glm::dvec3 dir = glm::normalize(glm::dvec3(l.direction));
  switch (l.type) {
    case SceneLightType::Point: {
      // OpenGL's cube-map faces: their order and (forward, up) pairs.
      static const glm::dvec3 kForward[6] = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},
                                             {0, -1, 0}, {0, 0, 1},  {0, 0, -1}};
      static const glm::dvec3 kUp[6] = {{0, -1, 0}, {0, -1, 0}, {0, 0, 1},
                                        {0, 0, -1}, {0, -1, 0}, {0, -1, 0}};
      for (int k = 0; k < 6; ++k)
        faces.push_back(
            perspectiveFace(index, k, l.position, kForward[k], kUp[k], kPiDouble / 4.0, l.range));
      break;
    }
    case SceneLightType::Spot: {
      double half = double(l.outerConeAngle);
      if (2.0 * half > kMaxSpotFov) {
        notes.push_back("shadow maps: light " + std::to_string(index) + " (spot): its cone of " +
                        fullText(std::round(2.0 * half * 180.0 / kPiDouble * 10.0) / 10.0) +
                        " degrees is wider than a map's 170: the rim beyond 85 degrees from its "
                        "axis lies outside its shadow map");
        half = kMaxSpotFov / 2.0;
      }
      faces.push_back(perspectiveFace(index, 0, l.position, dir, anyUp(dir), half, l.range));
      break;
    }
    case SceneLightType::Directional:
      if (empty(geometry))
        throw Error("shadow maps: light " + std::to_string(index) +
                    " (directional) casts a shadow but the scene has no geometry to fit its "
                    "map to");
      faces.push_back(
          directionalFace(index, dir, geometry, empty(receivers) ? geometry : receivers));
      break;
  }
  return faces;
}

}  // namespace

void checkShadowAtlasOptions(const ShadowAtlasOptions& o) {
  if (!powerOfTwo(o.mapSize) || o.mapSize < kShadowMinFaceSize || o.mapSize > kShadowMaxFaceSize)
    badOptionValue("--shadow-map-size", std::to_string(o.mapSize),
                   "expected a power of two from " + std::to_string(kShadowMinFaceSize) + " to " +
                       std::to_string(kShadowMaxFaceSize));
  if (!(std::isfinite(o.budgetMB) && o.budgetMB > 0.0 && o.budgetMB <= kShadowMaxBudgetMB))
    badOptionValue("--shadow-budget", fullText(o.budgetMB),
                   "expected megabytes (MiB) above 0, at most " + fullText(kShadowMaxBudgetMB));
}

ShadowAtlasLayout planShadowAtlas(const std::vector<SceneLight>& lights, const Bounds& geometry,
                                  const SceneCamera& camera, const ShadowAtlasOptions& o,
                                  const Bounds& receivers) {
  checkShadowAtlasOptions(o);
  ShadowAtlasLayout layout;
  const glm::dvec3 eye(glm::inverse(camera.viewFromWorld) * glm::dvec4(0.0, 0.0, 0.0, 1.0));
  std::vector<std::vector<ShadowFace>> perLight;
  for (size_t i = 0; i < lights.size(); ++i) {
    const SceneLight& l = lights[i];
    if (!l.castsShadow) continue;
    ShadowLightMap m;
    m.light = uint32_t(i);
    m.type = l.type;
    perLight.push_back(facesOf(uint32_t(i), l, geometry, receivers, layout.notes));
    m.faces = int(perLight.back().size());
    if (l.type == SceneLightType::Directional) {
      m.requestedSize = std::min(kDirectionalFactor * o.mapSize, kShadowMaxFaceSize);
      m.importance = std::numeric_limits<double>::infinity();
    } else {
      // The share of the view the light's sphere covers (1 with the eye inside it), by range.
      const double d = glm::length(l.position - eye), r = double(l.range);
      m.importance = (d <= r ? 1.0 : (r / d) * (r / d)) * r;
      m.requestedSize = o.mapSize;
    }
    m.size = m.requestedSize;
    layout.lights.push_back(m);
  }
  if (layout.lights.empty()) return layout;

  // The budget: lights lose resolution in rounds of one halving, least important first.
  const uint64_t budgetTexels = uint64_t(o.budgetMB * double(1 << 20)) / sizeof(float);
  uint64_t area = 0;
  for (const ShadowLightMap& m : layout.lights)
    area += uint64_t(m.faces) * uint64_t(m.size) * uint64_t(m.size);
  std::vector<size_t> order(layout.lights.size());
  std::iota(order.begin(), order.end(), size_t(0));
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    const double ia = layout.lights[a].importance, ib = layout.lights[b].importance;
    return ia < ib || (ia == ib && a > b);  // ties: the higher index loses first
  });
  auto fits = [&] { return atlasTexels(area) <= budgetTexels; };
  for (bool shrunk = true; !fits() && shrunk;) {
    shrunk = false;
    for (size_t k = 0; k < order.size() && !fits(); ++k) {
      ShadowLightMap& m = layout.lights[order[k]];
      if (m.size <= kShadowMinFaceSize) continue;
      const uint64_t s = uint64_t(m.size);
      area -= uint64_t(m.faces) * (s * s - (s / 2) * (s / 2));
      m.size /= 2;
      shrunk = true;
    }
  }
  if (!fits()) {
    uint64_t faces = 0;
    for (const ShadowLightMap& m : layout.lights) faces += uint64_t(m.faces);
    throw Error("--shadow-budget " + fullText(o.budgetMB) + " MB: the " + std::to_string(faces) +
                " shadow-map face(s) of " + std::to_string(layout.lights.size()) +
                " shadow-casting light(s) need " + megabytes(atlasTexels(area) * sizeof(float)) +
                " MB even at " + std::to_string(kShadowMinFaceSize) + "x" +
                std::to_string(kShadowMinFaceSize) + " each");
  }

  // W x W or W x W/2 (W >= every face: the area is at least the largest face's).
  const uint64_t texels = atlasTexels(area);
  int bits = 0;
  while ((uint64_t(1) << bits) < texels) ++bits;
  layout.width = 1 << ((bits + 1) / 2);
  layout.height = int(texels >> ((bits + 1) / 2));

  for (size_t k = 0; k < layout.lights.size(); ++k)
    for (ShadowFace& f : perLight[k]) {
      f.size = layout.lights[k].size;
      layout.faces.push_back(f);
    }
  // Largest first in Morton order: a face of side s starts at a multiple of s^2 of the order, so
  // it fills one aligned s x s cell; the W x W/2 atlas is the first half of a W x W one (its
  // top rows: y is the higher bit of each pair).
  std::vector<size_t> bySize(layout.faces.size());
  std::iota(bySize.begin(), bySize.end(), size_t(0));
  std::stable_sort(bySize.begin(), bySize.end(),
                   [&](size_t a, size_t b) { return layout.faces[a].size > layout.faces[b].size; });
  uint64_t offset = 0;
  for (size_t i : bySize) {
    ShadowFace& f = layout.faces[i];
    const uint64_t s = uint64_t(f.size), cell = offset / (s * s);
    f.x = int(deinterleave(cell, 0) * s);
    f.y = int(deinterleave(cell, 1) * s);
    offset += s * s;
  }

  std::vector<const ShadowLightMap*> lost;
  for (const ShadowLightMap& m : layout.lights)
    if (m.size < m.requestedSize) lost.push_back(&m);
  if (!lost.empty()) {
    std::string note = "shadow maps: " + std::to_string(lost.size()) + " of " +
                       std::to_string(layout.lights.size()) +
                       " shadow-casting light(s) lost resolution to --shadow-budget " +
                       fullText(o.budgetMB) + " MB:";
    for (size_t k = 0; k < lost.size() && k < kNoteLights; ++k)
      note += std::string(k ? "," : "") + " light " + std::to_string(lost[k]->light) + " (" +
              toString(lost[k]->type) + ") " + std::to_string(lost[k]->requestedSize) + " -> " +
              std::to_string(lost[k]->size);
    if (lost.size() > kNoteLights)
      note += ", and " + std::to_string(lost.size() - kNoteLights) +
              " more (stats.json shadow_maps.lights)";
    layout.notes.push_back(note);
  }
  return layout;
}

Bounds viewGeometryBounds(const GBuffer& g, const SceneCamera& camera) {
  const CameraIntrinsics in = CameraIntrinsics::from(camera, g.width, g.height);
  const glm::dmat4 worldFromView = glm::inverse(camera.viewFromWorld);
  glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
  double far = 0.0;
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      const double d = g.depth[size_t(y) * size_t(g.width) + size_t(x)];
      if (!(d > 0.0)) continue;
      const double nx = 2.0 * (x + 0.5) / g.width - 1.0, ny = 1.0 - 2.0 * (y + 0.5) / g.height;
      const glm::dvec3 p(worldFromView *
                         glm::dvec4(nx * in.tanHalfFovX * d, ny * in.tanHalfFovY * d, -d, 1.0));
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
      far = std::max(far, d);
    }
  Bounds b;
  if (far == 0.0) return b;
  // A pixel centre stands for its whole footprint: half a pixel at the deepest depth, and more.
  const double footprint =
      far * std::max(double(in.tanHalfFovX) / g.width, double(in.tanHalfFovY) / g.height) * 2.0;
  b.extend(glm::vec3(lo - footprint));
  b.extend(glm::vec3(hi + footprint));
  return b;
}

}  // namespace ts
