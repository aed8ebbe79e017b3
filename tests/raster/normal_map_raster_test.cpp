// Normal maps in the software rasterizer's G-buffer (shaders/normal_mapping.h through
// resolve()): a flat map or scale 0 gives the interpolated normal bit for bit, a tilted map the
// normal of glTF's tangent frame computed here analytically, `--normal-maps off` and
// RasterOptions::normalMaps = false the plain normals. The OpenGL rasterizer against this one:
// tests/raster/gl_raster_test.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "gltf_builder.h"
#include "png_bytes.h"
#include "raster/rasterizer.h"
#include "scene/scene_loader.h"

namespace ts {
namespace {

constexpr int kSize = 32;

Scene quad(const std::vector<unsigned char>& rgb, double scale,
           const std::vector<float>& tangents = {}) {
  const std::string uri = test::uniformPngUri(2, 2, rgb);
  if (uri.empty()) return Scene{};
  const std::string text = test::normalMappedQuad(uri, scale, true, tangents).dump();
  std::vector<std::string> warnings;
  return loadGltfFromMemory(reinterpret_cast<const unsigned char*>(text.data()), text.size(),
                            "/nonexistent", "normals.gltf", &warnings);
}

GBuffer draw(const Scene& s, bool normalMaps = true) {
  RasterOptions o;
  o.model = ShadingModel::MetallicRoughness;
  o.normalMaps = normalMaps;
  return rasterize(s, s.camera(0), kSize, kSize, o);
}

// Covered pixels, each compared by `check(mapped, plain)`; at least half the frame is the quad.
template <typename Check>
void forCoveredPixels(const GBuffer& mapped, const GBuffer& plain, Check check) {
  size_t covered = 0;
  for (size_t i = 0; i < mapped.pixelCount(); ++i) {
    if (!(mapped.depth[i] > 0.0f)) continue;
    ++covered;
    check(glm::vec3(mapped.normal[i]), glm::vec3(plain.normal[i]));
  }
  EXPECT_GT(covered, mapped.pixelCount() / 2);
}

// glTF's tangent-space normal (2 rgb - 1) (s, s, 1) in the frame (T, cross(N, T) w, N), world
// space, normalised, then in view space.
glm::dvec3 analytic(const Scene& s, const std::vector<unsigned char>& rgb, double scale,
                    glm::dvec3 T, double w) {
  const glm::dvec3 N(0, 1, 0);
  const glm::dvec3 tn((2.0 * rgb[0] / 255.0 - 1.0) * scale, (2.0 * rgb[1] / 255.0 - 1.0) * scale,
                      2.0 * rgb[2] / 255.0 - 1.0);
  const glm::dvec3 world = glm::normalize(tn.x * T + tn.y * glm::cross(N, T) * w + tn.z * N);
  return glm::normalize(glm::dmat3(s.camera(0).viewFromWorld) * world);
}

double angle(glm::dvec3 a, glm::dvec3 b) {
  return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

#define REQUIRE_SCENE(s) \
  if ((s).vertices.empty()) GTEST_SKIP() << "built without OpenImageIO"

TEST(NormalMapRaster, AFlatMapGivesExactlyTheInterpolatedNormal) {
  // 8-bit PNGs cannot hold 0.5 (128 is 0.502): the flat map's texels are set to it exactly.
  Scene s = quad({128, 128, 255}, 1.0);
  REQUIRE_SCENE(s);
  for (glm::vec4& t : s.textures[size_t(s.materials[0].normalTexture)].texels)
    t = glm::vec4(0.5f, 0.5f, 1.0f, 1.0f);
  forCoveredPixels(draw(s), draw(s, false), [](glm::vec3 mapped, glm::vec3 plain) {
    EXPECT_EQ(mapped, plain);  // bit for bit
  });
}

TEST(NormalMapRaster, ScaleZeroGivesExactlyTheInterpolatedNormal) {
  Scene s = quad({230, 64, 220}, 0.0);
  REQUIRE_SCENE(s);
  forCoveredPixels(draw(s), draw(s, false),
                   [](glm::vec3 mapped, glm::vec3 plain) { EXPECT_EQ(mapped, plain); });
}

TEST(NormalMapRaster, ATiltedMapGivesTheAnalyticNormal) {
  for (double scale : {1.0, 0.5, -2.0}) {
    const std::vector<unsigned char> rgb = {230, 64, 220};
    Scene s = quad(rgb, scale);
    REQUIRE_SCENE(s);
    const glm::dvec3 expected = analytic(s, rgb, scale, {1, 0, 0}, 1.0);
    const glm::dvec3 plainExpected = glm::dmat3(s.camera(0).viewFromWorld) * glm::dvec3(0, 1, 0);
    ASSERT_GT(angle(expected, plainExpected), 0.3) << "the map tilts the normal visibly";
    forCoveredPixels(draw(s), draw(s, false), [&](glm::vec3 mapped, glm::vec3) {
      EXPECT_LT(angle(glm::dvec3(mapped), expected), 1e-5) << "scale " << scale;
    });
  }
}

TEST(NormalMapRaster, TheFilesTangentsAndTheirSignOrientTheMap) {
  // T = +z, w = -1: the bitangent is cross(+y, +z) (-1) = -x; the green tilt turns towards it.
  const std::vector<unsigned char> rgb = {128, 220, 230};
  std::vector<float> tangents;
  for (int k = 0; k < 4; ++k) tangents.insert(tangents.end(), {0, 0, 1, -1});
  Scene s = quad(rgb, 1.0, tangents);
  REQUIRE_SCENE(s);
  const glm::dvec3 expected = analytic(s, rgb, 1.0, {0, 0, 1}, -1.0);
  forCoveredPixels(draw(s), draw(s, false), [&](glm::vec3 mapped, glm::vec3) {
    EXPECT_LT(angle(glm::dvec3(mapped), expected), 1e-5);
  });
}

TEST(NormalMapRaster, NormalMapsOffGivesThePlainNormals) {
  const std::string uri = test::uniformPngUri(2, 2, {230, 64, 220});
  if (uri.empty()) GTEST_SKIP() << "built without OpenImageIO";
  const std::string path =
      (std::filesystem::temp_directory_path() / "tileshade_normal_maps_off.gltf").string();
  std::ofstream(path) << test::normalMappedQuad(uri, 1.0).dump();
  SceneOptions off;
  off.normalMaps = false;
  const Scene plain = loadScene(path, off), mapped = loadScene(path, SceneOptions{});
  std::filesystem::remove(path);
  EXPECT_TRUE(plain.tangents.empty());
  EXPECT_EQ(plain.materials[0].normalTexture, -1);
  const GBuffer a = draw(plain), b = draw(mapped, false), c = draw(mapped);
  EXPECT_EQ(a.normal, b.normal);
  EXPECT_NE(a.normal, c.normal);
}

}  // namespace
}  // namespace ts
