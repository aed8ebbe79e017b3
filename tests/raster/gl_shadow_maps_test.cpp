// The shadow maps drawn by OpenGL (GlRasterizer::drawShadowAtlas, `--raster gl`) against the
// software ones (drawShadowAtlas) of the same layout, as tests/raster/gl_raster_test.cpp checks
// the G-buffers: compareShadowAtlases (src/raster/shadow_map_compare.h) with the bound derived in
// docs/shadows.md. Depths agree within the bound on texels both cover, coverage differs only on
// silhouettes (and by at most what edges moved by 1/128 texel flip), another surface wins only on
// an edge between two (slivers one texel thin are counted apart), unused texels hold 0 in both;
// point, spot and directional lights, a MASK cut-out, the atrium's thesis-big-shadows and the
// street. Skips where no OpenGL context can be made; the figures are printed and recorded as test
// properties.
#include <gtest/gtest.h>

#include <iostream>
#include <string>
#include <vector>

#include "raster/gl_rasterizer.h"
#include "raster/raster_backend.h"
#include "raster/shadow_map_compare.h"
#include "raster/shadow_maps.h"
#include "require_gl.h"
#include "scene/mesh_builder.h"
#include "scene/scene_loader.h"
#include "scene/shadow_casters.h"
#include "test_scenes.h"

namespace ts {
namespace {

constexpr float kFloor = 10.0f;  // the floor spans [-kFloor, kFloor] in x and z

SceneCamera camera() {
  return SceneCamera::lookAt({0.0, 3.0, 12.0}, {0.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, 1.0f, 0.1f,
                             100.0f);
}

// A floor at y = 0, a box standing on it and a thin slab floating over it (its silhouettes
// against the floor: texels where another surface wins).
Scene floorBoxAndSlab() {
  Scene s;
  s.name = "floor-box-slab";
  MeshBuilder b(s);
  const uint32_t m = b.addMaterial(Material{});
  test::addFloor(b, kFloor, m);
  b.box({-1.0f, 0.0f, -1.0f}, {1.0f, 1.0f, 1.0f}, m, false);
  b.box({1.5f, 1.5f, -2.0f}, {3.5f, 1.6f, 0.5f}, m, false);
  s.cameraPath.push_back(camera());
  return s;
}

// A floor and a quad at y = 2 over it whose texture (2x1, NEAREST) has alpha 0.2 where x < 0 and
// 1 where x > 0 (as tests/raster/shadow_maps_test.cpp's leaf).
Scene floorAndLeaf(AlphaMode mode) {
  Scene s;
  s.name = "floor-and-leaf";
  MeshBuilder b(s);
  const uint32_t floor = b.addMaterial(Material{});
  Material leaf;
  leaf.alphaMode = mode;
  leaf.diffuseTexture = leaf.baseColorTexture = 0;
  const uint32_t m = b.addMaterial(leaf);
  s.textures.push_back(test::halfCutOutTexture());
  test::addFloor(b, kFloor, floor);
  b.quad({-2.0f, 2.0f, 2.0f}, {2.0f, 2.0f, 2.0f}, {2.0f, 2.0f, -2.0f}, {-2.0f, 2.0f, -2.0f}, m);
  s.cameraPath.push_back(camera());
  return s;
}

struct Both {
  ShadowAtlas soft, gl;
  ShadowAtlasComparison c;
};

// The scene's shadow-casting lights' atlas (mapSize per point/spot face) drawn by both.
Both drawBoth(const Scene& scene, int mapSize) {
  ShadowAtlasOptions o;
  o.mapSize = mapSize;
  const ShadowAtlasLayout layout =
      planShadowAtlas(scene.lights, scene.bounds(), scene.camera(0), o);
  GlRasterizer gl(scene);
  Both b{drawShadowAtlas(scene, layout, 2), gl.drawShadowAtlas(layout), {}};
  b.c = compareShadowAtlases(b.soft, b.gl, scene);
  return b;
}

std::vector<SceneLight> casting(std::vector<SceneLight> lights) {
  for (SceneLight& l : lights) l.castsShadow = true;
  return lights;
}

// The agreement every pair of maps must show; minCovered keeps the check from passing on maps
// that see nothing.
void expectAgreement(const Both& b, const std::string& label, uint64_t minCovered) {
  const ShadowAtlasComparison& c = b.c;
  std::cout << "[gl shadow maps] " << label << ": " << c.summary() << "\n";
  ::testing::Test::RecordProperty(label, c.summary());
  EXPECT_EQ(b.soft.rasterizer, "software");
  EXPECT_EQ(b.gl.rasterizer, "gl");
  EXPECT_TRUE(b.soft.faceTriangles == b.gl.faceTriangles) << label << ": the same culling";
  EXPECT_GE(c.bothCovered, minCovered) << label;
  EXPECT_EQ(c.mismatchesOffSilhouette, 0u) << label << ": " << c.summary();
  EXPECT_EQ(c.depthDiffersOffEdge, 0u) << label << ": " << c.summary();
  // Slivers one texel thin (their slope across the texel unseen) are reported, not bounded.
  ::testing::Test::RecordProperty(label + " thin", std::to_string(c.thinDiffers));
  EXPECT_LE(c.worstRatio, 1.0) << label << ": " << c.summary();
  EXPECT_EQ(c.unusedNonZero, 0u) << label;
  // An edge moved by kShadowSnapMove flips at most the texel centres that near it (docs/opengl.md).
  const double faces = double(b.soft.layout.faces.size());
  EXPECT_LE(double(c.onlyA + c.onlyB), 2.0 * kShadowSnapMove * double(c.silhouetteA) + 4.0 * faces)
      << label << ": " << c.summary();
}

TEST(GlShadowMaps, TheSoftwareBackendDrawsTheSameAtlasAsBefore) {
  // --raster software goes through SceneRasterizer: the same atlas, bit for bit.
  Scene scene = floorBoxAndSlab();
  scene.lights = casting(
      {SceneLight::point({0.5, 3.0, 0.25}, glm::vec3(1), 20),
       SceneLight::directional(glm::normalize(glm::vec3(0.3f, -1.0f, 0.2f)), glm::vec3(1))});
  ShadowAtlasOptions o;
  o.mapSize = 32;
  const ShadowAtlasLayout layout =
      planShadowAtlas(scene.lights, scene.bounds(), scene.camera(0), o);
  SceneRasterizer software(scene, RasterBackend::Software);
  const ShadowAtlas through = software.drawShadowAtlas(layout);
  EXPECT_TRUE(through.depth == drawShadowAtlas(scene, layout).depth);
  EXPECT_EQ(through.rasterizer, "software");
  EXPECT_EQ(through.readMs, 0.0);
}

TEST(GlShadowMaps, PointSpotAndDirectionalMapsMatchSoftware) {
  REQUIRE_GL();
  Scene scene = floorBoxAndSlab();
  scene.lights = casting(
      {SceneLight::point({0.5, 3.0, 0.25}, glm::vec3(1), 20),
       SceneLight::spot({2.0, 4.0, 0.5}, glm::normalize(glm::vec3(-0.2f, -1.0f, 0.1f)),
                        glm::vec3(1), 20, 0.4f, 0.7f),
       SceneLight::directional(glm::normalize(glm::vec3(0.3f, -1.0f, 0.2f)), glm::vec3(1)),
       // Under the floor looking down: a face that sees nothing, far in both.
       SceneLight::spot({0.0, -2.0, 0.0}, {0.0f, -1.0f, 0.0f}, glm::vec3(1), 5, 0.3f, 0.6f)});
  for (int size : {32, 128}) {
    const Both b = drawBoth(scene, size);
    ASSERT_EQ(b.soft.layout.faces.size(), 9u);
    expectAgreement(b, "floor, box, slab at " + std::to_string(size), uint64_t(size) * size);
    EXPECT_GT(b.c.silhouetteA, 0u);
    EXPECT_GT(b.c.texels, b.c.bothCovered);  // some texels see nothing
    const ShadowFace& under = b.gl.layout.faces.back();
    ASSERT_EQ(under.light, 3u);
    EXPECT_EQ(b.gl.faceTriangles.back(), 0u);
    for (int y = 0; y < under.size; ++y)
      for (int x = 0; x < under.size; ++x)
        ASSERT_EQ(b.gl.at(under.x + x, under.y + y), float(under.view.zfar));
  }
}

TEST(GlShadowMaps, MaskCutOutCastsNoShadowAsInSoftware) {
  REQUIRE_GL();
  const std::vector<SceneLight> lights = casting(
      {SceneLight::spot({0.3, 5.0, 0.2}, {0.0f, -1.0f, 0.0f}, glm::vec3(1), 20, 0.5f, 0.8f),
       SceneLight::directional(glm::normalize(glm::vec3(0.3f, -1.0f, 0.2f)), glm::vec3(1))});
  Scene masked = floorAndLeaf(AlphaMode::Mask), opaque = floorAndLeaf(AlphaMode::Opaque);
  masked.lights = opaque.lights = lights;
  const Both m = drawBoth(masked, 64), o = drawBoth(opaque, 64);
  expectAgreement(m, "MASK leaf", 4000);
  expectAgreement(o, "OPAQUE leaf", 4000);
  // The cut-out half shows the floor in OpenGL's masked maps: many texels deeper than the opaque
  // leaf's.
  size_t deeper = 0;
  for (size_t i = 0; i < m.gl.depth.size(); ++i) deeper += m.gl.depth[i] > o.gl.depth[i] * 1.01f;
  EXPECT_GT(deeper, 200u);
}

TEST(GlShadowMaps, AtriumAndStreetMapsMatchSoftware) {
  REQUIRE_GL();
  SceneOptions atriumOptions;
  atriumOptions.lightSet = "thesis-big-shadows";
  const Scene atrium = loadScene("builtin:atrium", atriumOptions);
  ASSERT_GT(shadowCasterCount(atrium.lights), 0u);
  expectAgreement(drawBoth(atrium, 32), "atrium thesis-big-shadows at 32", 10000);
  SceneOptions streetOptions;
  streetOptions.shadows = "6";
  const Scene street = loadScene("builtin:street", streetOptions);
  ASSERT_EQ(shadowCasterCount(street.lights), 6u);
  expectAgreement(drawBoth(street, 64), "street, 6 casting lights at 64", 10000);
}

}  // namespace
}  // namespace ts
