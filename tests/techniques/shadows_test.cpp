// Shading with the shadow maps (kernels/shadows.h, docs/shadows.md): every G-buffer technique,
// layout and lanes width against the double reference, which samples the same maps; a light
// enclosed by a box gives exactly 0, a light whose map holds no occluder its unshadowed image
// exactly (a point light over a floor: no crack along the cube's seams, for every filter); a box
// over a floor shadows the floor where the analytic shadow is (away from its outline); the
// reference's shadow hook records the maps' factors and shades with an override.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "raster/shadow_maps.h"
#include "reference/error_metrics.h"
#include "reference_check.h"
#include "render/frame_setup.h"
#include "scene/mesh_builder.h"
#include "scene/scene_features.h"
#include "scene/scene_loader.h"
#include "shading/shading_cpu.h"
#include "techniques/technique.h"
#include "test_support.h"
#include "test_scenes.h"
#include "util/error.h"

namespace ts {
namespace {

constexpr float kFloor = 10.0f;  // the floor spans [-kFloor, kFloor] in x and z
// A box floating over the floor (its shadow is detached from it).
const glm::vec3 kBoxLo(-1.0f, 1.0f, -1.0f), kBoxHi(1.0f, 2.0f, 1.0f);

Scene floorScene(bool withBox, glm::dvec3 eye) {
  Scene s;
  s.name = withBox ? "floor-and-box" : "floor";
  s.ambient = glm::vec3(0.0f);  // a pixel is the sum of its lights' contributions
  MeshBuilder b(s);
  const uint32_t m = b.addMaterial(Material{});
  test::addFloor(b, kFloor, m);
  if (withBox) b.box(kBoxLo, kBoxHi, m, true);
  s.cameraPath.push_back(
      SceneCamera::lookAt(eye, {0.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, 1.2f, 0.1f, 100.0f));
  return s;
}

SceneLight casting(SceneLight l, bool casts = true) {
  l.castsShadow = casts;
  return l;
}

struct ShadowedFrame {
  PreparedFrame frame;
  std::shared_ptr<const ShadowAtlas> atlas;
};

// The scene's frame 0 with the maps of its shadow-casting lights attached, as `render` does.
ShadowedFrame shadowedFrame(const Scene& scene, GBufferFormat format, int taps, int width = 96,
                            int height = 64, float biasSlope = 1.5f) {
  ShadowedFrame s;
  const SceneFeatures features = analyzeScene(scene, ShadingModel::BlinnPhong);
  s.frame = prepareFrame(scene, 0, width, height, format, features);
  if (!features.shadows) return s;
  const ShadowAtlasLayout layout =
      planShadowAtlas(scene.lights, scene.bounds(), s.frame.camera, ShadowAtlasOptions{},
                      viewGeometryBounds(s.frame.gbuffer, s.frame.camera));
  s.atlas = std::make_shared<ShadowAtlas>(drawShadowAtlas(scene, layout, 1));
  ShadowSampling sampling;
  sampling.taps = taps;
  sampling.biasSlope = biasSlope;
  attachShadowMaps(s.atlas, scene.lights, s.frame.camera.viewFromWorld, sampling, s.frame.lights);
  return s;
}

TechniqueConfig configFor(const PreparedFrame& f, int lanes) {
  TechniqueConfig config;
  config.features = f.features;
  config.format = f.encoded.format;
  config.lanes = lanes;
  return config;
}

std::vector<glm::vec4> image(const PreparedFrame& f, const std::string& technique, int lanes) {
  return test::renderOnly(f, test::cachedTechnique(technique, configFor(f, lanes)), false).image;
}

// The box over the floor lit by a point, a spot and a directional light that cast shadows and a
// point light that casts none.
Scene litFloorAndBox() {
  Scene s = floorScene(true, {0.0, 6.0, 9.0});
  s.lights.push_back(casting(SceneLight::point({1.5, 4.0, 0.5}, glm::vec3(8.0f), 20.0f)));
  s.lights.push_back(casting(SceneLight::spot({-3.0, 5.0, 2.0}, {0.5f, -1.0f, -0.3f},
                                              glm::vec3(10.0f), 20.0f, 0.3f, 0.7f)));
  s.lights.push_back(casting(SceneLight::directional({-0.3f, -1.0f, -0.4f}, glm::vec3(0.5f))));
  s.lights.push_back(SceneLight::point({4.0, 1.0, 4.0}, glm::vec3(2.0f), 8.0f));
  return s;
}

TEST(Shadows, EveryTechniqueLayoutAndLanesMatchTheReference) {
  const Scene scene = litFloorAndBox();
  for (GBufferFormat format : {GBufferFormat::FP32, GBufferFormat::FP16, GBufferFormat::PACKED}) {
    const ShadowedFrame s = shadowedFrame(scene, format, 3);
    const PreparedFrame& f = s.frame;
    ASSERT_TRUE(f.features.shadows);
    ASSERT_TRUE(f.lights.hasShadows());
    const ReferenceImage ref = shadeReference(f.encoded, f.intrinsics, f.lights, f.ambient, 0);
    // The shadows are there: the unshadowed reference has more contributing pairs.
    ViewLights open = f.lights;
    for (int& first : open.shadow) first = -1;
    for (int& first : open.directionalShadow) first = -1;
    const ReferenceImage unshadowed = shadeReference(f.encoded, f.intrinsics, open, f.ambient, 0);
    EXPECT_LT(ref.contributing + 100, unshadowed.contributing) << toString(format);
    for (const std::string& name : gbufferTechniqueNames()) {
      for (int lanes : {1, 4, 8, 16}) {
        if (format != GBufferFormat::FP32 && (lanes == 4 || lanes == 8)) continue;
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

// The reference's shadow hook (the maps against exact visibility, docs/shadows.md): it records
// the maps' factors without changing the image, and an override of every pair shades with it.
TEST(Shadows, TheReferenceHookRecordsTheFactorsAndTakesAnOverride) {
  const ShadowedFrame s = shadowedFrame(litFloorAndBox(), GBufferFormat::FP32, 1);  // filter none
  const PreparedFrame& f = s.frame;
  const ReferenceImage ref = shadeReference(f.encoded, f.intrinsics, f.lights, f.ambient, 0);
  ReferenceShadowHook hook;
  const ReferenceImage hooked = shadeReference(f.encoded, f.intrinsics, f.lights, f.ambient, 0, 0,
                                               {}, ReferencePositions::FromDepth, &hook);
  EXPECT_EQ(compareReferences(hooked, ref, 0.0).maxAbs, 0.0);
  // Slots: the point, the spot, the unshadowed point, then the directional light.
  ASSERT_EQ(hook.factors.size(), 4u);
  EXPECT_TRUE(hook.factors[2].empty());
  for (size_t slot : {0u, 1u, 3u}) {
    ASSERT_EQ(hook.factors[slot].size(), f.encoded.pixelCount()) << slot;
    size_t lit = 0, shadowed = 0, other = 0;
    for (double v : hook.factors[slot]) {
      lit += v == 1.0;
      shadowed += v == 0.0;
      other += !std::isnan(v) && v != 0.0 && v != 1.0;
    }
    EXPECT_GT(lit, 100u) << slot;
    EXPECT_GT(shadowed, 10u) << slot;
    EXPECT_EQ(other, 0u) << slot;  // one tap: 0 or 1
  }
  // Every pair overridden lit: the unshadowed image exactly.
  ViewLights open = f.lights;
  for (int& first : open.shadow) first = -1;
  for (int& first : open.directionalShadow) first = -1;
  const ReferenceImage unshadowed = shadeReference(f.encoded, f.intrinsics, open, f.ambient, 0);
  ReferenceShadowHook allLit;
  allLit.visibility.assign(4, std::vector<uint8_t>(f.encoded.pixelCount(), 1));
  const ReferenceImage lit = shadeReference(f.encoded, f.intrinsics, f.lights, f.ambient, 0, 0, {},
                                            ReferencePositions::FromDepth, &allLit);
  EXPECT_EQ(compareReferences(lit, unshadowed, 0.0).maxAbs, 0.0);
  EXPECT_GT(compareReferences(ref, unshadowed, 0.0).maxAbs, 0.0);
  // Overridden with the maps' own answers: the map-shaded image exactly (agreeing pairs, no
  // error).
  ReferenceShadowHook same;
  same.visibility.resize(4);
  for (size_t slot : {0u, 1u, 3u})
    for (double v : hook.factors[slot])
      same.visibility[slot].push_back(std::isnan(v) ? 2 : uint8_t(v));
  const ReferenceImage agreeing = shadeReference(f.encoded, f.intrinsics, f.lights, f.ambient, 0, 0,
                                                 {}, ReferencePositions::FromDepth, &same);
  EXPECT_EQ(compareReferences(agreeing, ref, 0.0).maxAbs, 0.0);
}

// The receivers' slack (reference.h, ReceiverRounding; issue #18): the forward techniques decide
// a shadow test at their fragment's position, a rounding away from the reference's. Emulated here
// with receivers moved along their rays by 1e-3 of their position (the depth scaled: at most
// ~1.2e-2 here), inside a rounding box made that wide (W = 3e4: a half-side of ~2.9e-2): the image
// shaded with the moved receivers' shadow answers differs from the reference's where a test
// flipped, and lies within the slack everywhere; the slack leaves the reference's image unchanged.
TEST(Shadows, ReceiverSlackCoversShadowTestsFlippedWithinRounding) {
  const ShadowedFrame s = shadowedFrame(litFloorAndBox(), GBufferFormat::FP32, 1);  // filter none
  const PreparedFrame& f = s.frame;
  ReferenceShadowHook here;
  const ReferenceImage ref = shadeReference(f.encoded, f.intrinsics, f.lights, f.ambient, 0, 0, {},
                                            ReferencePositions::FromDepth, &here);
  EncodedGBuffer moved = f.encoded;
  for (float& d : moved.depth) d *= 1.0f + 1e-3f;
  ReferenceShadowHook there;
  shadeReference(moved, f.intrinsics, f.lights, f.ambient, 0, 0, {}, ReferencePositions::FromDepth,
                 &there);
  // The moved receivers' answers (one tap: 0 or 1) at the reference's own receivers.
  ReferenceShadowHook answers;
  answers.visibility.resize(there.factors.size());
  size_t flipped = 0;
  for (size_t slot = 0; slot < there.factors.size(); ++slot)
    for (size_t i = 0; i < there.factors[slot].size(); ++i) {
      const double v = there.factors[slot][i];
      answers.visibility[slot].push_back(std::isnan(v) ? 2 : uint8_t(v));
      flipped += !std::isnan(v) && !std::isnan(here.factors[slot][i]) && v != here.factors[slot][i];
    }
  const ReferenceImage forwardLike = shadeReference(f.encoded, f.intrinsics, f.lights, f.ambient, 0,
                                                    0, {}, ReferencePositions::FromDepth, &answers);
  ASSERT_GT(flipped, 0u) << "no shadow test flipped: the case does not test the slack";
  ReceiverRounding wide;
  wide.worldMagnitude = 3e4;
  const ReferenceImage slacked = shadeReference(f.encoded, f.intrinsics, f.lights, f.ambient, 0, 0,
                                                {}, ReferencePositions::FromDepth, nullptr, &wide);
  EXPECT_EQ(compareReferences(slacked, ref, 0.0).maxAbs, 0.0);
  ASSERT_EQ(slacked.receiverSlack.size(), f.encoded.pixelCount());
  EXPECT_GE(slacked.ambiguousShadowPairs, flipped);
  std::vector<glm::vec4> image;
  for (const glm::dvec3& c : forwardLike.rgb) image.emplace_back(glm::vec3(c), 1.0f);
  const ErrorStats strict = compareToReference(image, slacked, 0.0);
  EXPECT_GT(strict.maxRelPeak, 1e-3) << flipped << " flipped pair(s)";
  const ErrorStats allowed = compareToReference(image, slacked, 0.0, ReceiverSlack::Allow);
  EXPECT_LE(allowed.maxRelPeak, 1e-6);  // the float image's rounding only
  EXPECT_TRUE(allowed.receiverSlack);
  EXPECT_GE(allowed.slackPixels, 1u);
  // The true rounding box (W: the scene's own) is far smaller: few pairs, if any, are ambiguous.
  ReceiverRounding small;
  small.worldMagnitude = 10.0;
  const ReferenceImage own = shadeReference(f.encoded, f.intrinsics, f.lights, f.ambient, 0, 0, {},
                                            ReferencePositions::FromDepth, nullptr, &small);
  EXPECT_LT(own.ambiguousShadowPairs, slacked.ambiguousShadowPairs);
  std::cout << "[ receiver slack ] " << flipped << " flipped pair(s), "
            << slacked.ambiguousShadowPairs << " ambiguous in the wide box, "
            << own.ambiguousShadowPairs << " in W = 10's; strict " << strict.maxRelPeak
            << " of the peak, allowed " << allowed.maxRelPeak << "\n";
}

// Kernels built without TS_HAS_SHADOWS would shade a shadow-casting light unshadowed: refused.
TEST(Shadows, KernelsWithoutShadowsRefuseAShadowedFrame) {
  const ShadowedFrame s = shadowedFrame(litFloorAndBox(), GBufferFormat::FP32, 1, 32, 24);
  TechniqueConfig config = configFor(s.frame, 1);
  config.features.shadows = false;
  try {
    test::renderOnly(s.frame, *createTechnique("tiled", test::context(), config), false);
    FAIL() << "kernels without shadows shaded a frame with shadow-casting lights";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("shadow-casting"), std::string::npos) << e.what();
  }
}

// A light inside a closed box lights nothing the camera sees: its contribution is exactly 0, so
// the image is the one without it, bit for bit (x + 0 = x); unshadowed, it lights the floor.
TEST(Shadows, AnEnclosedLightGivesExactlyZero) {
  Scene without = floorScene(true, {0.0, 6.0, 9.0});
  without.lights.push_back(casting(SceneLight::point({4.0, 5.0, 3.0}, glm::vec3(8.0f), 30.0f)));
  Scene with = without;
  with.lights.push_back(casting(SceneLight::point({0.2, 1.5, -0.1}, glm::vec3(8.0f), 30.0f)));
  Scene open = with;
  open.lights.back().castsShadow = false;
  const ShadowedFrame a = shadowedFrame(without, GBufferFormat::FP32, 1);
  const ShadowedFrame b = shadowedFrame(with, GBufferFormat::FP32, 1);
  const ShadowedFrame c = shadowedFrame(open, GBufferFormat::FP32, 1);
  for (const std::string& name : gbufferTechniqueNames())
    for (int lanes : {1, 16}) {
      const std::vector<glm::vec4> expected = image(a.frame, name, lanes);
      EXPECT_TRUE(image(b.frame, name, lanes) == expected) << name << " lanes " << lanes;
      EXPECT_FALSE(image(c.frame, name, lanes) == expected) << name << " lanes " << lanes;
    }
  // The reference agrees: nothing of the enclosed light reaches a pixel.
  const PreparedFrame& f = b.frame;
  const ReferenceImage withRef = shadeReference(f.encoded, f.intrinsics, f.lights, f.ambient, 0);
  const PreparedFrame& g = a.frame;
  const ReferenceImage withoutRef = shadeReference(g.encoded, g.intrinsics, g.lights, g.ambient, 0);
  EXPECT_EQ(withRef.contributing, withoutRef.contributing);
}

// A point light low over an open floor: the floor crosses five of its cube's faces, and no
// occluder stands anywhere, so every pixel is lit with a factor of exactly 1 by every filter --
// the image is the unshadowed one bit for bit (no acne, no crack along a seam between faces).
TEST(Shadows, AnOpenFloorUnderAPointLightIsLitAcrossTheCubeSeams) {
  Scene shadowed = floorScene(false, {0.0, 9.0, 7.0});
  shadowed.lights.push_back(casting(SceneLight::point({0.3, 1.2, -0.2}, glm::vec3(4.0f), 40.0f)));
  Scene open = shadowed;
  open.lights.back().castsShadow = false;
  const ShadowedFrame plain = shadowedFrame(open, GBufferFormat::FP32, 1, 160, 96);
  for (int taps : {1, 2, 3, 5}) {
    const ShadowedFrame s = shadowedFrame(shadowed, GBufferFormat::FP32, taps, 160, 96);
    // The floor's pixels sample five faces (every one but +Y).
    std::vector<int> facesSampled(6, 0);
    const glm::dmat4 worldFromView = glm::inverse(s.frame.camera.viewFromWorld);
    const CameraIntrinsics& in = s.frame.intrinsics;
    for (int y = 0; y < in.height; ++y)
      for (int x = 0; x < in.width; ++x) {
        const float depth = s.frame.encoded.depth[size_t(y) * size_t(in.width) + size_t(x)];
        if (depth <= 0.0f) continue;
        const glm::dvec3 p(worldFromView * glm::dvec4(glm::dvec3(shading_f::ts_view_position(
                                                          x, y, depth, in.tanHalfFovX,
                                                          in.tanHalfFovY, in.width, in.height)),
                                                      1.0));
        const glm::dvec3 d = p - glm::dvec3(0.3, 1.2, -0.2);
        int axis = std::abs(d.x) >= std::abs(d.y) && std::abs(d.x) >= std::abs(d.z) ? 0
                   : std::abs(d.y) >= std::abs(d.z)                                 ? 1
                                                                                    : 2;
        ++facesSampled[size_t(2 * axis + (d[axis] < 0.0 ? 1 : 0))];
      }
    for (int face : {0, 1, 3, 4, 5}) EXPECT_GT(facesSampled[size_t(face)], 0) << face;
    for (const char* name : {"tiled", "deferred", "clustered"})
      for (int lanes : {1, 16})
        EXPECT_TRUE(image(s.frame, name, lanes) == image(plain.frame, name, lanes))
            << name << " lanes " << lanes << " filter " << shadowFilterName(taps);
  }
}

// Whether the ray p + t l (t > 0) meets the box [lo - m, hi + m].
bool rayMeetsBox(glm::dvec3 p, glm::dvec3 l, double m) {
  double t0 = 0.0, t1 = 1e30;
  for (int k = 0; k < 3; ++k) {
    const double lo = double(kBoxLo[k]) - m, hi = double(kBoxHi[k]) + m;
    if (l[k] == 0.0) {
      if (p[k] < lo || p[k] > hi) return false;
      continue;
    }
    double a = (lo - p[k]) / l[k], b = (hi - p[k]) / l[k];
    if (a > b) std::swap(a, b);
    t0 = std::max(t0, a);
    t1 = std::min(t1, b);
  }
  return t0 <= t1;
}

// A directional light over the floating box: a floor pixel whose ray to the light meets the box
// (shrunk by a margin) gets exactly 0, one whose ray misses it (grown by the margin) gets light.
// The margin (0.1, ten texels of the fitted map) leaves out the outline, where the map's texels
// and the bias decide.
TEST(Shadows, TheBoxShadowsTheFloorWhereTheAnalyticShadowIs) {
  Scene scene = floorScene(true, {0.0, 7.0, 8.0});
  const glm::vec3 travel = glm::normalize(glm::vec3(-0.3f, -1.0f, 0.6f));
  scene.lights.push_back(casting(SceneLight::directional(travel, glm::vec3(1.0f))));
  const glm::dvec3 towards = -glm::dvec3(travel);
  constexpr double kMargin = 0.1;
  for (int taps : {1, 3}) {
    const ShadowedFrame s = shadowedFrame(scene, GBufferFormat::FP32, taps, 160, 96);
    const CameraIntrinsics& in = s.frame.intrinsics;
    const glm::dmat4 worldFromView = glm::inverse(s.frame.camera.viewFromWorld);
    for (const char* name : {"tiled", "deferred-stencil"}) {
      const std::vector<glm::vec4> img = image(s.frame, name, 1);
      size_t shadowed = 0, lit = 0, wrong = 0;
      for (int y = 0; y < in.height; ++y)
        for (int x = 0; x < in.width; ++x) {
          const size_t i = size_t(y) * size_t(in.width) + size_t(x);
          const float depth = s.frame.encoded.depth[i];
          if (depth <= 0.0f) continue;
          const glm::dvec3 p(worldFromView * glm::dvec4(glm::dvec3(shading_f::ts_view_position(
                                                            x, y, depth, in.tanHalfFovX,
                                                            in.tanHalfFovY, in.width, in.height)),
                                                        1.0));
          if (std::abs(p.y) > 1e-3) continue;  // the box's pixels
          const bool inside = rayMeetsBox(p, towards, -kMargin);
          const bool outside = !rayMeetsBox(p, towards, kMargin);
          if (!inside && !outside) continue;  // near the outline
          const bool dark = img[i].x == 0.0f && img[i].y == 0.0f && img[i].z == 0.0f;
          (inside ? shadowed : lit)++;
          wrong += inside != dark;
        }
      EXPECT_EQ(wrong, 0u) << name << " filter " << shadowFilterName(taps);
      EXPECT_GT(shadowed, 100u) << name;
      EXPECT_GT(lit, 1000u) << name;
    }
  }
}

// alphaMode MASK in the shadow maps: a leaf over the floor (y = 1.5, [-2, 2] in x and z) whose
// texture (2x1, NEAREST) has alpha 0.2 where x < 0 and 1 where x > 0, under a directional light.
// A floor pixel whose ray to the light meets the covered half (shrunk by a margin) is dark, one
// whose ray passes the cut-out half (or misses the leaf by the margin) is lit; the same image for
// 1 and 3 rasterizer threads. BLEND follows --blend's policy: as-mask the same image, as-opaque
// the whole leaf casts.
constexpr float kLeafY = 1.5f, kLeaf = 2.0f;
Scene floorAndLeaf(AlphaMode mode) {
  Scene s = floorScene(false, {0.0, 7.0, 8.0});
  s.name = "floor-and-leaf";
  MeshBuilder b(s);
  Material leaf;
  leaf.alphaMode = mode;
  leaf.diffuseTexture = leaf.baseColorTexture = 0;
  const uint32_t m = b.addMaterial(leaf);
  s.textures.push_back(ts::test::halfCutOutTexture());
  b.quad({-kLeaf, kLeafY, kLeaf}, {kLeaf, kLeafY, kLeaf}, {kLeaf, kLeafY, -kLeaf},
         {-kLeaf, kLeafY, -kLeaf}, m);  // u runs along +x
  s.lights.push_back(casting(
      SceneLight::directional(glm::normalize(glm::vec3(-0.3f, -1.0f, 0.2f)), glm::vec3(1.0f))));
  return s;
}

struct LeafShadow {
  size_t shadowed = 0, lit = 0, underCutOut = 0, wrong = 0;
};

// `cutOut`: whether the x < 0 half lets the light through.
LeafShadow leafShadow(const ShadowedFrame& s, const std::vector<glm::vec4>& img, bool cutOut) {
  constexpr double kMargin = 0.1;
  const glm::dvec3 towards = -glm::dvec3(glm::normalize(glm::vec3(-0.3f, -1.0f, 0.2f)));
  const CameraIntrinsics& in = s.frame.intrinsics;
  const glm::dmat4 worldFromView = glm::inverse(s.frame.camera.viewFromWorld);
  LeafShadow c;
  for (int y = 0; y < in.height; ++y)
    for (int x = 0; x < in.width; ++x) {
      const size_t i = size_t(y) * size_t(in.width) + size_t(x);
      const float depth = s.frame.encoded.depth[i];
      if (depth <= 0.0f) continue;
      const glm::dvec3 p(worldFromView * glm::dvec4(glm::dvec3(shading_f::ts_view_position(
                                                        x, y, depth, in.tanHalfFovX, in.tanHalfFovY,
                                                        in.width, in.height)),
                                                    1.0));
      if (std::abs(p.y) > 1e-3) continue;  // the leaf's pixels
      const glm::dvec3 q = p + (double(kLeafY) - p.y) / towards.y * towards;
      const double ax = std::abs(q.x), az = std::abs(q.z);
      const bool outside = ax > kLeaf + kMargin || az > kLeaf + kMargin;
      const bool inside = ax < kLeaf - kMargin && az < kLeaf - kMargin && ax > kMargin;
      if (!inside && !outside) continue;  // near the outline or the split
      const bool underCutOut = inside && q.x < 0.0 && cutOut;
      const bool shadowed = inside && !underCutOut;
      const bool dark = img[i].x == 0.0f && img[i].y == 0.0f && img[i].z == 0.0f;
      (shadowed ? c.shadowed : c.lit)++;
      c.underCutOut += underCutOut;
      c.wrong += shadowed != dark;
    }
  return c;
}

TEST(Shadows, AMaskedLeafShadowsTheFloorUnderItsCoveredHalfOnly) {
  const Scene scene = floorAndLeaf(AlphaMode::Mask);
  const ShadowedFrame s = shadowedFrame(scene, GBufferFormat::FP32, 1, 160, 96);
  ASSERT_TRUE(s.frame.lights.hasShadows());
  const std::vector<glm::vec4> img = image(s.frame, "tiled", 1);
  const LeafShadow c = leafShadow(s, img, true);
  EXPECT_EQ(c.wrong, 0u);
  EXPECT_GT(c.shadowed, 100u);
  EXPECT_GT(c.underCutOut, 100u);
  // The maps do not depend on the rasterizer's thread count.
  const ShadowAtlas three = drawShadowAtlas(scene, s.atlas->layout, 3);
  EXPECT_TRUE(three.depth == s.atlas->depth);
  // BLEND as the scene's --blend policy made it, the same materials as the G-buffer's.
  Scene asMask = floorAndLeaf(AlphaMode::Blend);
  applyBlendPolicy(asMask, BlendPolicy::AsMask);
  const ShadowedFrame m = shadowedFrame(asMask, GBufferFormat::FP32, 1, 160, 96);
  EXPECT_TRUE(image(m.frame, "tiled", 1) == img);
  Scene asOpaque = floorAndLeaf(AlphaMode::Blend);
  applyBlendPolicy(asOpaque, BlendPolicy::AsOpaque);
  const ShadowedFrame o = shadowedFrame(asOpaque, GBufferFormat::FP32, 1, 160, 96);
  const LeafShadow co = leafShadow(o, image(o.frame, "tiled", 1), false);
  EXPECT_EQ(co.wrong, 0u);
  EXPECT_GT(co.shadowed, c.shadowed + 100u);
}

}  // namespace
}  // namespace ts
