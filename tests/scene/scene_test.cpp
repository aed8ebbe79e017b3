// Built-in scenes and the scene-spec/options layer (src/scene/scene_loader.cpp, builtin_*.cpp).
#include <cmath>
#include <cstring>
#include <set>

#include <gtest/gtest.h>

#include "scene/scene_loader.h"
#include "util/error.h"
#include "util/pi.h"

namespace {

using ts::Scene;
using ts::SceneOptions;

using ts::kPi;

// Every built-in must be a well-formed scene.
void expectWellFormed(const Scene& s) {
  ASSERT_EQ(s.indices.size() % 3, 0u);
  ASSERT_EQ(s.triangleMaterial.size(), s.triangleCount());
  EXPECT_GT(s.triangleCount(), 1000u);
  EXPECT_LE(s.triangleCount(), 100000u);
  for (uint32_t i : s.indices) ASSERT_LT(i, s.vertices.size());
  for (uint32_t m : s.triangleMaterial) ASSERT_LT(m, s.materials.size());
  for (const auto& v : s.vertices) {
    ASSERT_TRUE(std::isfinite(v.position.x) && std::isfinite(v.position.y) &&
                std::isfinite(v.position.z));
    ASSERT_NEAR(glm::length(v.normal), 1.0f, 1e-3f);
  }
  for (const auto& l : s.lights) {
    ASSERT_TRUE(std::isfinite(l.position.x) && std::isfinite(l.position.y) &&
                std::isfinite(l.position.z));
    ASSERT_TRUE(std::isfinite(l.color.x) && l.color.x >= 0.0f && l.color.y >= 0.0f &&
                l.color.z >= 0.0f);
    ASSERT_GT(l.range, 0.0f);
  }
  // Several materials with varied terms, some emissive.
  std::set<float> shininess;
  int emissive = 0;
  for (const auto& m : s.materials) {
    shininess.insert(m.shininess);
    if (m.emissive.x + m.emissive.y + m.emissive.z > 0.0f) ++emissive;
  }
  EXPECT_GE(s.materials.size(), 8u);
  EXPECT_GE(shininess.size(), 4u);
  EXPECT_GE(emissive, 1);
  EXPECT_GE(s.cameraPath.size(), 120u);
  for (const auto& c : s.cameraPath) {
    EXPECT_NEAR(c.yfov, 60.0f * kPi / 180.0f, 1e-4f);
    EXPECT_GT(c.znear, 0.0f);
    EXPECT_GT(c.zfar, c.znear * 100.0f);
  }
  EXPECT_GT(s.ambient.x, 0.0f);
  EXPECT_LE(s.ambient.x, 0.05f);
}

glm::vec3 eyeOf(const ts::SceneCamera& c) { return glm::vec3(glm::inverse(c.viewFromWorld)[3]); }

template <typename T>
bool sameBytes(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

bool sameLights(const Scene& a, const Scene& b) {
  if (a.lights.size() != b.lights.size()) return false;
  for (size_t i = 0; i < a.lights.size(); ++i)
    if (a.lights[i].position != b.lights[i].position || a.lights[i].color != b.lights[i].color ||
        a.lights[i].range != b.lights[i].range)
      return false;
  return true;
}

bool sameGeometry(const Scene& a, const Scene& b) {
  if (a.vertices.size() != b.vertices.size() || !sameBytes(a.indices, b.indices)) return false;
  for (size_t i = 0; i < a.vertices.size(); ++i)
    if (a.vertices[i].position != b.vertices[i].position) return false;
  return true;
}

TEST(SceneBuiltin, NamesAndLightSets) {
  EXPECT_EQ(ts::builtinSceneNames(), (std::vector<std::string>{"street", "atrium"}));
  EXPECT_EQ(ts::builtinLightSets("street"), (std::vector<std::string>{"many", "few"}));
  EXPECT_EQ(ts::builtinLightSets("atrium"),
            (std::vector<std::string>{"small", "big", "mixed", "thesis-small", "thesis-big",
                                      "thesis-big-shadows", "thesis-mixed"}));
  EXPECT_THROW(ts::builtinLightSets("nope"), ts::Error);
}

TEST(SceneBuiltin, AllScenesAndLightSetsAreWellFormed) {
  for (const auto& name : ts::builtinSceneNames())
    for (const auto& set : ts::builtinLightSets(name)) {
      SCOPED_TRACE(name + "/" + set);
      expectWellFormed(ts::makeBuiltinScene(name, set, 1));
    }
}

TEST(SceneBuiltin, DeterministicForASeedAndDifferentAcrossSeeds) {
  for (const auto& name : ts::builtinSceneNames()) {
    SCOPED_TRACE(name);
    Scene a = ts::makeBuiltinScene(name, "", 7), b = ts::makeBuiltinScene(name, "", 7);
    EXPECT_TRUE(sameGeometry(a, b));
    EXPECT_TRUE(sameLights(a, b));
    Scene c = ts::makeBuiltinScene(name, "", 8);
    EXPECT_FALSE(sameLights(a, c));
    if (name == "street") {
      EXPECT_FALSE(sameGeometry(a, c));  // building heights, robots
    }
  }
}

TEST(SceneBuiltin, UnknownNamesThrowListingTheKnownOnes) {
  try {
    ts::loadScene("builtin:nope", {});
    FAIL() << "no exception";
  } catch (const ts::Error& e) {
    EXPECT_NE(std::string(e.what()).find("street"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("atrium"), std::string::npos) << e.what();
  }
  SceneOptions o;
  o.lightSet = "bogus";
  try {
    ts::loadScene("builtin:street", o);
    FAIL() << "no exception";
  } catch (const ts::Error& e) {
    EXPECT_NE(std::string(e.what()).find("many, few"), std::string::npos) << e.what();
  }
  try {
    ts::loadScene("builtin:atrium", o);
    FAIL() << "no exception";
  } catch (const ts::Error& e) {
    EXPECT_NE(std::string(e.what()).find("small, big, mixed"), std::string::npos) << e.what();
  }
  EXPECT_THROW(ts::loadScene("street", {}), ts::Error);  // neither builtin: nor .gltf/.glb
  EXPECT_THROW(ts::loadScene("scene.obj", {}), ts::Error);
  EXPECT_THROW(ts::makeBuiltinScene("nope", "", 1), ts::Error);
}

TEST(SceneStreet, ManyLightsEvenlyAlongTheRobotPaths) {
  Scene s = ts::loadScene("builtin:street", {});
  ASSERT_EQ(s.lights.size(), 924u);
  for (size_t k = 0; k < s.lights.size(); ++k) {
    const auto& l = s.lights[k];
    EXPECT_EQ(l.range, 12.5f);
    EXPECT_GE(l.position.y, 1.0f);
    EXPECT_LE(l.position.y, 6.0f);
    EXPECT_LT(std::fabs(l.position.x), 14.55f);  // inside the street
    // 11 paths x 84 evenly spaced slots over z in [-150, 150].
    size_t slot = k / 11;
    EXPECT_NEAR(l.position.z, -150.0f + 300.0f * (float(slot) + 0.5f) / 84.0f, 1e-3f);
  }
}

TEST(SceneStreet, FewLightsOnePerRobot) {
  SceneOptions o;
  o.lightSet = "few";
  Scene s = ts::loadScene("builtin:street", o);
  ASSERT_EQ(s.lights.size(), 11u);
  std::set<float> zs;
  for (const auto& l : s.lights) {
    EXPECT_EQ(l.range, 40.0f);
    EXPECT_GT(l.position.y, 2.5f);
    zs.insert(std::round(l.position.z));
  }
  EXPECT_EQ(zs.size(), 11u);  // over 11 different robots along the street
  // The robots' beacons (emissive) are there too: 11 robots, one beacon each.
  uint32_t beacon = UINT32_MAX;
  for (size_t m = 0; m < s.materials.size(); ++m)
    if (s.materials[m].name == "robot_beacon") beacon = uint32_t(m);
  ASSERT_NE(beacon, UINT32_MAX);
  std::set<int> beaconZ;
  for (size_t t = 0; t < s.triangleCount(); ++t)
    if (s.triangleMaterial[t] == beacon)
      beaconZ.insert(int(std::floor(s.vertices[s.indices[3 * t]].position.z)));
  EXPECT_GE(beaconZ.size(), 11u);
}

TEST(SceneStreet, FacadesAre29Point1Apart) {
  Scene s = ts::makeBuiltinScene("street", "many", 3);
  std::set<std::string> facades = {"brick", "sandstone", "concrete", "slate_blue", "ochre_render"};
  int atPlus = 0, atMinus = 0;
  for (size_t t = 0; t < s.triangleCount(); ++t) {
    if (!facades.count(s.materials[s.triangleMaterial[t]].name)) continue;
    for (int k = 0; k < 3; ++k) {
      glm::vec3 p = s.vertices[s.indices[3 * t + k]].position;
      if (std::fabs(p.z) > 159.0f) continue;  // the blocks closing the street's ends
      ASSERT_GE(std::fabs(p.x), 14.55f - 1e-4f) << "building inside the street at z=" << p.z;
      if (std::fabs(p.x - 14.55f) < 1e-4f) ++atPlus;
      if (std::fabs(p.x + 14.55f) < 1e-4f) ++atMinus;
    }
  }
  EXPECT_GT(atPlus, 20);
  EXPECT_GT(atMinus, 20);
  // Robots stand in the street, 1..3 units tall (their material is only used by robots).
  float robotTop = 0.0f;
  for (size_t t = 0; t < s.triangleCount(); ++t)
    if (s.materials[s.triangleMaterial[t]].name == "robot_metal")
      for (int k = 0; k < 3; ++k) {
        glm::vec3 p = s.vertices[s.indices[3 * t + k]].position;
        ASSERT_LT(std::fabs(p.x), 12.0f);
        robotTop = std::max(robotTop, p.y);
      }
  EXPECT_GT(robotTop, 1.0f);
  EXPECT_LT(robotTop, 3.1f);
}

TEST(SceneStreet, CameraFliesDownTheStreetLowAndHigh) {
  Scene s = ts::makeBuiltinScene("street", "", 1);
  ASSERT_GE(s.cameraPath.size(), 100u);
  float minY = 1e9f, maxY = -1e9f;
  glm::vec3 previous = eyeOf(s.cameraPath[0]);
  for (const auto& c : s.cameraPath) {
    glm::vec3 e = eyeOf(c);
    EXPECT_LT(std::fabs(e.x), 14.55f);
    EXPECT_LT(glm::length(e - previous), 3.0f);  // smooth
    previous = e;
    minY = std::min(minY, e.y);
    maxY = std::max(maxY, e.y);
    // Looking along the street (-Z): the view direction's z dominates.
    glm::vec3 forward = -glm::vec3(glm::inverse(c.viewFromWorld)[2]);
    EXPECT_LT(forward.z, -0.8f);
  }
  EXPECT_LT(minY, 2.5f);
  EXPECT_GT(maxY, 10.0f);
  EXPECT_LT(eyeOf(s.cameraPath.back()).z, eyeOf(s.cameraPath.front()).z - 200.0f);
}

TEST(SceneAtrium, ProportionsAndLightSets) {
  Scene s = ts::makeBuiltinScene("atrium", "", 1);
  ts::Bounds b = s.bounds();
  EXPECT_NEAR(b.max.y, 16.3f, 0.01f);  // 16 m walls (+ roof slab)
  // Courtyard floor: the checker tiles span 30 x 13.
  ts::Bounds floor;
  for (size_t t = 0; t < s.triangleCount(); ++t) {
    const std::string& n = s.materials[s.triangleMaterial[t]].name;
    if (n == "floor_tile_light" || n == "floor_tile_dark")
      for (int k = 0; k < 3; ++k) floor.extend(s.vertices[s.indices[3 * t + k]].position);
  }
  EXPECT_NEAR(floor.extent().x, 30.0f, 1e-3f);
  EXPECT_NEAR(floor.extent().z, 13.0f, 1e-3f);
  ASSERT_EQ(s.lights.size(), 128u);  // small (default)
  for (const auto& l : s.lights) {
    EXPECT_GE(l.range, 0.5f);
    EXPECT_LE(l.range, 2.0f);
  }
  Scene big = ts::makeBuiltinScene("atrium", "big", 1);
  ASSERT_EQ(big.lights.size(), 16u);
  for (const auto& l : big.lights) {
    EXPECT_GE(l.range, 8.0f);
    EXPECT_LE(l.range, 20.0f);
  }
  Scene mixed = ts::makeBuiltinScene("atrium", "mixed", 1);
  ASSERT_EQ(mixed.lights.size(), 128u);
  int bigCount = 0;
  for (const auto& l : mixed.lights) bigCount += l.range >= 8.0f;
  EXPECT_EQ(bigCount, 4);
  // The camera walks inside the courtyard.
  for (const auto& c : s.cameraPath) {
    glm::vec3 e = eyeOf(c);
    EXPECT_LT(std::fabs(e.x), 15.0f);
    EXPECT_LT(std::fabs(e.z), 6.5f);
    EXPECT_GT(e.y, 1.0f);
    EXPECT_LT(e.y, 8.0f);
  }
}

// The thesis's four scenarios (issue #18): the small, big and mixed lights of a seed, the big
// ones casting in thesis-big-shadows and thesis-mixed, at the thesis's light counts.
TEST(SceneBuiltin, ThesisLightSetsCastFromTheirBigLights) {
  struct Expect {
    const char* set;
    const char* same;  // the set whose lights these are
    bool bigCast;
  };
  for (const Expect& x :
       {Expect{"thesis-small", "small", false}, Expect{"thesis-big", "big", false},
        Expect{"thesis-big-shadows", "big", true}, Expect{"thesis-mixed", "mixed", true}})
    for (int count : {-1, 1, 10, 50, 100}) {
      SCOPED_TRACE(std::string(x.set) + " x " + std::to_string(count));
      SceneOptions o;
      o.lightSet = x.set;
      o.lightCount = count;
      o.seed = 3;
      const Scene s = ts::loadScene("builtin:atrium", o);
      EXPECT_TRUE(sameLights(s, ts::loadScene("builtin:atrium", o)));
      o.lightSet = x.same;
      const Scene plain = ts::loadScene("builtin:atrium", o);
      ASSERT_EQ(s.lights.size(), plain.lights.size());
      if (count >= 0) {
        EXPECT_EQ(s.lights.size(), size_t(count));
      }
      size_t casters = 0, big = 0;
      for (size_t i = 0; i < s.lights.size(); ++i) {
        EXPECT_EQ(s.lights[i].position, plain.lights[i].position);
        EXPECT_EQ(s.lights[i].range, plain.lights[i].range);
        EXPECT_FALSE(plain.lights[i].castsShadow);
        const bool isBig = s.lights[i].range >= 8.0f;
        EXPECT_EQ(s.lights[i].castsShadow, x.bigCast && isBig);
        casters += s.lights[i].castsShadow;
        big += isBig;
      }
      const size_t n = s.lights.size();
      // mixed: every 32nd light is big (light 0 first).
      const size_t expectedBig = std::string(x.same) == "small" ? 0
                                 : std::string(x.same) == "big" ? n
                                                                : (n + 31) / 32;
      EXPECT_EQ(big, expectedBig);
      EXPECT_EQ(casters, x.bigCast ? expectedBig : 0u);
    }
  // --shadows overrides the set's marks.
  SceneOptions o;
  o.lightSet = "thesis-big-shadows";
  o.shadows = "none";
  for (const auto& l : ts::loadScene("builtin:atrium", o).lights) EXPECT_FALSE(l.castsShadow);
}

template <class F>
void expectOneLine(F&& f, const std::string& needle) {
  try {
    f();
    ADD_FAILURE() << "no ts::Error thrown";
  } catch (const ts::Error& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    EXPECT_NE(m.find(needle), std::string::npos) << m;
  }
}

// The scenarios for a glTF scene: placed inside its bounds, ranges in proportion to them,
// deterministic for a seed, the stated counts and casters; no geometry is one line.
TEST(SceneThesisLights, PlacedFromTheBounds) {
  ts::Bounds b;
  b.extend({-10.0f, 0.0f, -5.0f});
  b.extend({30.0f, 20.0f, 5.0f});
  const float diagonal = glm::length(b.extent());
  for (const std::string& set : ts::thesisLightSets())
    for (int count : {-1, 1, 10, 100}) {
      SCOPED_TRACE(set + " x " + std::to_string(count));
      const auto a = ts::placeThesisLights(b, set, 4, count);
      const auto again = ts::placeThesisLights(b, set, 4, count);
      const auto other = ts::placeThesisLights(b, set, 5, count);
      const size_t n = count >= 0                                       ? size_t(count)
                       : set == "thesis-small" || set == "thesis-mixed" ? 128u
                                                                        : 16u;
      ASSERT_EQ(a.size(), n);
      size_t casters = 0, big = 0;
      for (size_t i = 0; i < n; ++i) {
        EXPECT_EQ(a[i].position, again[i].position);
        EXPECT_EQ(a[i].range, again[i].range);
        EXPECT_NE(a[i].position, other[i].position);
        EXPECT_EQ(a[i].type, ts::SceneLightType::Point);
        for (int c = 0; c < 3; ++c) {
          EXPECT_GE(a[i].position[c], b.min[c] + 0.05f * b.extent()[c] - 1e-4f);
          EXPECT_LE(a[i].position[c], b.max[c] - 0.05f * b.extent()[c] + 1e-4f);
        }
        const bool isBig = a[i].range >= 0.2f * diagonal * 0.999f;
        EXPECT_TRUE(isBig || a[i].range <= 0.05f * diagonal * 1.001f) << a[i].range;
        big += isBig;
        casters += a[i].castsShadow;
        EXPECT_TRUE(!a[i].castsShadow || isBig);
      }
      const size_t expectedBig = set == "thesis-small"   ? 0u
                                 : set == "thesis-mixed" ? (n + 31) / 32
                                                         : n;
      EXPECT_EQ(big, expectedBig);
      const bool cast = set == "thesis-big-shadows" || set == "thesis-mixed";
      EXPECT_EQ(casters, cast ? expectedBig : 0u);
    }
  expectOneLine([&] { ts::placeThesisLights(ts::Bounds{}, "thesis-big", 1, 4); }, "geometry");
  expectOneLine([&] { ts::placeThesisLights(b, "thesis-huge", 1, 4); }, "thesis-mixed");
}

TEST(SceneOptions, LightCountAndRange) {
  SceneOptions o;
  o.lightCount = 100;
  Scene s = ts::loadScene("builtin:street", o);
  ASSERT_EQ(s.lights.size(), 100u);
  for (const auto& l : s.lights) EXPECT_EQ(l.range, 12.5f);
  // 100 = 11 paths x 9 + 1: the first path has 10 slots.
  EXPECT_NEAR(s.lights[0].position.z, -150.0f + 300.0f * 0.5f / 10.0f, 1e-3f);
  EXPECT_NEAR(s.lights[1].position.z, -150.0f + 300.0f * 0.5f / 9.0f, 1e-3f);
  EXPECT_EQ(ts::loadScene("builtin:street", o).lights[99].position, s.lights[99].position);

  o.lightCount = 0;
  EXPECT_TRUE(ts::loadScene("builtin:street", o).lights.empty());
  EXPECT_EQ(ts::loadScene("builtin:street", o).triangleCount(), s.triangleCount());

  o.lightCount = 3000;
  o.lightRange = 3.0f;
  Scene many = ts::loadScene("builtin:street", o);
  ASSERT_EQ(many.lights.size(), 3000u);
  for (const auto& l : many.lights) ASSERT_EQ(l.range, 3.0f);

  o = SceneOptions{};
  o.lightSet = "few";
  o.lightCount = 30;
  Scene few = ts::loadScene("builtin:street", o);
  ASSERT_EQ(few.lights.size(), 30u);
  for (const auto& l : few.lights) EXPECT_EQ(l.range, 40.0f);

  o = SceneOptions{};
  o.lightSet = "mixed";
  o.lightCount = 64;
  Scene mixed = ts::loadScene("builtin:atrium", o);
  ASSERT_EQ(mixed.lights.size(), 64u);
  int big = 0;
  for (const auto& l : mixed.lights) big += l.range >= 8.0f;
  EXPECT_EQ(big, 2);  // every 32nd light is big

  o = SceneOptions{};
  o.lightCount = -2;
  EXPECT_THROW(ts::loadScene("builtin:street", o), ts::Error);
  o.lightCount = -1;
  o.lightRange = -1.0f;
  EXPECT_THROW(ts::loadScene("builtin:street", o), ts::Error);
}

TEST(SceneOptions, SeedChangesLightsButKeepsTheirRule) {
  SceneOptions a, b;
  a.seed = 1;
  b.seed = 2;
  Scene sa = ts::loadScene("builtin:street", a), sb = ts::loadScene("builtin:street", b);
  ASSERT_EQ(sa.lights.size(), sb.lights.size());
  EXPECT_FALSE(sameLights(sa, sb));
  for (size_t k = 0; k < sa.lights.size(); ++k)
    EXPECT_EQ(sa.lights[k].position.z, sb.lights[k].position.z);  // same slots along the paths
}

}  // namespace
