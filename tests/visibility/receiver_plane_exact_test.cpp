// The receiver-plane depth bias against exact visibility (docs/shadows.md): on the box floating
// over the floor, at the same map size and filter, the maps sampled with the receiver plane get
// no more (pixel, light) pairs wrong than with the plain bias (the default constant + slope), and
// fewer at a small constant, where the plain bias shows acne.
#include <gtest/gtest.h>

#include <iostream>
#include <memory>
#include <string>

#include "raster/shadow_maps.h"
#include "render/frame_setup.h"
#include "scene/scene_features.h"
#include "test_scenes.h"
#include "visibility/shadow_error.h"

namespace ts {
namespace {

SceneLight casting(SceneLight l) {
  l.castsShadow = true;
  return l;
}

// The floor and box under a casting point light and a slanted sun, 96x54.
Scene boxOverFloor() {
  Scene s = test::floorAndBox(glm::vec3(0.0f));
  s.lights.push_back(casting(SceneLight::point({1.5, 4.0, 0.5}, glm::vec3(8.0f), 20.0f)));
  s.lights.push_back(casting(SceneLight::directional({-0.6f, -1.0f, 0.3f}, glm::vec3(0.5f))));
  return s;
}

struct Wrong {
  uint64_t pairs = 0, wrong = 0;
};

Wrong wrongPairs(const Scene& scene, int mapSize, int taps, const std::string& bias) {
  const SceneFeatures features = analyzeScene(scene, ShadingModel::BlinnPhong);
  PreparedFrame f = prepareFrame(scene, 0, 96, 54, GBufferFormat::FP32, features);
  ShadowAtlasOptions options;
  options.mapSize = mapSize;
  const ShadowAtlasLayout layout = planShadowAtlas(scene.lights, scene.bounds(), f.camera, options,
                                                   viewGeometryBounds(f.gbuffer, f.camera));
  auto atlas = std::make_shared<ShadowAtlas>(drawShadowAtlas(scene, layout, 1));
  ShadowSampling sampling;
  sampling.taps = taps;
  parseShadowBias(bias, sampling);
  attachShadowMaps(atlas, scene.lights, f.camera.viewFromWorld, sampling, f.lights);
  const ExactVisibilityResult r = measureAgainstExactVisibility(scene, f, f.encoded);
  const nlohmann::json& w = r.stats.at("wrong_pairs");
  Wrong out;
  out.pairs = w.at("pairs").get<uint64_t>();
  out.wrong = w.at("false_shadow").get<uint64_t>() + w.at("light_leak").get<uint64_t>();
  return out;
}

TEST(ReceiverPlaneExact, NoMoreWrongPairsThanThePlainBias) {
  const Scene scene = boxOverFloor();
  for (int mapSize : {64, 256})
    for (int taps : {1, 3, 5}) {
      const std::string what = std::to_string(mapSize) + "^2 " + shadowFilterName(taps);
      const Wrong plain = wrongPairs(scene, mapSize, taps, "1.5,1.5");
      const Wrong receiver = wrongPairs(scene, mapSize, taps, "receiver,0.5");
      const Wrong plainSmall = wrongPairs(scene, mapSize, taps, "0.5,0");
      std::cout << "[ wrong pairs ] " << what << ": plain 1.5,1.5 " << plain.wrong
                << ", plain 0.5,0 " << plainSmall.wrong << ", receiver,0.5 " << receiver.wrong
                << " of " << plain.pairs << "\n";
      ASSERT_GT(plain.pairs, 1000u) << what;
      EXPECT_EQ(receiver.pairs, plain.pairs) << what;  // the same pairs count: only the test moves
      EXPECT_LE(receiver.wrong, plain.wrong) << what;
      EXPECT_LT(receiver.wrong, plainSmall.wrong) << what;
    }
}

}  // namespace
}  // namespace ts
