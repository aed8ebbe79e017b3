// The receiver-plane depth bias (--shadow-bias receiver,C; kernels/shadows.h, docs/shadows.md):
// every G-buffer technique, layout and lanes width samples the maps as the double reference does;
// a flat floor under a grazing sun, and under a low point light with pcf5 (its cube's corners),
// shows no acne with it at a constant bias where the plain bias of that constant does.
#include <gtest/gtest.h>

#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "raster/shadow_maps.h"
#include "reference_check.h"
#include "render/frame_setup.h"
#include "scene/mesh_builder.h"
#include "scene/scene_features.h"
#include "techniques/technique.h"
#include "test_scenes.h"
#include "test_support.h"

namespace ts {
namespace {

SceneLight casting(SceneLight l) {
  l.castsShadow = true;
  return l;
}

// Frame 0 of `scene` with its casters' maps attached, sampled with `bias` (--shadow-bias's text).
PreparedFrame shadowedFrame(const Scene& scene, GBufferFormat format, int taps,
                            const std::string& bias, int width = 96, int height = 54) {
  const SceneFeatures features = analyzeScene(scene, ShadingModel::BlinnPhong);
  PreparedFrame f = prepareFrame(scene, 0, width, height, format, features);
  const ShadowAtlasLayout layout =
      planShadowAtlas(scene.lights, scene.bounds(), f.camera, ShadowAtlasOptions{},
                      viewGeometryBounds(f.gbuffer, f.camera));
  auto atlas = std::make_shared<ShadowAtlas>(drawShadowAtlas(scene, layout, 1));
  ShadowSampling sampling;
  sampling.taps = taps;
  parseShadowBias(bias, sampling);
  attachShadowMaps(atlas, scene.lights, f.camera.viewFromWorld, sampling, f.lights);
  return f;
}

TechniqueConfig configFor(const PreparedFrame& f, int lanes) {
  TechniqueConfig config;
  config.features = f.features;
  config.format = f.encoded.format;
  config.lanes = lanes;
  return config;
}

std::vector<glm::vec4> image(const PreparedFrame& f, const std::string& technique) {
  return test::renderOnly(f, test::cachedTechnique(technique, configFor(f, 1)), false).image;
}

// The box over the floor under a casting point, spot and directional light.
Scene litFloorAndBox() {
  Scene s = test::floorAndBox(glm::vec3(0.0f));
  s.lights.push_back(casting(SceneLight::point({1.5, 4.0, 0.5}, glm::vec3(8.0f), 20.0f)));
  s.lights.push_back(casting(SceneLight::spot({-3.0, 5.0, 2.0}, {0.5f, -1.0f, -0.3f},
                                              glm::vec3(10.0f), 20.0f, 0.3f, 0.7f)));
  s.lights.push_back(casting(SceneLight::directional({-0.3f, -1.0f, -0.4f}, glm::vec3(0.5f))));
  return s;
}

TEST(ShadowReceiverPlane, EveryTechniqueLayoutAndLanesMatchTheReference) {
  const Scene scene = litFloorAndBox();
  for (GBufferFormat format : {GBufferFormat::FP32, GBufferFormat::FP16, GBufferFormat::PACKED}) {
    const PreparedFrame f = shadowedFrame(scene, format, 5, "receiver,0.25");
    // fp16 and packed with lanes 1 only: each (layout, lanes) builds every technique's kernels.
    const std::vector<int> widths =
        format == GBufferFormat::FP32 ? std::vector<int>{1, 16} : std::vector<int>{1};
    const ReferenceImage ref = shadeReference(f.encoded, f.intrinsics, f.lights, f.ambient, 0);
    // The knob reaches the sampling: the plain bias of that constant shades differently.
    const PreparedFrame plain = shadowedFrame(scene, format, 5, "0.25,0");
    const ReferenceImage plainRef =
        shadeReference(plain.encoded, plain.intrinsics, plain.lights, plain.ambient, 0);
    EXPECT_GT(compareReferences(ref, plainRef, 0.0).maxAbs, 0.0) << toString(format);
    for (const std::string& name : gbufferTechniqueNames()) {
      for (int lanes : widths) {
        Technique& t = test::cachedTechnique(name, configFor(f, lanes));
        if (lanes > 1 && t.lanes() != lanes) continue;  // no lanes path: lanes 1 covers it
        const test::Checked c = test::renderAndCheck(f, t, ref);
        const std::string what = name + " lanes " + std::to_string(lanes) + " " + toString(format);
        EXPECT_EQ(c.missed, 0u) << what;
        EXPECT_LE(c.error.maxRelPeak, 1e-4) << what;
      }
    }
  }
}

// Pixels of `img` darker than `open` in some channel (a shadow where nothing occludes: acne).
size_t darkened(const std::vector<glm::vec4>& img, const std::vector<glm::vec4>& open) {
  size_t n = 0;
  for (size_t i = 0; i < img.size(); ++i)
    n += img[i].x < open[i].x || img[i].y < open[i].y || img[i].z < open[i].z;
  return n;
}

Scene openFloor(SceneLight light) {
  Scene s;
  s.name = "floor";
  s.ambient = glm::vec3(0.0f);
  MeshBuilder b(s);
  test::addFloor(b, 10.0f, b.addMaterial(Material{}));
  s.cameraPath.push_back(
      SceneCamera::lookAt({0.0, 9.0, 7.0}, {0.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, 1.2f, 0.1f, 100.0f));
  s.lights.push_back(casting(light));
  return s;
}

// Nothing occludes the floor, so every pixel's factor should be 1: with the receiver plane it
// is (the image is the unshadowed one bit for bit) at a constant bias of half a footprint, where
// the plain bias with that constant and no slope darkens many pixels (acne). The sun at
// 14 degrees over the floor (its depth changes by 4 footprints a texel); the point light low over
// the floor with pcf5, whose taps reach 2 texels off at the cube faces' corners.
TEST(ShadowReceiverPlane, AFlatFloorShowsNoAcneAtAConstantBias) {
  struct Case {
    const char* what;
    SceneLight light;
    int taps;
    size_t left;  // pixels still darkened with the receiver plane
  };
  const Case cases[] = {
      {"grazing sun", SceneLight::directional({-1.0f, -0.25f, 0.0f}, glm::vec3(1.0f)), 1, 0},
      // One pixel (3, 41: 3 of its 9 taps dark, the same at C = 0.25 and 0.5) is left, not yet
      // explained (docs/shadows.md, "Not done yet").
      {"grazing sun pcf3", SceneLight::directional({-1.0f, -0.25f, 0.0f}, glm::vec3(1.0f)), 3, 1},
      {"low point pcf5", SceneLight::point({0.3, 1.2, -0.2}, glm::vec3(4.0f), 40.0f), 5, 0}};
  for (const Case& c : cases) {
    Scene shadowed = openFloor(c.light);
    Scene open = shadowed;
    open.lights.back().castsShadow = false;
    const PreparedFrame none = prepareFrame(open, 0, 96, 54, GBufferFormat::FP32,
                                            analyzeScene(open, ShadingModel::BlinnPhong));
    const std::vector<glm::vec4> unshadowed = image(none, "tiled");
    const PreparedFrame plain = shadowedFrame(shadowed, GBufferFormat::FP32, c.taps, "0.5,0");
    const PreparedFrame receiver =
        shadowedFrame(shadowed, GBufferFormat::FP32, c.taps, "receiver,0.5");
    const size_t acne = darkened(image(plain, "tiled"), unshadowed);
    const size_t receiverAcne = darkened(image(receiver, "tiled"), unshadowed);
    std::cout << "[ acne ] " << c.what << ": plain 0.5,0 " << acne << " pixel(s), receiver,0.5 "
              << receiverAcne << " of " << unshadowed.size() << "\n";
    EXPECT_GT(acne, 20u) << c.what;
    EXPECT_LE(receiverAcne, c.left) << c.what;
  }
}

}  // namespace
}  // namespace ts
