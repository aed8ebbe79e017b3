// Fitting the pipeline to the scene (docs/features.md): kernels refuse frames that need more than
// they shade, the specialised kernels and G-buffer layouts against the general ones, spot and
// directional lights and the metallic-roughness model in every technique against the double
// reference. (The feature analysis and the planes it keeps: scene/scene_features_test.cpp.)
#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <memory>
#include <random>

#include "reference/error_metrics.h"
#include "reference/reference.h"
#include "render/frame_setup.h"
#include "scene/scene_features.h"
#include "scene/scene_loader.h"
#include "techniques/technique.h"
#include "util/error.h"
#include "reference_check.h"
#include "test_support.h"
#include "random_draws.h"
#include "builtin_variant.h"

namespace ts {
namespace {

using test::builtin;
using test::Checked;
using test::kFp32RelativeTolerance;
using test::renderAndCheck;
using test::renderOnly;

// ---- the analysis ----------------------------------------------------------------------------

// Kernels that lack a feature the frame needs refuse it instead of shading it wrong.
TEST(SceneFeatures, KernelsRefuseFramesTheyCannotShade) {
  Scene s = builtin("street", "few", "spot,sun");
  SceneFeatures need = analyzeScene(s, ShadingModel::BlinnPhong);
  PreparedFrame f = prepareFrame(s, 0, 32, 24, GBufferFormat::FP32, need);
  TechniqueConfig config;
  config.features = need;
  config.features.spot = false;
  EXPECT_THROW(renderOnly(f, *createTechnique("tiled", test::context(), config), false), Error);
  config.features = need;
  config.features.directional = false;
  EXPECT_THROW(renderOnly(f, *createTechnique("brute", test::context(), config), false), Error);
  // A trimmed G-buffer under general kernels (they would read planes that are not there).
  Scene plain = builtin("atrium", "small", "diffuse");
  PreparedFrame trimmed = prepareFrame(plain, 0, 32, 24, GBufferFormat::FP32,
                                       analyzeScene(plain, ShadingModel::BlinnPhong));
  EXPECT_THROW(
      renderOnly(trimmed, *createTechnique("tiled", test::context(), TechniqueConfig()), false),
      Error);
}

// ---- specialised == general --------------------------------------------------------------------

// The specialised pipeline compiles less and stores less, and shades the same image: bit for bit
// (the terms it leaves out are exactly zero in the general one).
class SpecialisedPipeline : public ::testing::TestWithParam<std::string> {};

TEST_P(SpecialisedPipeline, SameImageAsTheGeneralOne) {
  const std::string& name = GetParam();
  auto differingPixels = [](const FrameResult& a, const FrameResult& b) {
    size_t n = 0;
    for (size_t i = 0; i < a.image.size(); ++i) n += glm::vec3(a.image[i]) != glm::vec3(b.image[i]);
    return n;
  };
  for (const char* variant : {"diffuse", "metallic-roughness,no-emission", ""}) {
    Scene s = builtin("street", "many", variant);
    SceneFeatures need = analyzeScene(s, nativeShadingModel(s));
    SceneFeatures general = SceneFeatures::general(need.model);
    // Each precision once, per pixel and in lanes.
    for (auto [format, lanes] : {std::pair{GBufferFormat::FP32, 1},
                                 {GBufferFormat::PACKED, 16},
                                 {GBufferFormat::FP16, 4}}) {
      PreparedFrame fs = prepareFrame(s, 30, 96, 64, format, need);
      PreparedFrame fg = prepareFrame(s, 30, 96, 64, format, general);
      if (need.specular != general.specular || need.emissive != general.emissive) {
        EXPECT_LT(fs.encoded.bytesPerPixel(), fg.encoded.bytesPerPixel()) << variant;
      }
      TechniqueConfig cs, cg;
      cs.format = cg.format = format;
      cs.lanes = cg.lanes = lanes;
      cs.features = need;
      cg.features = general;
      FrameResult rs = renderOnly(fs, test::cachedTechnique(name, cs), false);
      FrameResult rg = renderOnly(fg, test::cachedTechnique(name, cg), false);
      EXPECT_EQ(differingPixels(rs, rg), 0u)
          << name << " '" << variant << "' " << toString(format) << " lanes " << lanes;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(EveryTechnique, SpecialisedPipeline,
                         ::testing::ValuesIn(gbufferTechniqueNames()), [](const auto& info) {
                           std::string n = info.param;
                           for (char& ch : n)
                             if (ch == '-') ch = '_';
                           return n;
                         });

// ---- spot and directional lights, metallic-roughness: every technique ------------------------

struct LightCase {
  std::string label, scene, lights, variant;
  int frame;
};

void PrintTo(const LightCase& c, std::ostream* os) { *os << c.label; }

class EveryTechniqueWithLightTypes
    : public ::testing::TestWithParam<std::tuple<std::string, LightCase>> {};

const PreparedFrame& lightCaseFrame(const LightCase& c) {
  static std::map<std::string, std::unique_ptr<PreparedFrame>> cache;
  auto& p = cache[c.label];
  if (!p) {
    Scene s = builtin(c.scene, c.lights, c.variant);
    p = std::make_unique<PreparedFrame>(prepareFrame(s, c.frame, 160, 96, GBufferFormat::FP32,
                                                     analyzeScene(s, nativeShadingModel(s))));
  }
  return *p;
}

TEST_P(EveryTechniqueWithLightTypes, MatchesReferenceWithNoMissedLight) {
  const auto& [name, lc] = GetParam();
  const PreparedFrame& f = lightCaseFrame(lc);
  for (int lanes : {1, 16}) {
    TechniqueConfig config;
    config.features = f.features;
    config.lanes = lanes;
    Checked c = renderAndCheck(f, test::cachedTechnique(name, config));
    EXPECT_EQ(c.missed, 0u) << lanes;
    EXPECT_LE(c.error.maxRelPeak, kFp32RelativeTolerance) << lanes;
    EXPECT_GT(c.contributing, 0u);
    for (const auto& px : c.result.image) ASSERT_TRUE(std::isfinite(px.x + px.y + px.z));
  }
}

std::vector<LightCase> lightCases() {
  return {{"street_spot", "street", "many", "spot", 40},
          {"street_spot_sun", "street", "few", "spot,sun", 100},
          {"atrium_spot_mr", "atrium", "mixed", "spot,metallic-roughness", 20},
          {"atrium_sun_mr_diffuse_lights", "atrium", "big", "sun,metallic-roughness", 70},
          {"street_diffuse_spot", "street", "many", "diffuse,spot", 0}};
}

INSTANTIATE_TEST_SUITE_P(Variants, EveryTechniqueWithLightTypes,
                         ::testing::Combine(::testing::ValuesIn(gbufferTechniqueNames()),
                                            ::testing::ValuesIn(lightCases())),
                         [](const auto& info) {
                           std::string n =
                               std::get<0>(info.param) + "_" + std::get<1>(info.param).label;
                           for (char& ch : n)
                             if (ch == '-') ch = '_';
                           return n;
                         });

// Spot lights placed against the camera: the camera inside a cone, cones behind it and through
// the near plane, cones seen edge-on, narrow and wide; random cameras in both built-ins.
TEST(SpotCulling, ConesAroundTheCameraMissNothing) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (const char* name : {"street", "atrium"}) {
    Scene scene = builtin(name, name == std::string("street") ? "few" : "small", "");
    Bounds b = scene.bounds();
    for (int cam = 0; cam < 3; ++cam) {
      auto draw = [&] { return u(rng); };
      const auto e = test::drawnLastFirst<3>(draw);
      glm::vec3 eye = b.min + glm::vec3(e[0], 0.05f + 0.3f * e[1], e[2]) * b.extent();
      const auto d = test::drawnLastFirst<3>(draw);
      glm::vec3 fwd = glm::normalize(glm::vec3(d[0] - 0.5f, 0.2f * (d[1] - 0.5f), d[2] - 0.5f));
      glm::vec3 side = glm::normalize(glm::cross(fwd, glm::vec3(0, 1, 0)));
      scene.cameraPath = {SceneCamera::lookAt(eye, eye + fwd, {0, 1, 0}, 1.0f, 0.1f, 500.0f)};
      scene.lights.clear();
      float range = 0.15f * glm::length(b.extent());
      auto spot = [&](glm::vec3 p, glm::vec3 axis, float outerDeg) {
        float outer = glm::radians(outerDeg);
        scene.lights.push_back(SceneLight::spot(
            p, glm::normalize(axis), glm::vec3(range * range * 0.02f), range, 0.5f * outer, outer));
      };
      spot(eye + glm::vec3(0, 0.5f, 0), -fwd + glm::vec3(0, -0.3f, 0), 40);  // camera inside
      spot(eye - 2.0f * fwd, fwd, 25);                 // behind, shining past the camera
      spot(eye + 0.05f * fwd, fwd + 0.2f * side, 60);  // apex at the near plane
      spot(eye + 0.3f * range * fwd, side, 15);        // edge-on, narrow
      spot(eye + 0.5f * range * fwd - 0.4f * range * side, side, 85);  // edge-on, almost flat
      for (int k = 0; k < 20; ++k) {                                   // anywhere, any direction
        // Last argument first, as g++ drew them (random_draws.h).
        const float outerDeg = 5.0f + 80.0f * u(rng);
        const auto a = test::drawnLastFirst<3>(draw);
        const auto p = test::drawnLastFirst<3>(draw);
        spot(b.min + glm::vec3(p[0], p[1], p[2]) * b.extent(),
             glm::vec3(a[0] - 0.5f, a[1] - 0.5f, a[2] - 0.5f), outerDeg);
      }
      SceneFeatures need = analyzeScene(scene, ShadingModel::BlinnPhong);
      PreparedFrame f = prepareFrame(scene, 0, 128, 80, GBufferFormat::FP32, need);
      ReferenceImage ref = shadeReference(f.encoded, f.intrinsics, f.lights, f.ambient, 0);
      ASSERT_GT(ref.contributing, 0u);
      for (const auto& technique : gbufferTechniqueNames()) {
        for (const char* cull : {"cone", "bound-sphere"}) {
          TechniqueConfig config;
          config.features = need;
          config.spotCulling = spotCullingNames().parse(cull);
          config.tileWidth = config.tileHeight = 8;
          Checked c = renderAndCheck(f, test::cachedTechnique(technique, config), ref);
          EXPECT_EQ(c.missed, 0u) << name << " camera " << cam << " " << technique << " " << cull;
          EXPECT_LE(c.error.maxRelPeak, kFp32RelativeTolerance)
              << name << " camera " << cam << " " << technique << " " << cull;
        }
      }
    }
  }
}

// Cone culling lists fewer lights than culling the cone's bounding sphere, which lists fewer than
// the range sphere (on the spot variant of the street, every other light a spot).
TEST(SpotCulling, ConesCullMoreThanSpheres) {
  Scene s = builtin("street", "many", "spot");
  SceneFeatures need = analyzeScene(s, ShadingModel::BlinnPhong);
  PreparedFrame f = prepareFrame(s, 40, 160, 96, GBufferFormat::FP32, need);
  uint64_t previous = 0;
  for (const char* cull : {"cone", "bound-sphere", "range-sphere"}) {
    TechniqueConfig config;
    config.features = need;
    config.spotCulling = spotCullingNames().parse(cull);
    Checked c = renderAndCheck(f, test::cachedTechnique("tiled", config));
    EXPECT_EQ(c.missed, 0u) << cull;
    EXPECT_GT(c.result.counters.lightingComputations, previous) << cull;
    previous = c.result.counters.lightingComputations;
  }
}

// Real glTF content in its own model (metallic-roughness, with base colour, metallic-roughness and
// emissive textures, point and directional lights), through every technique: no light missed,
// within the fp32 tolerance.
TEST(RealContentInItsOwnModel, EveryTechniqueMatchesTheReference) {
  struct Real {
    std::string path;
    bool addLights;
  };
  std::vector<Real> scenes;
  if (auto p = test::sharedScene("dungeon/level-dungeon.gltf"); !p.empty())
    scenes.push_back({p, false});
  if (auto p = test::sharedScene("sponza-crytek/sponza.gltf"); !p.empty())
    scenes.push_back({p, true});
  const std::string engine =
      "/usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb";
  if (std::filesystem::exists(engine)) scenes.push_back({engine, true});
  if (scenes.empty())
    GTEST_SKIP() << "no real glTF scene here (../shared/scenes, assimp-testmodels)";
  for (const Real& r : scenes) {
    ::testing::internal::CaptureStderr();
    Scene scene = loadGltf(r.path);
    ::testing::internal::GetCapturedStderr();
    if (r.addLights) {  // Sponza and the engine bring none: point and spot lights through them
      Bounds b = scene.bounds();
      float size = glm::length(b.extent());
      std::mt19937 rng(4);
      std::uniform_real_distribution<float> u(0.0f, 1.0f);
      for (int i = 0; i < 24; ++i) {
        auto draw = [&] { return u(rng); };
        const auto p = test::drawnLastFirst<3>(draw);
        glm::vec3 at = b.min + glm::vec3(p[0], p[1], p[2]) * b.extent();
        const auto k = test::drawnLastFirst<3>(draw);
        glm::vec3 c = glm::vec3(k[0], k[1], k[2]) * size * size * 0.01f;
        if (i % 2) scene.lights.push_back(SceneLight::point(at, c, 0.3f * size));
        else
          scene.lights.push_back(
              SceneLight::spot(at, glm::vec3(0, -1, 0), c, 0.4f * size, 0.3f, 0.6f));
      }
      scene.lights.push_back(
          SceneLight::directional(glm::normalize(glm::vec3(0.2f, -1, 0.3f)), glm::vec3(0.3f)));
    }
    SceneFeatures need = analyzeScene(scene, nativeShadingModel(scene));
    ASSERT_EQ(need.model, ShadingModel::MetallicRoughness) << r.path;
    PreparedFrame f = prepareFrame(scene, 0, 128, 80, GBufferFormat::FP16, need);
    ASSERT_GT(f.gbuffer.geometryPixels(), 0u) << r.path;
    ReferenceImage ref = shadeReference(f.encoded, f.intrinsics, f.lights, f.ambient, 0);
    for (const auto& name : gbufferTechniqueNames()) {
      TechniqueConfig config;
      config.format = GBufferFormat::FP16;
      config.features = need;
      Checked c = renderAndCheck(f, test::cachedTechnique(name, config), ref);
      EXPECT_EQ(c.missed, 0u) << r.path << " " << name;
      EXPECT_LE(c.error.maxRelPeak, kFp32RelativeTolerance) << r.path << " " << name;
    }
  }
}

}  // namespace
}  // namespace ts
