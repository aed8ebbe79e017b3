// The shadow-map atlas's plan (src/raster/shadow_atlas.cpp): faces per light type, sizes by
// importance within the budget, packing without overlaps, the notes and the errors.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "raster/shadow_atlas.h"
#include "util/error.h"

namespace {

using ts::Bounds;
using ts::SceneCamera;
using ts::SceneLight;
using ts::SceneLightType;
using ts::ShadowAtlasLayout;
using ts::ShadowAtlasOptions;

Bounds unitScene() {
  Bounds b;
  b.extend({-10.0f, 0.0f, -10.0f});
  b.extend({10.0f, 5.0f, 10.0f});
  return b;
}

SceneCamera camera() {
  return SceneCamera::lookAt({0.0, 2.0, 20.0}, {0.0, 2.0, 0.0}, {0.0, 1.0, 0.0}, 1.0f, 0.1f,
                             100.0f);
}

// Point lights along -Z away from the camera: the farther, the less important.
std::vector<SceneLight> row(int n, bool casts = true) {
  std::vector<SceneLight> lights;
  for (int i = 0; i < n; ++i) {
    lights.push_back(SceneLight::point({0.0, 2.0, 10.0 - 2.0 * i}, glm::vec3(1.0f), 3.0f));
    lights.back().castsShadow = casts;
  }
  return lights;
}

std::vector<SceneLight> mixed() {
  std::vector<SceneLight> lights = row(2);
  lights.push_back(
      SceneLight::spot({0.0, 4.0, 0.0}, {0.0f, -1.0f, 0.0f}, glm::vec3(1.0f), 8.0f, 0.2f, 0.5f));
  lights.push_back(
      SceneLight::directional(glm::normalize(glm::vec3(0.3f, -1.0f, 0.2f)), glm::vec3(1.0f)));
  for (SceneLight& l : lights) l.castsShadow = true;
  return lights;
}

uint64_t faceArea(const ShadowAtlasLayout& a) {
  uint64_t area = 0;
  for (const auto& f : a.faces) area += uint64_t(f.size) * uint64_t(f.size);
  return area;
}

// Every face inside the atlas, none overlapping another (an occupancy map of the atlas).
void expectPacked(const ShadowAtlasLayout& a) {
  ASSERT_GT(a.width, 0);
  ASSERT_GT(a.height, 0);
  EXPECT_TRUE(a.width == a.height || a.width == 2 * a.height) << a.width << "x" << a.height;
  const uint64_t texels = uint64_t(a.width) * uint64_t(a.height);
  EXPECT_EQ(texels & (texels - 1), 0u);
  EXPECT_GE(texels, faceArea(a));
  EXPECT_LT(texels, 2 * faceArea(a));  // no more than the power of two rounding wastes
  std::vector<uint8_t> used(texels, 0);
  size_t overlaps = 0, outside = 0;
  for (const auto& f : a.faces) {
    if (f.x < 0 || f.y < 0 || f.x + f.size > a.width || f.y + f.size > a.height) {
      ++outside;
      continue;
    }
    for (int y = f.y; y < f.y + f.size; ++y)
      for (int x = f.x; x < f.x + f.size; ++x) {
        uint8_t& u = used[size_t(y) * size_t(a.width) + size_t(x)];
        overlaps += u;
        u = 1;
      }
  }
  EXPECT_EQ(outside, 0u);
  EXPECT_EQ(overlaps, 0u);
}

TEST(ShadowAtlas, FacesAndSizesPerLightType) {
  ShadowAtlasOptions o;
  o.mapSize = 256;
  o.budgetMB = 4096;
  const ShadowAtlasLayout a = planShadowAtlas(mixed(), unitScene(), camera(), o);
  ASSERT_EQ(a.lights.size(), 4u);
  EXPECT_EQ(a.lights[0].faces, 6);
  EXPECT_EQ(a.lights[2].faces, 1);
  EXPECT_EQ(a.lights[3].faces, 1);
  ASSERT_EQ(a.faces.size(), 14u);
  for (const auto& m : a.lights) {
    EXPECT_EQ(m.size, m.requestedSize);
    EXPECT_EQ(m.size, m.type == SceneLightType::Directional ? 4 * o.mapSize : o.mapSize);
  }
  for (const auto& f : a.faces) EXPECT_EQ(f.size, a.lights[f.light].size);
  EXPECT_TRUE(a.notes.empty());
  EXPECT_EQ(a.bytes(), uint64_t(a.width) * uint64_t(a.height) * 4u);
  expectPacked(a);
}

TEST(ShadowAtlas, OnlyShadowCastersGetMaps) {
  std::vector<SceneLight> lights = row(5, false);
  lights[3].castsShadow = true;
  const ShadowAtlasLayout a = planShadowAtlas(lights, unitScene(), camera(), {});
  ASSERT_EQ(a.lights.size(), 1u);
  EXPECT_EQ(a.lights[0].light, 3u);
  for (const auto& f : a.faces) EXPECT_EQ(f.light, 3u);
  const ShadowAtlasLayout none = planShadowAtlas(row(5, false), unitScene(), camera(), {});
  EXPECT_TRUE(none.faces.empty());
  EXPECT_EQ(none.bytes(), 0u);
}

// Each cube face looks along its axis (OpenGL's order), and together they see every direction.
TEST(ShadowAtlas, CubeFacesCoverEveryDirection) {
  const ShadowAtlasLayout a = planShadowAtlas(row(1), unitScene(), camera(), {});
  ASSERT_EQ(a.faces.size(), 6u);
  const glm::dvec3 p(0.0, 2.0, 10.0);
  const glm::dvec3 axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (int k = 0; k < 6; ++k) {
    EXPECT_EQ(a.faces[size_t(k)].face, k);
    const glm::dvec4 c = a.faces[size_t(k)].mapFromWorld * glm::dvec4(p + axes[k], 1.0);
    EXPECT_NEAR(c.x / c.w, 0.0, 1e-12) << k;
    EXPECT_NEAR(c.y / c.w, 0.0, 1e-12) << k;
    EXPECT_NEAR(c.w, 1.0, 1e-12) << k;  // linear depth along the axis
  }
  int uncovered = 0;
  for (int i = 0; i < 2000; ++i) {
    // A spiral of directions over the sphere.
    const double z = 1.0 - (i + 0.5) / 1000.0, r = std::sqrt(1.0 - z * z), phi = 2.39996 * i;
    const glm::dvec3 d(r * std::cos(phi), r * std::sin(phi), z);
    bool seen = false;
    for (const auto& f : a.faces) {
      const glm::dvec4 c = f.mapFromWorld * glm::dvec4(p + d, 1.0);
      seen = seen || (c.w > 0.0 && std::abs(c.x) <= c.w && std::abs(c.y) <= c.w);
    }
    uncovered += !seen;
  }
  EXPECT_EQ(uncovered, 0);
}

TEST(ShadowAtlas, DirectionalMapCoversTheScene) {
  const Bounds b = unitScene();
  const ShadowAtlasLayout a = planShadowAtlas(mixed(), b, camera(), {});
  const auto& f = a.faces.back();
  ASSERT_TRUE(f.view.orthographic);
  for (int c = 0; c < 8; ++c) {
    const glm::dvec3 corner(c & 1 ? b.max.x : b.min.x, c & 2 ? b.max.y : b.min.y,
                            c & 4 ? b.max.z : b.min.z);
    const glm::dvec4 ndc = f.mapFromWorld * glm::dvec4(corner, 1.0);
    EXPECT_LT(std::abs(ndc.x), 1.0) << c;
    EXPECT_LT(std::abs(ndc.y), 1.0) << c;
    EXPECT_LT(std::abs(ndc.z), 1.0) << c;
  }
}

// Fitted to the view's geometry across the light (finer texels), to the scene along it (every
// caster between the light and the receivers within the depth range).
TEST(ShadowAtlas, DirectionalMapFitsTheReceiversAcrossAndTheSceneAlong) {
  const Bounds scene = unitScene();
  Bounds receivers;
  receivers.extend({2.0f, 0.0f, 1.0f});
  receivers.extend({5.0f, 1.0f, 3.0f});
  const ShadowAtlasLayout whole = planShadowAtlas(mixed(), scene, camera(), {});
  const ShadowAtlasLayout fitted = planShadowAtlas(mixed(), scene, camera(), {}, receivers);
  const auto& f = fitted.faces.back();
  ASSERT_TRUE(f.view.orthographic);
  EXPECT_LT(f.view.halfX, whole.faces.back().view.halfX / 2.0);
  for (int c = 0; c < 8; ++c) {
    const glm::dvec3 r(c & 1 ? receivers.max.x : receivers.min.x,
                       c & 2 ? receivers.max.y : receivers.min.y,
                       c & 4 ? receivers.max.z : receivers.min.z);
    const glm::dvec4 rn = f.mapFromWorld * glm::dvec4(r, 1.0);
    EXPECT_LT(std::abs(rn.x), 1.0) << c;
    EXPECT_LT(std::abs(rn.y), 1.0) << c;
    const glm::dvec3 s(c & 1 ? scene.max.x : scene.min.x, c & 2 ? scene.max.y : scene.min.y,
                       c & 4 ? scene.max.z : scene.min.z);
    EXPECT_LT(std::abs((f.mapFromWorld * glm::dvec4(s, 1.0)).z), 1.0) << c;
  }
}

TEST(ShadowAtlas, DirectionalWithoutGeometryIsAnError) {
  std::vector<SceneLight> lights = {SceneLight::directional({0.0f, -1.0f, 0.0f}, glm::vec3(1.0f))};
  lights[0].castsShadow = true;
  try {
    planShadowAtlas(lights, Bounds{}, camera(), {});
    FAIL() << "no error";
  } catch (const ts::Error& e) {
    EXPECT_NE(std::string(e.what()).find("no geometry"), std::string::npos) << e.what();
  }
}

TEST(ShadowAtlas, WideSpotConeIsClampedWithANote) {
  std::vector<SceneLight> lights = {
      SceneLight::spot({0.0, 4.0, 0.0}, {0.0f, -1.0f, 0.0f}, glm::vec3(1.0f), 8.0f, 0.2f, 1.55f)};
  lights[0].castsShadow = true;
  const ShadowAtlasLayout a = planShadowAtlas(lights, unitScene(), camera(), {});
  ASSERT_EQ(a.faces.size(), 1u);
  EXPECT_NEAR(a.faces[0].view.halfX, std::tan(85.0 * 3.14159265358979 / 180.0), 1e-9);
  ASSERT_EQ(a.notes.size(), 1u);
  EXPECT_NE(a.notes[0].find("light 0 (spot)"), std::string::npos) << a.notes[0];
  // Within 170 degrees: the cone itself, no note.
  lights[0].outerConeAngle = 0.5f;
  const ShadowAtlasLayout b = planShadowAtlas(lights, unitScene(), camera(), {});
  EXPECT_NEAR(b.faces[0].view.halfX, std::tan(0.5), 1e-6);
  EXPECT_TRUE(b.notes.empty());
}

TEST(ShadowAtlas, BudgetShrinksTheLeastImportantFirstWithANote) {
  ShadowAtlasOptions o;
  o.mapSize = 512;
  o.budgetMB = 32;
  const std::vector<SceneLight> lights = row(8);
  const ShadowAtlasLayout full = planShadowAtlas(lights, unitScene(), camera(), {512, 4096});
  ASSERT_GT(full.bytes(), uint64_t(32) << 20);  // so the budget must bite
  const ShadowAtlasLayout a = planShadowAtlas(lights, unitScene(), camera(), o);
  EXPECT_LE(a.bytes(), uint64_t(32) << 20);
  expectPacked(a);
  size_t lost = 0;
  for (const auto& m : a.lights) lost += m.size < m.requestedSize;
  EXPECT_GT(lost, 0u);
  for (const auto& m : a.lights)
    for (const auto& n : a.lights)
      if (m.importance > n.importance) {
        EXPECT_GE(m.size, n.size) << m.light << " " << n.light;
      }
  // The nearest light is the most important: it keeps its size.
  EXPECT_EQ(a.lights[0].size, o.mapSize);
  ASSERT_EQ(a.notes.size(), 1u);
  EXPECT_NE(a.notes[0].find("lost resolution to --shadow-budget 32 MB"), std::string::npos)
      << a.notes[0];
  const auto& last = a.lights.back();
  EXPECT_NE(a.notes[0].find("light " + std::to_string(last.light) + " (point) 512 -> " +
                            std::to_string(last.size)),
            std::string::npos)
      << a.notes[0];
}

TEST(ShadowAtlas, BudgetTooSmallForTheSmallestMapsIsAnError) {
  ShadowAtlasOptions o;
  o.budgetMB = 0.01;
  try {
    planShadowAtlas(row(100), unitScene(), camera(), o);
    FAIL() << "no error";
  } catch (const ts::Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("--shadow-budget 0.01 MB"), std::string::npos) << m;
    EXPECT_NE(m.find("600 shadow-map face(s)"), std::string::npos) << m;
    EXPECT_NE(m.find("16x16"), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  }
}

// 10 000 shadow-casting point lights: 60 000 faces. Either a clear error or tiny maps, packed,
// within the budget, with one bounded note.
TEST(ShadowAtlas, TenThousandLightsDoNotExplode) {
  const std::vector<SceneLight> lights = row(10000);
  ShadowAtlasLayout a;
  try {
    a = planShadowAtlas(lights, unitScene(), camera(), {});
  } catch (const ts::Error& e) {
    EXPECT_NE(std::string(e.what()).find("--shadow-budget"), std::string::npos) << e.what();
    return;
  }
  EXPECT_EQ(a.faces.size(), 60000u);
  EXPECT_LE(a.bytes(), uint64_t(ts::kDefaultShadowBudgetMB) << 20);
  expectPacked(a);
  ASSERT_EQ(a.notes.size(), 1u);
  EXPECT_LT(a.notes[0].size(), 1000u);
  EXPECT_NE(a.notes[0].find("10000 of 10000"), std::string::npos) << a.notes[0].substr(0, 200);
}

TEST(ShadowAtlas, BadOptionsAreOneLineErrors) {
  for (int size : {0, 8, 100, 16384, -512}) {
    ShadowAtlasOptions o;
    o.mapSize = size;
    try {
      ts::checkShadowAtlasOptions(o);
      ADD_FAILURE() << size;
    } catch (const ts::Error& e) {
      EXPECT_NE(std::string(e.what()).find("--shadow-map-size"), std::string::npos) << e.what();
    }
  }
  for (double mb : {0.0, -1.0, std::nan(""), 1e9}) {
    ShadowAtlasOptions o;
    o.budgetMB = mb;
    try {
      ts::checkShadowAtlasOptions(o);
      ADD_FAILURE() << mb;
    } catch (const ts::Error& e) {
      EXPECT_NE(std::string(e.what()).find("--shadow-budget"), std::string::npos) << e.what();
    }
  }
  ShadowAtlasOptions ok;
  ok.mapSize = 16;
  ok.budgetMB = 0.5;
  EXPECT_NO_THROW(ts::checkShadowAtlasOptions(ok));
}

}  // namespace
