// The feature analysis (src/scene/scene_features.h, docs/features.md): what a scene needs of the
// kernels, how an explicit choice overrides it without dropping a need, and the G-buffer planes
// the features keep.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "render/frame_setup.h"
#include "scene/scene_features.h"
#include "scene/scene_loader.h"
#include "util/error.h"
#include "builtin_variant.h"
#include "test_support.h"

namespace ts {
namespace {

using test::builtin;

// ---- the analysis ----------------------------------------------------------------------------

TEST(SceneFeatures, BuiltinsAndTheirVariants) {
  struct Expect {
    std::string variant;
    ShadingModel model;
    bool specular, emissive, point, spot, directional;
  };
  const ShadingModel bp = ShadingModel::BlinnPhong, mr = ShadingModel::MetallicRoughness;
  for (const Expect& e :
       std::vector<Expect>{{"", bp, true, true, true, false, false},
                           {"diffuse", bp, false, false, true, false, false},
                           {"no-emission", bp, true, false, true, false, false},
                           {"spot", bp, true, true, true, true, false},
                           {"sun", bp, true, true, true, false, true},
                           {"metallic-roughness", mr, true, true, true, false, false},
                           {"diffuse,spot,sun", bp, false, false, true, true, true}}) {
    Scene s = builtin("street", "many", e.variant);
    SceneFeatures f = analyzeScene(s, nativeShadingModel(s));
    EXPECT_EQ(f.model, e.model) << e.variant;
    EXPECT_EQ(f.specular, e.specular) << e.variant;
    EXPECT_EQ(f.emissive, e.emissive) << e.variant;
    EXPECT_EQ(f.point, e.point) << e.variant;
    EXPECT_EQ(f.spot, e.spot) << e.variant;
    EXPECT_EQ(f.directional, e.directional) << e.variant;
    EXPECT_FALSE(f.textures) << e.variant;
  }
  // A Blinn-Phong scene shaded with metallic-roughness always has the GGX term.
  EXPECT_TRUE(analyzeScene(builtin("atrium", "small", "diffuse"), ShadingModel::MetallicRoughness)
                  .specular);
}

TEST(SceneFeatures, OnlyMaterialsThatTrianglesUseCount) {
  Scene s = builtin("atrium", "small", "diffuse");
  Material shiny;
  shiny.specular = glm::vec3(0.5f);
  shiny.emissive = glm::vec3(1.0f);
  s.materials.push_back(shiny);  // no triangle uses it
  SceneFeatures f = analyzeScene(s, ShadingModel::BlinnPhong);
  EXPECT_FALSE(f.specular);
  EXPECT_FALSE(f.emissive);
  s.triangleMaterial[0] = uint32_t(s.materials.size() - 1);
  f = analyzeScene(s, ShadingModel::BlinnPhong);
  EXPECT_TRUE(f.specular);
  EXPECT_TRUE(f.emissive);
}

TEST(SceneFeatures, RealGltfContent) {
  std::string path = test::sharedScene("dungeon/level-dungeon.gltf");
  if (path.empty()) GTEST_SKIP() << "../shared/scenes/dungeon absent";
  ::testing::internal::CaptureStderr();
  Scene s = loadGltf(path);
  ::testing::internal::GetCapturedStderr();
  SceneFeatures f = analyzeScene(s, nativeShadingModel(s));
  EXPECT_EQ(f.model, ShadingModel::MetallicRoughness);
  EXPECT_TRUE(f.textures);
  EXPECT_TRUE(f.point);
  EXPECT_TRUE(f.directional);
  EXPECT_FALSE(f.spot);
}

TEST(SceneFeatures, ChoosingOverridesTheAnalysisButNeverDropsANeed) {
  SceneFeatures need =
      analyzeScene(builtin("street", "many", "diffuse,spot"), ShadingModel::BlinnPhong);
  EXPECT_EQ(chooseFeatures("auto", need), need);
  SceneFeatures general = chooseFeatures("general", need);
  EXPECT_TRUE(general.specular && general.emissive && general.spot && general.directional);
  EXPECT_TRUE(general.covers(need));
  SceneFeatures listed = chooseFeatures("point, spot,emissive", need);
  EXPECT_TRUE(listed.emissive && listed.spot && listed.point);
  EXPECT_FALSE(listed.specular || listed.directional);
  try {
    chooseFeatures("point", need);
    FAIL() << "a list without spot was accepted for a scene with spot lights";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("spot"), std::string::npos) << e.what();
  }
  EXPECT_THROW(chooseFeatures("point,spot,fog", need), Error);
  // The build options follow the features.
  EXPECT_NE(listed.kernelDefines().find("-DTS_HAS_SPECULAR=0"), std::string::npos);
  EXPECT_NE(general.kernelDefines().find("-DTS_HAS_DIRECTIONAL=1"), std::string::npos);
  // No light casts a shadow here: `general` builds no shadow sampling, a list may ask for it.
  EXPECT_FALSE(need.shadows || general.shadows);
  EXPECT_EQ(general.kernelDefines().find("TS_HAS_SHADOWS"), std::string::npos);
  EXPECT_NE(
      chooseFeatures("point,spot,emissive,shadows", need).kernelDefines().find(" -DTS_HAS_SHADOWS"),
      std::string::npos);
}

// A shadow-casting light makes `shadows` a need: on in auto and general, never dropped by a list.
TEST(SceneFeatures, AShadowCastingLightNeedsShadows) {
  Scene scene = builtin("street", "many", "diffuse,spot");
  scene.lights.front().castsShadow = true;
  const SceneFeatures need = analyzeScene(scene, ShadingModel::BlinnPhong);
  EXPECT_TRUE(need.shadows);
  EXPECT_NE(need.describe().find("shadows"), std::string::npos);
  EXPECT_TRUE(chooseFeatures("general", need).shadows);
  try {
    chooseFeatures("point,spot,emissive", need);
    FAIL() << "a list without shadows was accepted for a scene with a shadow-casting light";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("shadows"), std::string::npos) << e.what();
  }
}

// ---- trimmed layouts -------------------------------------------------------------------------

TEST(GBufferLayouts, OnlyThePlanesTheFeaturesNeed) {
  struct Expect {
    std::string variant;
    ShadingModel model;
    size_t fp32, fp16, packed;
  };
  const ShadingModel bp = ShadingModel::BlinnPhong, mr = ShadingModel::MetallicRoughness;
  for (const Expect& e : std::vector<Expect>{
           {"", bp, 68, 36, 24},                    // depth + normal, diffuse, specular, emissive
           {"no-emission", bp, 52, 28, 16},         // no emissive plane
           {"diffuse", bp, 36, 20, 12},             // depth + normal + diffuse
           {"metallic-roughness", mr, 52, 28, 21},  // + emissive; packed: + roughness byte
           {"metallic-roughness,no-emission", mr, 36, 20, 13}}) {
    Scene s = builtin("atrium", "small", e.variant);
    SceneFeatures f = analyzeScene(s, nativeShadingModel(s));
    ASSERT_EQ(f.model, e.model) << e.variant;
    size_t expected[3] = {e.fp32, e.fp16, e.packed};
    int k = 0;
    for (GBufferFormat format : {GBufferFormat::FP32, GBufferFormat::FP16, GBufferFormat::PACKED}) {
      PreparedFrame p = prepareFrame(s, 0, 16, 8, format, f);
      EXPECT_EQ(p.encoded.bytesPerPixel(), expected[k++]) << e.variant << " " << toString(format);
      size_t bytes = p.encoded.depth.size() * 4 + p.encoded.normal.size() +
                     p.encoded.diffuse.size() + p.encoded.specular.size() +
                     p.encoded.emissive.size();
      EXPECT_EQ(bytes, p.encoded.bytesPerPixel() * p.encoded.pixelCount()) << e.variant;
    }
  }
}

}  // namespace
}  // namespace ts
