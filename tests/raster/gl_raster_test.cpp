// The OpenGL rasterizer (src/raster/gl_rasterizer.cpp) against the software one: coverage, the
// fill rule, facing, depth, normals and material planes, on hand-made scenes, the built-in scenes
// (several frames, random cameras through the near plane, odd sizes) and the real scenes in
// ../shared/scenes; images shaded from its G-buffer pass the reference checks. Every test skips,
// saying why, where no OpenGL context can be made. The bounds are derived in docs/opengl.md
// ("How close the two rasterizers are"); the measured figures are recorded as test properties
// and printed.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <iostream>
#include <map>
#include <random>
#include <tuple>

#include <glm/gtc/matrix_transform.hpp>

#include "raster/egl_context.h"
#include "gbuffer/gbuffer_compare.h"
#include "raster/gl_rasterizer.h"
#include "raster/raster_backend.h"
#include "reference_check.h"
#include "require_gl.h"
#include "scene/scene_features.h"
#include "shaders/material_planes.h"
#include "util/error.h"
#include "util/pi.h"
#include "test_scenes.h"
#include "gltf_builder.h"
#include "png_bytes.h"
#include "scene/scene_loader.h"

namespace ts {
namespace {

// ---- The per-pixel bound (docs/opengl.md) ----------------------------------------------------
//
// Both rasterizers snap vertices to 1/256 pixel and use the same top-left rule, so coverage can
// only differ where an edge lies within the difference of the two snapped positions of a pixel
// centre. Attribute values differ because OpenGL interpolates over its snapped, float-transformed
// triangle while the software rasterizer interpolates the exact plane in double: each vertex
// moves by at most kMoveFraction ... on screen, which moves a barycentric coordinate by at most
// 3 kMove / h_min (h_min: the smallest altitude of the screen triangle in pixels), times the
// ratio of the vertices' depths for perspective-correct interpolation.
constexpr double kMove = 1.0 / 128.0;  // 2 snap steps: >= half a step per axis of each side
                                       // (sqrt(2)/512) plus the float transform's < 1e-3 px
// Float rounding of the view transform, the interpolation and the normalisation, relative.
constexpr double kFloatRel = 8.0 * 1.1920929e-7;

// What the bound needs to know about one triangle, from the scene and the camera (double).
struct TriangleBound {
  bool valid = false;          // false: not bounded (degenerate on screen)
  double baryError = 0.0;      // bound on the barycentric difference
  double invDepthRange = 0;    // max 1/d_i - min 1/d_i over the (near-clipped) vertices
  double depthRatio = 1.0;     // max d_i / min d_i: amplifies float rounding in OpenGL's
                               // perspective division (a/w and 1/w planes, then their ratio)
  double worldScale = 0.0;     // largest |coordinate| entering the float view transform
  double normalSpread = 0.0;   // largest angle between the vertex normals (view space)
  double normalGain = 1.0;     // 1 / shortest interpolated vertex-normal length
  double uvSpread = 0.0;       // largest |uv_i - uv_j| (max norm)
  double uvScale = 0.0;        // largest |uv| component
  double tangentSpread = 0.0;  // largest angle between the vertex tangents (normal maps)
};

TriangleBound boundOf(const Scene& scene, const SceneCamera& camera, const CameraIntrinsics& in,
                      uint32_t t) {
  TriangleBound b;
  const glm::dmat4 view(camera.viewFromWorld);
  glm::dvec3 p[3], n[3];
  glm::dvec2 uv[3];
  for (int k = 0; k < 3; ++k) {
    const Vertex& v = scene.vertices[scene.indices[3 * t + uint32_t(k)]];
    p[k] = glm::dvec3(view * glm::dvec4(glm::dvec3(v.position), 1.0));
    n[k] = glm::dvec3(glm::transpose(glm::inverse(glm::dmat3(view))) * glm::dvec3(v.normal));
    uv[k] = glm::dvec2(v.uv);
    for (int c = 0; c < 3; ++c)
      b.worldScale = std::max(b.worldScale, double(std::abs(v.position[c])));
    for (int c = 0; c < 2; ++c) b.uvScale = std::max(b.uvScale, std::abs(uv[k][c]));
  }
  for (int c = 0; c < 3; ++c) b.worldScale += std::abs(view[3][c]);
  // Clip against the near plane (as both rasterizers do) and project the polygon.
  std::vector<glm::dvec3> poly;
  for (int k = 0; k < 3; ++k) {
    const glm::dvec3 &a = p[k], &c = p[(k + 1) % 3];
    const double da = -a.z - in.znear, dc = -c.z - in.znear;
    if (da >= 0) poly.push_back(a);
    if ((da >= 0) != (dc >= 0)) poly.push_back(a + (c - a) * (da / (da - dc)));
  }
  if (poly.size() < 3) return b;
  std::vector<glm::dvec2> s;
  double minInv = 1e300, maxInv = 0.0;
  for (const auto& q : poly) {
    const double d = -q.z;
    s.push_back({(q.x / (d * in.tanHalfFovX) + 1.0) * 0.5 * in.width,
                 (1.0 - q.y / (d * in.tanHalfFovY)) * 0.5 * in.height});
    minInv = std::min(minInv, 1.0 / d);
    maxInv = std::max(maxInv, 1.0 / d);
  }
  // Smallest altitude over the fan's sub-triangles.
  double hMin = 1e300;
  for (size_t k = 1; k + 1 < s.size(); ++k) {
    const glm::dvec2 e[3] = {s[k] - s[0], s[k + 1] - s[k], s[0] - s[k + 1]};
    const double area2 = std::abs(e[0].x * e[1].y - e[0].y * e[1].x);
    double longest = 0.0;
    for (const auto& edge : e) longest = std::max(longest, glm::length(edge));
    if (longest > 0.0) hMin = std::min(hMin, area2 / longest);
  }
  if (!(hMin > 0.0) || hMin > 1e299) return b;
  b.valid = true;
  b.baryError = std::min(1.0, 3.0 * kMove * (maxInv / minInv) / hMin);
  b.invDepthRange = maxInv - minInv;
  b.depthRatio = maxInv / minInv;
  double minLen = 1.0;
  for (int i = 0; i < 3; ++i) {
    for (int j = i + 1; j < 3; ++j) {
      const double li = glm::length(n[i]), lj = glm::length(n[j]);
      if (li > 0 && lj > 0) {
        const double c = glm::dot(n[i], n[j]) / (li * lj);
        const double angle = std::acos(std::clamp(c, -1.0, 1.0));
        b.normalSpread = std::max(b.normalSpread, angle);
        minLen = std::min(minLen, std::cos(0.5 * angle));  // of unit normals interpolated
      }
      b.uvSpread = std::max({b.uvSpread, std::abs(uv[i].x - uv[j].x), std::abs(uv[i].y - uv[j].y)});
    }
  }
  b.normalGain = minLen > 1e-3 ? 1.0 / minLen : 1e3;
  if (!scene.tangents.empty())
    for (int i = 0; i < 3; ++i)
      for (int j = i + 1; j < 3; ++j) {
        const glm::dvec3 ti(scene.tangents[scene.indices[3 * t + uint32_t(i)]]),
            tj(scene.tangents[scene.indices[3 * t + uint32_t(j)]]);
        const double li = glm::length(ti), lj = glm::length(tj);
        b.tangentSpread = std::max(
            b.tangentSpread, li > 0 && lj > 0
                                 ? std::acos(std::clamp(glm::dot(ti, tj) / (li * lj), -1.0, 1.0))
                                 : kPiDouble);
      }
  return b;
}

// Largest difference between neighbouring texels of a texture (REPEAT wrap): how much a sample
// can change per texel of UV movement.
double texelLipschitz(const Texture& t) {
  double l = 0.0;
  for (int y = 0; y < t.height; ++y)
    for (int x = 0; x < t.width; ++x) {
      const glm::vec4 a = t.texels[size_t(y) * size_t(t.width) + size_t(x)];
      const glm::vec4 r = t.texels[size_t(y) * size_t(t.width) + size_t((x + 1) % t.width)];
      const glm::vec4 d = t.texels[size_t((y + 1) % t.height) * size_t(t.width) + size_t(x)];
      for (int c = 0; c < 4; ++c)
        l = std::max({l, double(std::abs(a[c] - r[c])), double(std::abs(a[c] - d[c]))});
    }
  return l;
}

// The shortest tangent-space normal (2 rgb - 1) (s, s, 1) of a normal map's texels: how much a
// change of the vector can turn it.
double shortestMapNormal(const Texture& t, float scale) {
  double shortest = 1e300;
  for (const glm::vec4& v : t.texels) {
    const glm::dvec3 tn((2.0 * v.x - 1.0) * scale, (2.0 * v.y - 1.0) * scale, 2.0 * v.z - 1.0);
    shortest = std::min(shortest, glm::length(tn));
  }
  return shortest;
}

struct Tolerances {
  double depthRel, normalRad, material;
};

// The per-pixel tolerances for triangle t at linear depth `depth`.
Tolerances tolerancesAt(const Scene& scene, const TriangleBound& b, uint32_t t, double depth,
                        std::map<int, double>& lipschitz) {
  Tolerances tol;
  tol.depthRel = kFloatRel * (1.0 + b.worldScale / depth) + b.baryError * depth * b.invDepthRange;
  // The 2e-5 rad floor: llvmpipe's interpolation, measured up to 1.3e-5 rad on flat atrium
  // triangles seen from a random camera, more than the float terms explain (docs/opengl.md).
  tol.normalRad = 2e-5 + kFloatRel * b.depthRatio + b.baryError * b.normalSpread * b.normalGain;
  static const Material kDefault;
  const Material& m = scene.triangleMaterial.empty()
                          ? (scene.materials.empty() ? kDefault : scene.materials[0])
                          : scene.materials[scene.triangleMaterial[t]];
  // Untextured terms are the same float products on both sides: exact. A texture sample moves by
  // its texel Lipschitz constant per texel of UV difference, plus the sampler's weight precision
  // (2^-8 of a texel on GPUs with 8-bit filter weights; llvmpipe's are float).
  double material = 0.0;
  const double factor =
      std::max({1.0f, m.diffuse.x, m.diffuse.y, m.diffuse.z, m.baseColor.x, m.baseColor.y,
                m.baseColor.z, m.emissive.x, m.emissive.y, m.emissive.z, m.metallic, m.roughness});
  for (int slot = 0; slot < TS_TEXTURE_SLOTS; ++slot) {
    const int index = materialTexture(m, slot);
    if (index < 0 || scene.textures[size_t(index)].width <= 0) continue;
    const Texture& tex = scene.textures[size_t(index)];
    auto it = lipschitz.find(index);
    if (it == lipschitz.end()) it = lipschitz.emplace(index, texelLipschitz(tex)).first;
    const double size = std::max(tex.width, tex.height);
    const double texels =
        size * (b.baryError * b.uvSpread + kFloatRel * b.depthRatio * (1.0 + b.uvScale));
    material = std::max(material, factor * it->second * (texels + 1.0 / 256.0));
  }
  tol.material = material + kFloatRel;
  // A normal map: its texel moves as a material texture's does (Lipschitz constant times the UV
  // difference in texels, plus the sampler's weight precision), which moves the tangent-space
  // normal by 2 |scale| (1 for z) times that per component and turns it by at most pi/2 times that
  // over its shortest length; the tangent frame turns with the interpolated tangents as the normal
  // does with the vertex normals.
  if (m.normalTexture >= 0 && !scene.tangents.empty() &&
      scene.textures[size_t(m.normalTexture)].width > 0) {
    const Texture& tex = scene.textures[size_t(m.normalTexture)];
    auto it = lipschitz.find(m.normalTexture);
    if (it == lipschitz.end()) it = lipschitz.emplace(m.normalTexture, texelLipschitz(tex)).first;
    const double size = std::max(tex.width, tex.height);
    const double texels =
        size * (b.baryError * b.uvSpread + kFloatRel * b.depthRatio * (1.0 + b.uvScale));
    const double change = 2.0 * std::max(1.0, double(std::abs(m.normalScale))) * std::sqrt(3.0) *
                          it->second * (texels + 1.0 / 256.0);
    // Cached beside the Lipschitz constants, under negative keys (texture indices are >= 0).
    auto sh = lipschitz.find(-1 - m.normalTexture);
    if (sh == lipschitz.end())
      sh = lipschitz.emplace(-1 - m.normalTexture, shortestMapNormal(tex, m.normalScale)).first;
    const double shortest = std::max(sh->second, 1e-3);
    tol.normalRad += std::min(kPiDouble, 0.5 * kPiDouble * change / shortest) +
                     b.baryError * b.tangentSpread * b.normalGain;
  }
  return tol;
}

// The GL G-buffer against the software one for one frame; fails the test on any violation.
struct FrameFigures {
  GBufferComparison c;
  uint64_t outOfBound = 0;           // same-triangle pixels outside their per-pixel tolerance
  uint64_t unexplainedTriangle = 0;  // other winner, neither an edge nor a depth tie
  uint64_t coverageBound = 0;
  double worstDepthRatio = 0, worstNormalRatio = 0, worstMaterialRatio = 0;  // error / tolerance
};

FrameFigures compareFrame(const Scene& scene, GlRasterizer& gl, const SceneCamera& camera,
                          int width, int height, ShadingModel model, const std::string& label) {
  RasterOptions o;
  o.model = model;
  o.triangleIds = true;
  const GBuffer soft = rasterize(scene, camera, width, height, o);
  const GBuffer hard = gl.rasterize(camera, width, height, o);
  FrameFigures f;
  f.c = compareGBuffers(soft, hard);
  const CameraIntrinsics in = CameraIntrinsics::from(camera, width, height);
  std::map<uint32_t, TriangleBound> bounds;
  std::map<int, double> lipschitz;
  auto boundFor = [&](int32_t t) -> const TriangleBound& {
    auto it = bounds.find(uint32_t(t));
    if (it == bounds.end())
      it = bounds.emplace(uint32_t(t), boundOf(scene, camera, in, uint32_t(t))).first;
    return it->second;
  };
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const size_t i = size_t(y) * size_t(width) + size_t(x);
      if (!(soft.depth[i] > 0.0f) || !(hard.depth[i] > 0.0f)) continue;
      const int32_t ts = soft.triangleId[i], th = hard.triangleId[i];
      const TriangleBound& bs = boundFor(ts);
      if (!bs.valid) continue;  // degenerate on screen: counted in c, not bounded
      const Tolerances tol = tolerancesAt(scene, bs, uint32_t(ts), soft.depth[i], lipschitz);
      const double depthRel = std::abs(double(hard.depth[i]) - soft.depth[i]) / soft.depth[i];
      if (ts != th) {
        // Another winner: an edge between the two (compareGBuffers' "edge" test), or a depth tie
        // decided the other way (both depths within the depth tolerance of either triangle).
        const bool edge = [&] {
          for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
              const int nx = x + dx, ny = y + dy;
              if (nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
              const size_t j = size_t(ny) * size_t(width) + size_t(nx);
              if (soft.triangleId[j] == th || hard.triangleId[j] == ts) return true;
            }
          return false;
        }();
        const TriangleBound& bh = boundFor(th);
        const double tieTol = std::max(
            tol.depthRel,
            bh.valid ? tolerancesAt(scene, bh, uint32_t(th), hard.depth[i], lipschitz).depthRel
                     : 1.0);
        if (!edge && depthRel > 2.0 * tieTol) {
          ++f.unexplainedTriangle;
          ADD_FAILURE() << label << ": pixel (" << x << "," << y << ") software triangle " << ts
                        << " at depth " << soft.depth[i] << ", OpenGL triangle " << th
                        << " at depth " << hard.depth[i] << ": neither an edge nor a depth tie";
        }
        continue;
      }
      const glm::dvec3 ns(soft.normal[i]), nh(hard.normal[i]);
      const double angle = std::atan2(glm::length(glm::cross(ns, nh)), glm::dot(ns, nh));
      double material = 0.0;
      for (int c = 0; c < 4; ++c)
        material = std::max({material, double(std::abs(soft.diffuse[i][c] - hard.diffuse[i][c])),
                             double(std::abs(soft.specular[i][c] - hard.specular[i][c])),
                             double(std::abs(soft.emissive[i][c] - hard.emissive[i][c]))});
      f.worstDepthRatio = std::max(f.worstDepthRatio, depthRel / tol.depthRel);
      f.worstNormalRatio = std::max(f.worstNormalRatio, angle / tol.normalRad);
      f.worstMaterialRatio = std::max(f.worstMaterialRatio, material / tol.material);
      if (depthRel > tol.depthRel || angle > tol.normalRad || material > tol.material) {
        if (++f.outOfBound <= 5)
          ADD_FAILURE() << label << ": pixel (" << x << "," << y << ") triangle " << ts
                        << ": depth rel " << depthRel << " (tolerance " << tol.depthRel
                        << "), normal " << angle << " rad (" << tol.normalRad << "), material "
                        << material << " (" << tol.material << ")";
      }
    }
  // Coverage: only along silhouettes, and at most ~2 kMove of the silhouette pixels (an edge
  // moved by kMove flips the pixel centres within kMove of it), plus a few for vertices.
  f.coverageBound = uint64_t(2.0 * kMove * double(f.c.silhouetteA)) + 4;
  EXPECT_EQ(f.c.mismatchesOffSilhouette, 0u) << label << ": " << f.c.summary();
  EXPECT_LE(f.c.onlyA + f.c.onlyB, f.coverageBound) << label << ": " << f.c.summary();
  std::cout << label << ": " << f.c.summary() << "; worst error/tolerance: depth "
            << f.worstDepthRatio << ", normal " << f.worstNormalRatio << ", material "
            << f.worstMaterialRatio << "\n";
  return f;
}

// ---- Hand-made scenes --------------------------------------------------------------------------

SceneCamera lookingDownZ() {
  SceneCamera c;
  c.yfov = 1.5707963f;
  c.znear = 0.1f;
  c.zfar = 100.0f;
  return c;
}

glm::vec3 unproject(const CameraIntrinsics& in, double sx, double sy, double d) {
  const double ndcX = 2.0 * sx / in.width - 1.0, ndcY = 1.0 - 2.0 * sy / in.height;
  return glm::vec3(glm::dvec3(ndcX * in.tanHalfFovX * d, ndcY * in.tanHalfFovY * d, -d));
}

// A linear texture of random texels, each channel drawn in its own statement (in a call's
// arguments the order would be the compiler's; drawnLastFirst keeps the values g++ drew).
Texture randomTexture(int width, int height, uint32_t seed) {
  Texture t;
  t.width = width;
  t.height = height;
  t.srgb = false;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (int i = 0; i < width * height; ++i) {
    const auto c = test::drawnLastFirst<3>([&] { return unit(rng); });
    t.texels.emplace_back(c[0], c[1], c[2], 1.0f);
  }
  return t;
}

// Appends a quad facing the camera at depth 3 over pixels [x0, x1] x [y0, y1], white and textured
// by `texture` with the wrap modes `wrap` (a material and a texture of its own), with the UV that
// `uvAt(x, y)` gives each corner.
template <typename UvAt>
void addTexturedQuad(Scene& s, const CameraIntrinsics& in, Texture texture,
                     std::pair<TextureWrap, TextureWrap> wrap, double x0, double x1, double y0,
                     double y1, UvAt uvAt) {
  std::tie(texture.wrapS, texture.wrapT) = wrap;
  s.textures.push_back(texture);
  Material m;
  m.diffuse = glm::vec3(1.0f);
  m.diffuseTexture = int(s.textures.size() - 1);
  s.materials.push_back(m);
  const uint32_t material = uint32_t(s.materials.size() - 1);
  const uint32_t base = uint32_t(s.vertices.size());
  for (auto [x, y] : {std::pair{x0, y0}, {x0, y1}, {x1, y0}, {x1, y1}})
    s.vertices.push_back(Vertex{unproject(in, x, y, 3.0), glm::vec3(0.0f, 0.0f, 1.0f), uvAt(x, y)});
  s.indices.insert(s.indices.end(), {base, base + 1, base + 2, base + 2, base + 1, base + 3});
  s.triangleMaterial.insert(s.triangleMaterial.end(), {material, material});
}

void addTriangle(Scene& s, glm::vec3 a, glm::vec3 b, glm::vec3 c, uint32_t material,
                 glm::vec3 normal) {
  const uint32_t base = uint32_t(s.vertices.size());
  for (const auto& p : {a, b, c}) s.vertices.push_back({p, normal, {0.0f, 0.0f}});
  s.indices.insert(s.indices.end(), {base, base + 1, base + 2});
  s.triangleMaterial.push_back(material);
}

TEST(GlRaster, FillRuleMatchesSoftwareOnEdgesThroughPixelCentres) {
  REQUIRE_GL();
  const int W = 48, H = 40;
  const SceneCamera cam = lookingDownZ();
  const CameraIntrinsics in = CameraIntrinsics::from(cam, W, H);
  Scene s;
  s.name = "fill rule";
  s.materials.resize(2);
  s.materials[1].diffuse = glm::vec3(0.2f, 0.9f, 0.1f);
  const glm::vec3 n(0, 0, 1);
  auto at = [&](double x, double y) { return unproject(in, x, y, 4.0); };
  // A rectangle whose border runs through pixel centres (top/left in, bottom/right out), split
  // along its diagonal (shared edge through centres), and a fan around a centre.
  addTriangle(s, at(3.5, 2.5), at(3.5, 20.5), at(21.5, 20.5), 0, n);
  addTriangle(s, at(3.5, 2.5), at(21.5, 20.5), at(21.5, 2.5), 1, n);
  const glm::vec3 centre = at(34.5, 20.5);
  const double r = 9.0;
  for (int k = 0; k < 8; ++k) {
    const double a0 = k * 0.7853981633974483, a1 = (k + 1) * 0.7853981633974483;
    // Counter-clockwise on screen = clockwise in image coordinates (y down).
    addTriangle(s, centre, at(34.5 + r * std::cos(a1), 20.5 - r * std::sin(a1)),
                at(34.5 + r * std::cos(a0), 20.5 - r * std::sin(a0)), uint32_t(k % 2), n);
  }
  GlRasterizer gl(s);
  RasterOptions o;
  o.triangleIds = true;
  const GBuffer soft = rasterize(s, cam, W, H, o), hard = gl.rasterize(cam, W, H, o);
  int covered = 0;
  for (size_t i = 0; i < soft.pixelCount(); ++i) {
    ASSERT_EQ(soft.triangleId[i], hard.triangleId[i]) << "pixel (" << i % W << "," << i / W << ")";
    covered += soft.triangleId[i] >= 0;
  }
  // Rectangle x 3.5..21.5, y 2.5..20.5: its top row and left column are in, the pixels whose
  // centres lie on its bottom and right edges are out.
  EXPECT_GE(soft.triangleId[2 * W + 3], 0);
  EXPECT_EQ(soft.triangleId[10 * W + 20], 1);
  EXPECT_EQ(soft.triangleId[19 * W + 10], 0);
  EXPECT_EQ(soft.triangleId[20 * W + 10], -1);
  EXPECT_EQ(soft.triangleId[10 * W + 21], -1);
  EXPECT_GT(covered, 18 * 18);
}

TEST(GlRaster, FacingNormalsAndMaterialTermsMatchSoftware) {
  REQUIRE_GL();
  const int W = 64, H = 48;
  const SceneCamera cam = lookingDownZ();
  const CameraIntrinsics in = CameraIntrinsics::from(cam, W, H);
  Scene s;
  s.name = "facing";
  Material single, twoSided;
  single.diffuse = {0.7f, 0.2f, 0.1f};
  single.specular = {0.3f, 0.3f, 0.5f};
  single.shininess = 77.0f;
  single.emissive = {0.0f, 0.5f, 0.25f};
  twoSided = single;
  twoSided.doubleSided = true;
  s.materials = {single, twoSided};
  auto at = [&](double x, double y, double d) { return unproject(in, x, y, d); };
  const glm::vec3 n(0.3f, 0.2f, 0.9f);
  // Front-facing (counter-clockwise on screen), then back-facing single- and double-sided, then
  // zero vertex normals (the geometric normal is used).
  addTriangle(s, at(2, 2, 3), at(2, 20, 3), at(30, 2, 5), 0, n);
  addTriangle(s, at(34, 2, 3), at(62, 2, 5), at(34, 20, 3), 0, n);
  addTriangle(s, at(2, 26, 3), at(30, 26, 5), at(2, 46, 4), 1, n);
  addTriangle(s, at(34, 26, 3), at(34, 46, 4), at(62, 26, 5), 1, glm::vec3(0.0f));
  GlRasterizer gl(s);
  for (ShadingModel model : {ShadingModel::BlinnPhong, ShadingModel::MetallicRoughness}) {
    RasterOptions o;
    o.model = model;
    o.triangleIds = true;
    const GBuffer soft = rasterize(s, cam, W, H, o), hard = gl.rasterize(cam, W, H, o);
    EXPECT_EQ(hard.model, model);
    int seen[4] = {};
    for (size_t i = 0; i < soft.pixelCount(); ++i) {
      ASSERT_EQ(soft.triangleId[i], hard.triangleId[i]) << i;
      const int t = soft.triangleId[i];
      if (t < 0) continue;
      ++seen[t];
      const glm::vec3 a(soft.normal[i]), b(hard.normal[i]);
      // The geometric normal comes from screen-space derivatives in OpenGL: float differences of
      // neighbouring positions, ~1e-4 relative here.
      EXPECT_GT(glm::dot(a, b), t == 3 ? 0.9999f : 0.999999f) << "triangle " << t;
      EXPECT_EQ(soft.diffuse[i], hard.diffuse[i]) << "triangle " << t;
      EXPECT_EQ(soft.specular[i], hard.specular[i]) << "triangle " << t;
      EXPECT_EQ(soft.emissive[i], hard.emissive[i]) << "triangle " << t;
    }
    for (int t = 0; t < 4; ++t) EXPECT_GT(seen[t], 20) << "triangle " << t;
  }
  EXPECT_THROW(gl.rasterize(cam, W, H,
                            [] {
                              RasterOptions o;
                              o.fragmentCounts = true;
                              return o;
                            }()),
               Error);
}

// glTF's wrap modes on both sides (issue #16 item 5): quads whose UVs run from -1.3 to 2.4, one
// per pair of modes, within the per-pixel bound (the texel Lipschitz constant covers a mirrored
// or clamped neighbour: it is one of the REPEAT neighbours or the texel itself).
TEST(GlRaster, TextureWrapModesMatchSoftware) {
  REQUIRE_GL();
  const int W = 96, H = 40;
  const SceneCamera cam = lookingDownZ();
  const CameraIntrinsics in = CameraIntrinsics::from(cam, W, H);
  using Wrap = TextureWrap;
  const std::pair<Wrap, Wrap> modes[] = {{Wrap::ClampToEdge, Wrap::MirroredRepeat},
                                         {Wrap::MirroredRepeat, Wrap::ClampToEdge},
                                         {Wrap::Repeat, Wrap::MirroredRepeat}};
  const Texture texture = randomTexture(5, 3, 16);
  Scene s;
  s.name = "wrap modes";
  for (size_t k = 0; k < 3; ++k) {
    const double x0 = 2.0 + 31.0 * double(k), x1 = x0 + 29.0, y0 = 2.0, y1 = 38.0;
    addTexturedQuad(s, in, texture, modes[k], x0, x1, y0, y1, [&](double x, double y) {
      return glm::vec2(float(-1.3 + 3.7 * (x - x0) / (x1 - x0)),
                       float(-1.2 + 3.5 * (y - y0) / (y1 - y0)));
    });
  }
  GlRasterizer gl(s);
  const FrameFigures f = compareFrame(s, gl, cam, W, H, ShadingModel::BlinnPhong, "wrap modes");
  EXPECT_GT(f.c.bothCovered, 3000u) << f.c.summary();
}

// The NEAREST filter on both sides: flat quads at constant depth with 2 pixels per texel, so that
// every pixel centre lies a quarter texel from the nearest texel edge (far beyond what the two
// interpolations differ by) and both pick the same texel; with a LINEAR OpenGL the blend of a
// quarter texel would exceed the bound.
TEST(GlRaster, TheNearestFilterMatchesSoftware) {
  REQUIRE_GL();
  const int W = 72, H = 40;
  const SceneCamera cam = lookingDownZ();
  const CameraIntrinsics in = CameraIntrinsics::from(cam, W, H);
  using Wrap = TextureWrap;
  Texture texture = randomTexture(8, 6, 5);
  texture.nearest = true;
  Scene s;
  s.name = "nearest";
  const std::pair<Wrap, Wrap> modes[] = {{Wrap::Repeat, Wrap::ClampToEdge},
                                         {Wrap::MirroredRepeat, Wrap::Repeat}};
  for (size_t k = 0; k < 2; ++k) {
    const double x0 = 2.0 + 36.0 * double(k), x1 = x0 + 32.0, y0 = 2.0, y1 = 38.0;
    // u * 8 = (x - x0) / 2 - 6, v * 6 = (y - y0) / 2 - 5: texel coordinates -6..10 and -5..13.
    addTexturedQuad(s, in, texture, modes[k], x0, x1, y0, y1, [&](double x, double y) {
      return glm::vec2(float(((x - x0) / 2.0 - 6.0) / 8.0), float(((y - y0) / 2.0 - 5.0) / 6.0));
    });
  }
  GlRasterizer gl(s);
  const FrameFigures f = compareFrame(s, gl, cam, W, H, ShadingModel::BlinnPhong, "nearest");
  EXPECT_GT(f.c.bothCovered, 2000u) << f.c.summary();
}

TEST(GlRaster, OddSizesAndFarPlane) {
  REQUIRE_GL();
  const Scene& scene = test::builtinScene("street", "few");
  GlRasterizer gl(scene);
  SceneCamera cam = scene.camera(40);
  for (auto [w, h] : {std::pair{1, 1}, std::pair{7, 3}, std::pair{3, 97}, std::pair{333, 187}})
    compareFrame(scene, gl, cam, w, h, ShadingModel::BlinnPhong,
                 "street " + std::to_string(w) + "x" + std::to_string(h));
  cam.zfar = 40.0f;  // cuts the street: the far plane rejects per pixel on both sides
  FrameFigures f = compareFrame(scene, gl, cam, 160, 90, ShadingModel::BlinnPhong, "street far 40");
  EXPECT_LT(f.c.coveredA, 160u * 90u);
  EXPECT_THROW(gl.rasterize(cam, 70000, 2), Error);
}

// ---- Built-in and real scenes --------------------------------------------------------------

void compareScene(const Scene& scene, const std::vector<int>& frames, int width, int height,
                  ShadingModel model, const std::string& name) {
  GlRasterizer gl(scene);
  FrameFigures total;
  for (int frame : frames) {
    FrameFigures f = compareFrame(scene, gl, scene.camera(frame), width, height, model,
                                  name + " frame " + std::to_string(frame));
    total.c.onlyA += f.c.onlyA + f.c.onlyB;
    total.c.silhouetteA += f.c.silhouetteA;
    total.c.triangleDiffers += f.c.triangleDiffers;
    total.c.maxDepthRel = std::max(total.c.maxDepthRel, f.c.maxDepthRel);
    total.c.maxNormalRad = std::max(total.c.maxNormalRad, f.c.maxNormalRad);
    total.c.maxDiffuse =
        std::max({total.c.maxDiffuse, f.c.maxDiffuse, f.c.maxSpecular, f.c.maxEmissive});
  }
  ::testing::Test::RecordProperty("coverage_mismatches", int(total.c.onlyA));
  ::testing::Test::RecordProperty("silhouette_pixels", int(total.c.silhouetteA));
  ::testing::Test::RecordProperty("other_triangle_pixels", int(total.c.triangleDiffers));
  ::testing::Test::RecordProperty("max_depth_rel", std::to_string(total.c.maxDepthRel));
  ::testing::Test::RecordProperty("max_normal_rad", std::to_string(total.c.maxNormalRad));
  ::testing::Test::RecordProperty("max_material_abs", std::to_string(total.c.maxDiffuse));
}

TEST(GlRaster, StreetFramesMatchSoftware) {
  REQUIRE_GL();
  compareScene(test::builtinScene("street", "many"), {0, 57, 150, 233}, 321, 179,
               ShadingModel::BlinnPhong, "street");
}

TEST(GlRaster, AtriumFramesMatchSoftwareInBothModels) {
  REQUIRE_GL();
  compareScene(test::builtinScene("atrium", "small"), {0, 61, 170}, 256, 143,
               ShadingModel::BlinnPhong, "atrium");
  Scene mr = makeBuiltinScene("atrium", "small", 1);
  applyVariants(mr, "metallic-roughness", 1);
  compareScene(mr, {30}, 200, 120, ShadingModel::MetallicRoughness, "atrium metallic-roughness");
}

// Cameras anywhere inside the scenes, looking anywhere: triangles cut by the near plane.
TEST(GlRaster, RandomCamerasThroughTheNearPlaneMatchSoftware) {
  REQUIRE_GL();
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (const char* name : {"street", "atrium"}) {
    Scene scene = makeBuiltinScene(name, name == std::string("street") ? "few" : "small", 1);
    const Bounds b = scene.bounds();
    GlRasterizer gl(scene);
    for (int i = 0; i < 4; ++i) {
      // One draw per statement: the order of a call's arguments is the compiler's choice (g++
      // and clang differ), and the cameras must not depend on it.
      float r[7];
      for (float& v : r) v = u(rng);
      const glm::vec3 eye = b.min + glm::vec3(r[0], 0.02f + 0.4f * r[1], r[2]) * b.extent();
      const glm::vec3 dir(r[3] - 0.5f, 0.4f * (r[4] - 0.5f), r[5] - 0.5f);
      const SceneCamera cam =
          SceneCamera::lookAt(eye, eye + dir, {0, 1, 0}, 0.6f + 1.2f * r[6], 0.05f, 500.0f);
      compareFrame(scene, gl, cam, 160, 96, ShadingModel::BlinnPhong,
                   std::string(name) + " random camera " + std::to_string(i));
    }
  }
}

std::string findGltf(const std::string& relative) {
  const std::string dir = test::sharedScene(relative);
  if (dir.empty()) return "";
  if (!std::filesystem::is_directory(dir)) return dir;
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir))
    if (e.path().extension() == ".gltf" || e.path().extension() == ".glb") return e.path().string();
  return "";
}

TEST(GlRaster, CrytekSponzaMatchesSoftware) {
  REQUIRE_GL();
  const std::string path = findGltf("sponza-crytek");
  if (path.empty()) GTEST_SKIP() << "../shared/scenes/sponza-crytek absent";
  const Scene scene = loadGltf(path);
  compareScene(scene, {0, int(scene.cameraPath.size() / 2)}, 240, 135, nativeShadingModel(scene),
               "sponza");
}

TEST(GlRaster, TexturedDungeonMatchesSoftware) {
  REQUIRE_GL();
  const std::string path = findGltf("dungeon");
  if (path.empty()) GTEST_SKIP() << "../shared/scenes/dungeon absent";
  const Scene scene = loadGltf(path);
  ASSERT_FALSE(scene.textures.empty());
  compareScene(scene, {0, int(scene.cameraPath.size() / 3)}, 240, 135, ShadingModel::BlinnPhong,
               "dungeon blinn-phong");
  compareScene(scene, {0}, 200, 113, ShadingModel::MetallicRoughness, "dungeon metallic-roughness");
}

TEST(GlRaster, NormalMappedQuadsMatchSoftware) {
  REQUIRE_GL();
  const std::string uri = test::uniformPngUri(2, 2, {128, 128, 255});
  if (uri.empty()) GTEST_SKIP() << "built without OpenImageIO";
  // The builder's quad, generated tangents, its normal map replaced by random texels (bilinear),
  // seen from its camera and from a grazing one, then with the file's tangents (w = -1).
  for (bool fileTangents : {false, true}) {
    std::vector<float> tangents;
    if (fileTangents)
      for (int k = 0; k < 4; ++k) tangents.insert(tangents.end(), {0, 0, 1, -1});
    const std::string text = test::normalMappedQuad(uri, 0.8, true, tangents).dump();
    std::vector<std::string> warnings;
    Scene scene = loadGltfFromMemory(reinterpret_cast<const unsigned char*>(text.data()),
                                     text.size(), "/nonexistent", "normals.gltf", &warnings);
    Texture& map = scene.textures[size_t(scene.materials[0].normalTexture)];
    map = randomTexture(8, 8, 18);
    for (glm::vec4& t : map.texels) t.z = 0.6f + 0.4f * t.z;  // facing out, as real maps do
    GlRasterizer gl(scene);
    const std::string label = fileTangents ? "normal-mapped quad, file tangents"
                                           : "normal-mapped quad, generated tangents";
    compareFrame(scene, gl, scene.camera(0), 96, 80, ShadingModel::MetallicRoughness, label);
    const SceneCamera grazing =
        SceneCamera::lookAt({1.6, 0.5, -0.4}, {0.5, 0.0, 0.5}, {0, 1, 0}, 0.9f, 0.05f, 50.0f);
    compareFrame(scene, gl, grazing, 96, 80, ShadingModel::MetallicRoughness, label + " grazing");
    // The map is applied: the normals differ from the plain ones.
    RasterOptions plain;
    plain.model = ShadingModel::MetallicRoughness;
    plain.normalMaps = false;
    RasterOptions mapped = plain;
    mapped.normalMaps = true;
    EXPECT_NE(gl.rasterize(scene.camera(0), 32, 32, plain).normal,
              gl.rasterize(scene.camera(0), 32, 32, mapped).normal);
  }
}

// alphaMode MASK (issue #17): a quad at depth 2 whose texture (NEAREST) has alpha 0.2 in its
// left half and 1 in its right half, before a wall at depth 5. Both rasterizers leave its left
// half out through the one test of material_planes.h (ts_material_covered): the G-buffers agree
// within their bounds, every pixel has the same winner (the alpha boundary lies half a pixel from
// any pixel centre), the wall shows through the left half, and so it does in the depth pre-pass.
TEST(GlRaster, AlphaMaskLeavesTheSameFragmentsOutAsSoftware) {
  REQUIRE_GL();
  const int W = 64, H = 32;
  const SceneCamera cam = lookingDownZ();
  const CameraIntrinsics in = CameraIntrinsics::from(cam, W, H);
  Scene s;
  s.name = "alpha mask";
  Material wall, leaf;
  wall.diffuse = {0.2f, 0.3f, 0.4f};
  leaf.diffuse = leaf.baseColor = {0.9f, 0.8f, 0.7f};
  leaf.alphaMode = AlphaMode::Mask;
  leaf.diffuseTexture = leaf.baseColorTexture = 0;
  s.materials = {wall, leaf};
  s.textures.push_back(ts::test::halfCutOutTexture());
  auto at = [&](double x, double y, double d) { return unproject(in, x, y, d); };
  const glm::vec3 n(0.0f, 0.0f, 1.0f);
  addTriangle(s, at(0, 0, 5), at(0, H, 5), at(W, 0, 5), 0, n);
  addTriangle(s, at(W, 0, 5), at(0, H, 5), at(W, H, 5), 0, n);
  // Pixels x 8..55, y 4..27; u runs 0..1 along x (the alpha boundary at x = 32).
  const uint32_t base = uint32_t(s.vertices.size());
  for (auto [x, y] : {std::pair{8.0, 4.0}, {8.0, 28.0}, {56.0, 4.0}, {56.0, 28.0}})
    s.vertices.push_back(Vertex{at(x, y, 2), n, glm::vec2(float((x - 8.0) / 48.0), 0.5f)});
  s.indices.insert(s.indices.end(), {base, base + 1, base + 2, base + 2, base + 1, base + 3});
  s.triangleMaterial.insert(s.triangleMaterial.end(), {1u, 1u});
  GlRasterizer gl(s);
  for (ShadingModel model : {ShadingModel::BlinnPhong, ShadingModel::MetallicRoughness}) {
    SCOPED_TRACE(toString(model));
    const FrameFigures f = compareFrame(s, gl, cam, W, H, model, "alpha mask");
    EXPECT_EQ(f.c.bothCovered, uint64_t(W * H)) << f.c.summary();
    RasterOptions o;
    o.model = model;
    o.triangleIds = true;
    const GBuffer soft = rasterize(s, cam, W, H, o), hard = gl.rasterize(cam, W, H, o);
    int front[2] = {0, 0};  // left, right half of the quad's pixels showing the quad
    for (int y = 4; y < 28; ++y)
      for (int x = 8; x < 56; ++x) {
        const size_t i = size_t(y) * W + size_t(x);
        ASSERT_EQ(soft.triangleId[i], hard.triangleId[i]) << x << "," << y;
        front[x < 32 ? 0 : 1] += soft.triangleId[i] >= 2 ? 1 : 0;
      }
    EXPECT_EQ(front[0], 0);
    EXPECT_EQ(front[1], 24 * 24);
  }
  // The depth pre-pass of tiled-forward-prez leaves the same fragments out.
  double ms = 0.0;
  const std::vector<float> depth = gl.depthPrepass(cam, W, H, 1, ms);
  for (int x : {8, 20, 31, 32, 44, 55})
    EXPECT_NEAR(depth[size_t(16) * W + size_t(x)], x < 32 ? 5.0f : 2.0f, 1e-4f) << "x " << x;
  // BLEND is refused by this rasterizer as by the software one, naming the material.
  s.materials[1].alphaMode = AlphaMode::Blend;
  s.materials[1].name = "glass";
  try {
    GlRasterizer refused(s);
    ADD_FAILURE() << "a BLEND material was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("material 'glass' is alphaMode BLEND"), std::string::npos)
        << e.what();
  }
}

// ---- Shading the OpenGL G-buffer ---------------------------------------------------------------

TEST(GlRaster, ImagesFromTheOpenGLGBufferPassTheReferenceChecks) {
  REQUIRE_GL();
  const Scene& scene = test::builtinScene("street", "many");
  SceneRasterizer gl(scene, RasterBackend::Gl);
  for (GBufferFormat format : {GBufferFormat::FP32, GBufferFormat::PACKED}) {
    const PreparedFrame f =
        prepareFrame(gl, 90, 160, 96, format, analyzeScene(scene, ShadingModel::BlinnPhong));
    ASSERT_EQ(f.raster, RasterBackend::Gl);
    const ReferenceImage ref = shadeReference(f.encoded, f.intrinsics, f.lights, f.ambient, 0);
    TechniqueConfig config;
    config.format = format;
    for (const auto& name : gbufferTechniqueNames()) {
      test::Checked c = test::renderAndCheck(f, test::cachedTechnique(name, config), ref);
      EXPECT_EQ(c.missed, 0u) << name << " " << toString(format);
      EXPECT_LE(c.error.maxRelPeak, test::kFp32RelativeTolerance)
          << name << " " << toString(format);
    }
  }
}

TEST(GlRaster, ContextNamesItsRendererAndFailsClearlyWhenAskedForTheImpossible) {
  REQUIRE_GL();
  const EglContext& c = EglContext::shared();
  EXPECT_FALSE(c.renderer().empty());
  EXPECT_TRUE(c.platform() == "device" || c.platform() == "surfaceless") << c.platform();
  std::cout << "OpenGL: " << c.renderer() << ", " << c.version() << " via " << c.platform()
            << ", context in " << c.createMs() << " ms\n";
  EXPECT_EQ(toString(parseRasterBackend("gl")), "gl");
  EXPECT_THROW(parseRasterBackend("vulkan"), Error);
}

}  // namespace
}  // namespace ts
