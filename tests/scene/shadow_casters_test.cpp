// Shadow-casting lights, the first piece of shadows (issue #18): glTF extras "castsShadow" on a
// light or its node, `--shadows none|all|N` (chooseShadowCasters) and the export writing the mark
// back. These tests check the marks only (shading with the maps:
// tests/techniques/shadows_test.cpp).
#include <gtest/gtest.h>

#include <filesystem>

#include "gltf_builder.h"
#include "scene/scene_loader.h"
#include "scene/shadow_casters.h"
#include "util/error.h"

namespace ts {
namespace {

using test::json;

Scene load(const json& doc) {
  const std::string text = doc.dump();
  std::vector<std::string> warnings;
  return loadGltfFromMemory(reinterpret_cast<const unsigned char*>(text.data()), text.size(),
                            "/nonexistent", "shadows.gltf", &warnings);
}

std::vector<SceneLight> fourLights() {
  return {SceneLight::point({0, 0, 0}, glm::vec3(1), 2.0f),
          SceneLight::point({1, 0, 0}, glm::vec3(1), 8.0f),
          SceneLight::directional({0, -1, 0}, glm::vec3(1)),
          SceneLight::point({2, 0, 0}, glm::vec3(1), 8.0f)};
}

std::vector<bool> marks(const std::vector<SceneLight>& lights) {
  std::vector<bool> m;
  for (const SceneLight& l : lights) m.push_back(l.castsShadow);
  return m;
}

TEST(ShadowCasters, NoneAllAndTheNLightsOfLargestRange) {
  std::vector<SceneLight> lights = fourLights();
  chooseShadowCasters(lights, "all");
  EXPECT_EQ(shadowCasterCount(lights), 4u);
  chooseShadowCasters(lights, "none");
  EXPECT_EQ(shadowCasterCount(lights), 0u);
  // Directional first (unbounded), then range 8 (lower index first on the tie).
  chooseShadowCasters(lights, "2");
  EXPECT_EQ(marks(lights), (std::vector<bool>{false, true, true, false}));
  chooseShadowCasters(lights, "3");
  EXPECT_EQ(marks(lights), (std::vector<bool>{false, true, true, true}));
  chooseShadowCasters(lights, "0");
  EXPECT_EQ(shadowCasterCount(lights), 0u);
  lights[0].castsShadow = true;
  chooseShadowCasters(lights, "");  // the scene's own marks stay
  EXPECT_EQ(marks(lights), (std::vector<bool>{true, false, false, false}));
}

TEST(ShadowCasters, BadSpecsAreOneLineErrors) {
  for (const char* spec : {"some", "-1", "2.5", "5", "99999999999999"}) {
    std::vector<SceneLight> lights = fourLights();
    try {
      chooseShadowCasters(lights, spec);
      ADD_FAILURE() << "accepted --shadows " << spec;
    } catch (const Error& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("--shadows"), std::string::npos) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
  }
}

TEST(ShadowCasters, GltfExtrasOnTheLightOrItsNodeMarkIt) {
  json doc = test::triangle();
  EXPECT_FALSE(load(doc).lights.at(0).castsShadow);
  doc["extensions"]["KHR_lights_punctual"]["lights"][0]["extras"] = {{"castsShadow", true}};
  EXPECT_TRUE(load(doc).lights.at(0).castsShadow);
  doc = test::triangle();
  doc["nodes"][1]["extras"] = {{"castsShadow", true}};
  EXPECT_TRUE(load(doc).lights.at(0).castsShadow);
  doc["nodes"][1]["extras"] = {{"castsShadow", false}, {"other", "kept"}};
  EXPECT_FALSE(load(doc).lights.at(0).castsShadow);
  doc["nodes"][1]["extras"] = "free-form extras are no mark";
  EXPECT_FALSE(load(doc).lights.at(0).castsShadow);
}

TEST(ShadowCasters, ANonBooleanCastsShadowIsOneClearError) {
  json doc = test::triangle();
  doc["extensions"]["KHR_lights_punctual"]["lights"][0]["extras"] = {{"castsShadow", "yes"}};
  try {
    load(doc);
    FAIL() << "loaded castsShadow \"yes\"";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("castsShadow"), std::string::npos) << what;
    EXPECT_NE(what.find("true or false"), std::string::npos) << what;
  }
}

TEST(ShadowCasters, SceneExportWritesTheMarksBack) {
  SceneOptions options;
  options.shadows = "3";
  const Scene street = loadScene("builtin:street", options);
  ASSERT_EQ(shadowCasterCount(street.lights), 3u);
  const std::string path =
      (std::filesystem::temp_directory_path() / "tileshade_shadow_marks.gltf").string();
  exportGltf(street, path);
  std::vector<std::string> warnings;
  const Scene back = loadGltf(path, &warnings);
  std::filesystem::remove(path);
  EXPECT_EQ(marks(back.lights), marks(street.lights));
}

}  // namespace
}  // namespace ts
