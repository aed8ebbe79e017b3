// --shadow-storage per-light (docs/shadows.md): deferred and deferred-stencil draw each light's
// maps into one reused atlas just before its launch (the directional lights' before the base
// pass). The image is the atlas path's bit for bit (the same texels, sampled relative to their
// face), for point, spot and directional casters, every filter, lanes 1 and 16, and passes the
// reference check; the resident bytes are the largest light's maps; the other techniques refuse.
#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "raster/per_light_shadows.h"
#include "raster/shadow_maps.h"
#include "reference_check.h"
#include "render/frame_setup.h"
#include "scene/scene_features.h"
#include "techniques/technique.h"
#include "test_scenes.h"
#include "test_support.h"
#include "util/error.h"

namespace ts {
namespace {

using test::casting;

// A box floating over a floor, lit by a point, a spot and a directional light that cast shadows,
// one point light that casts none, and a casting point light behind the camera, off screen.
Scene litFloorAndBox() {
  Scene s = test::floorAndBox(glm::vec3(0.0f));
  s.lights.push_back(casting(SceneLight::point({1.5, 4.0, 0.5}, glm::vec3(8.0f), 20.0f)));
  s.lights.push_back(casting(SceneLight::spot({-3.0, 5.0, 2.0}, {0.5f, -1.0f, -0.3f},
                                              glm::vec3(10.0f), 20.0f, 0.3f, 0.7f)));
  s.lights.push_back(casting(SceneLight::directional({-0.3f, -1.0f, -0.4f}, glm::vec3(0.5f))));
  s.lights.push_back(SceneLight::point({4.0, 1.0, 4.0}, glm::vec3(2.0f), 8.0f));
  s.lights.push_back(casting(SceneLight::point({0.0, 8.0, 30.0}, glm::vec3(8.0f), 5.0f)));
  return s;
}

struct StoredFrame {
  PreparedFrame frame;
  std::shared_ptr<const ShadowAtlas> atlas;
  std::unique_ptr<PerLightShadowMaps> perLight;
};

StoredFrame shadowedFrame(const Scene& scene, int taps, GBufferFormat format) {
  StoredFrame s;
  const SceneFeatures features = analyzeScene(scene, ShadingModel::BlinnPhong);
  s.frame = prepareFrame(scene, 0, 96, 64, format, features);
  ShadowAtlasOptions options;
  options.mapSize = 128;
  const ShadowAtlasLayout layout =
      planShadowAtlas(scene.lights, scene.bounds(), s.frame.camera, options,
                      viewGeometryBounds(s.frame.gbuffer, s.frame.camera));
  s.atlas = std::make_shared<ShadowAtlas>(drawShadowAtlas(scene, layout, 1));
  ShadowSampling sampling;
  sampling.taps = taps;
  attachShadowMaps(s.atlas, scene.lights, s.frame.camera.viewFromWorld, sampling, s.frame.lights);
  s.perLight = std::make_unique<PerLightShadowMaps>(scene, layout);
  return s;
}

TechniqueConfig configFor(const PreparedFrame& f, int lanes, ShadowStorage storage) {
  TechniqueConfig config;
  config.features = f.features;
  config.format = f.encoded.format;
  config.lanes = lanes;
  config.shadowStorage = storage;
  return config;
}

FrameResult rendered(const StoredFrame& s, Technique& t, bool withPerLight = true) {
  DeviceFrame frame = s.frame.upload(test::context());
  if (withPerLight) frame.perLightShadows = s.perLight.get();
  FrameRequest request;
  request.wantAssignment = true;
  return t.render(frame, request);
}

TEST(ShadowStorage, PerLightImagesEqualTheAtlasOnesBitForBit) {
  const Scene scene = litFloorAndBox();
  for (GBufferFormat format : {GBufferFormat::FP32, GBufferFormat::PACKED})
    for (int taps : {1, 3}) {
      const StoredFrame s = shadowedFrame(scene, taps, format);
      const PreparedFrame& f = s.frame;
      ASSERT_TRUE(f.lights.hasShadows());
      const ReferenceImage ref = shadeReference(f.encoded, f.intrinsics, f.lights, f.ambient, 0);
      // The shadows are there: unshadowed, more (pixel, light) pairs contribute.
      ViewLights open = f.lights;
      for (int& first : open.shadow) first = -1;
      for (int& first : open.directionalShadow) first = -1;
      EXPECT_LT(ref.contributing + 100,
                shadeReference(f.encoded, f.intrinsics, open, f.ambient, 0).contributing);
      for (const std::string name : {"deferred", "deferred-stencil"})
        for (int lanes : {1, 16}) {
          const std::string what = name + " lanes " + std::to_string(lanes) + " " +
                                   toString(format) + " taps " + std::to_string(taps);
          const FrameResult atlas =
              rendered(s, test::cachedTechnique(name, configFor(f, lanes, ShadowStorage::Atlas)));
          const FrameResult own = rendered(
              s, test::cachedTechnique(name, configFor(f, lanes, ShadowStorage::PerLight)));
          ASSERT_EQ(atlas.image.size(), own.image.size());
          size_t differing = 0;
          for (size_t i = 0; i < own.image.size(); ++i) differing += own.image[i] != atlas.image[i];
          EXPECT_EQ(differing, 0u) << what;
          const ErrorStats e =
              compareToReference(own.image, ref, test::kFp32RelativeTolerance * ref.peak);
          EXPECT_LE(e.maxRelPeak, 1e-4) << what;
          ASSERT_TRUE(own.assignment) << what;
          EXPECT_EQ(countMissedContributions(*own.assignment, f.encoded, f.intrinsics, f.lights, 0),
                    0u)
              << what;
          // The atlas path draws nothing itself; per-light: the directional pass, the point
          // and the spot light's (the off-screen caster has no launch and draws no map).
          EXPECT_FALSE(atlas.shadowUse) << what;
          ASSERT_TRUE(own.shadowUse) << what;
          EXPECT_EQ(own.shadowUse->passes, 3) << what;
          const PerLightShadowMaps& maps = *s.perLight;
          const uint64_t point = maps.passOf(f.lights.shadow[0]).layout.bytes();
          const uint64_t spot = maps.passOf(f.lights.shadow[1]).layout.bytes();
          const uint64_t sun = maps.directionalPass()->layout.bytes();
          EXPECT_EQ(own.shadowUse->writtenBytes, point + spot + sun) << what;
          EXPECT_EQ(own.shadowUse->residentBytes, maps.residentBytes()) << what;
          EXPECT_EQ(maps.residentBytes(), std::max({point, spot, sun})) << what;
          EXPECT_LT(maps.residentBytes(), s.atlas->layout.bytes()) << what;
          EXPECT_GT(own.shadowUse->trianglesDrawn, 0u) << what;
          int writes = 0;
          for (const KernelTime& k : own.kernels)
            writes += k.name == "shadow_write" ? k.launches : 0;
          EXPECT_EQ(writes, 3) << what;
        }
    }
}

TEST(ShadowStorage, OtherTechniquesRefusePerLight) {
  const StoredFrame s = shadowedFrame(litFloorAndBox(), 1, GBufferFormat::FP32);
  for (const std::string& name : techniqueNames()) {
    if (findTechnique(name).reusesShadowMaps) continue;
    try {
      createTechnique(name, test::context(), configFor(s.frame, 1, ShadowStorage::PerLight));
      FAIL() << name << " took --shadow-storage per-light";
    } catch (const Error& e) {
      EXPECT_EQ(std::string(e.what()), shadowStorageRefusal(name));
      EXPECT_NE(std::string(e.what()).find("needs every map resident"), std::string::npos);
    }
  }
  EXPECT_TRUE(findTechnique("deferred").reusesShadowMaps);
  EXPECT_TRUE(findTechnique("deferred-stencil").reusesShadowMaps);
}

TEST(ShadowStorage, PerLightWithoutTheScenesMapsIsRefused) {
  const StoredFrame s = shadowedFrame(litFloorAndBox(), 1, GBufferFormat::FP32);
  Technique& t = test::cachedTechnique("deferred", configFor(s.frame, 1, ShadowStorage::PerLight));
  try {
    rendered(s, t, false);
    FAIL() << "per-light storage shaded without the frame's per-light maps";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("per-light"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace ts
