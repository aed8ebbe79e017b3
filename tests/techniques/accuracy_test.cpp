// Accuracy knobs (issue: speed against error): each knob's error stays within the bound
// documented for it in docs/accuracy.md, on the built-in scenes; changing the culling test never
// changes the image beyond fp32 rounding and never misses a light.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <map>
#include <memory>
#include <random>

#include "reference/error_metrics.h"
#include "reference/reference.h"
#include "shading/shading_cpu.h"
#include "render/frame_setup.h"
#include "render/gbuffer_dump.h"
#include "scene/light_range.h"
#include "scene/scene_features.h"
#include "scene/scene_loader.h"
#include "techniques/technique.h"
#include "reference_check.h"
#include "test_support.h"
#include "util/error.h"

namespace ts {
namespace {

const int kWidth = 192, kHeight = 108;

// fp32 rounding, relative to the reference peak: the "exact" threshold (docs/accuracy.md).
constexpr double kExact = 2e-5;
// docs/accuracy.md's bounds of --math fast and native, on every built-in scene and variant.
constexpr double kFastMathBound = 2.5e-4;
constexpr double kNativeMathBound = 1e-3;

struct Knobs {
  GBufferFormat format = GBufferFormat::FP32;
  CullTest culling = CullTest::Rect;
  MathMode math = MathMode::Precise;
  int tile = 16;
  std::string technique = "tiled";
  int slices = 16;
};

FrameResult renderTiled(const PreparedFrame& f, const Knobs& k, bool assignment = false) {
  TechniqueConfig config;
  config.format = k.format;
  config.culling = k.culling;
  config.math = k.math;
  config.tileWidth = config.tileHeight = k.tile;
  config.clusterSlices = k.slices;
  auto technique = createTechnique(k.technique, test::context(), config);
  DeviceFrame frame = f.upload(test::context());
  FrameRequest request;
  request.wantAssignment = assignment;
  return technique->render(frame, request);
}

// Measured values go to the test report (--gtest_output=xml) in full precision.
std::string sci(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3e", v);
  return buf;
}

const Scene& scene(const std::string& name, const std::string& lights) {
  static std::map<std::string, Scene> cache;
  auto key = name + "/" + lights;
  auto it = cache.find(key);
  if (it == cache.end()) it = cache.emplace(key, makeBuiltinScene(name, lights, 1)).first;
  return it->second;
}

// Culling test: frustum planes and frustum boxes only remove tiles that no contribution reaches,
// so the image equals the default's (lists are in light index order either way: measured equal
// bit for bit; a removed light could only add a rounding-level amount) and no light is missed;
// and they do cull more (fewer list entries), else the knob would be no knob.
TEST(AccuracyKnobs, CullingTestNeverChangesTheImage) {
  for (const auto& [name, lights] : {std::pair{"street", "many"}, std::pair{"atrium", "mixed"}}) {
    PreparedFrame f = prepareFrame(scene(name, lights), 20, kWidth, kHeight, GBufferFormat::FP32);
    ReferenceImage ref = shadeReference(f.encoded, f.intrinsics, f.lights, f.ambient, 0);
    FrameResult rect = renderTiled(f, {});
    for (CullTest mode : {CullTest::Frustum, CullTest::Aabb}) {
      Knobs k;
      k.culling = mode;
      FrameResult r = renderTiled(f, k, true);
      EXPECT_EQ(countMissedContributions(*r.assignment, f.encoded, f.intrinsics, f.lights, 0), 0u)
          << name << " " << toString(mode);
      double maxDiff = 0.0;
      for (size_t i = 0; i < r.image.size(); ++i)
        for (int c = 0; c < 3; ++c)
          maxDiff = std::max(maxDiff, double(std::abs(r.image[i][c] - rect.image[i][c])));
      RecordProperty(std::string(name) + "_" + toString(mode), sci(maxDiff / ref.peak));
      EXPECT_LE(maxDiff, kExact * ref.peak) << name << " " << toString(mode);
      EXPECT_LE(r.counters.lightingComputations, rect.counters.lightingComputations);
    }
  }
}

// Storage precision: error against the reference shaded from the fp32 G-buffer.
double storageError(GBufferFormat format, const std::string& name, const std::string& lights) {
  PreparedFrame f = prepareFrame(scene(name, lights), 40, kWidth, kHeight, format);
  EncodedGBuffer fp32 = encode(f.gbuffer, GBufferFormat::FP32);
  ReferenceImage truth = shadeReference(fp32, f.intrinsics, f.lights, f.ambient, 0);
  Knobs k;
  k.format = format;
  return compareToReference(renderTiled(f, k).image, truth, 0.0).maxRelPeak;
}

TEST(AccuracyKnobs, Fp16StorageErrorWithinItsBound) {
  for (const auto& [name, lights] : {std::pair{"street", "many"}, std::pair{"atrium", "small"}}) {
    double e = storageError(GBufferFormat::FP16, name, lights);
    RecordProperty(std::string("fp16_") + name, sci(e));
    EXPECT_LE(e, 2e-3) << name;  // docs/accuracy.md: fp16 storage <= 0.2% of the peak
    EXPECT_GT(e, 1e-6) << name;  // it is lossy: a zero would mean fp32 was used
  }
}

// Packed storage (octahedral normals, unorm8 colours, shininess byte, half emissive): against the
// reference from the fp32 G-buffer. Per light, the shininess byte changes the specular lobe by at
// most d/e = 0.55% (d = 1.51%, the shininess bound), the unorm8 colours kd and ks by 0.5/255 =
// 0.2% of full scale, the normal (<= 4.5e-5 rad) the lobe by <= sqrt(s) e^-1/2 4.5e-5 (0.1% at
// s = 256) and the emission by 2^-11: docs/accuracy.md bounds the image at 1% of the peak.
TEST(AccuracyKnobs, PackedStorageErrorWithinItsBound) {
  for (const auto& [name, lights] : {std::pair{"street", "many"}, std::pair{"atrium", "small"}}) {
    double e = storageError(GBufferFormat::PACKED, name, lights);
    RecordProperty(std::string("packed_") + name, sci(e));
    EXPECT_LE(e, 1e-2) << name;  // docs/accuracy.md: packed storage <= 1% of the peak
    EXPECT_GT(e, storageError(GBufferFormat::FP16, name, lights)) << name;  // lossier than fp16
  }
}

// The kernels shade exactly what the packed layout stores: against the reference shaded from the
// same packed values (decodeSurface mirrors the kernels' decoder) the error is fp32 rounding, with
// no missed light, for the tile and the cluster techniques.
TEST(AccuracyKnobs, PackedKernelsShadeTheStoredValues) {
  PreparedFrame f =
      prepareFrame(scene("atrium", "mixed"), 30, kWidth, kHeight, GBufferFormat::PACKED);
  ASSERT_EQ(f.encoded.format, GBufferFormat::PACKED);
  ReferenceImage ref = shadeReference(f.encoded, f.intrinsics, f.lights, f.ambient, 0);
  for (const char* technique : {"tiled", "clustered"}) {
    Knobs k;
    k.format = GBufferFormat::PACKED;
    k.technique = technique;
    FrameResult r = renderTiled(f, k, true);
    double e = compareToReference(r.image, ref, 0.0).maxRelPeak;
    RecordProperty(std::string("packed_vs_own_") + technique, sci(e));
    EXPECT_LE(e, kExact) << technique;
    EXPECT_EQ(countMissedContributions(*r.assignment, f.encoded, f.intrinsics, f.lights, 0), 0u)
        << technique;
  }
}

// Every code the packed layout can store decodes in the kernel (kernels/gbuffer.h through
// decode_gbuffer in kernels/dump.cl) to what decodeSurface returns: every byte of the colour and
// shininess channels, the extreme and random octahedral codes (incl. -32768, which the encoder
// never writes and the decoder clamps), random half emission.
TEST(AccuracyKnobs, PackedDecodeMatchesTheHostForEveryCode) {
  const int W = 256, H = 8;
  const size_t n = size_t(W) * H;
  EncodedGBuffer e;
  e.format = GBufferFormat::PACKED;
  e.width = W;
  e.height = H;
  e.depth.assign(n, 3.0f);
  e.normal.resize(n * 4);
  e.diffuse.resize(n * 4);
  e.specular.resize(n * 4);
  e.emissive.resize(n * 8);
  std::mt19937 rng(3);
  const int16_t extremes[] = {-32768, -32767, -1, 0, 1, 16384, 32766, 32767};
  for (size_t i = 0; i < n; ++i) {
    const uint32_t b = uint32_t(i & 255u), row = uint32_t(i >> 8);
    const uint32_t diffuse = b | (255u - b) << 8 | ((b * 7u + row) & 255u) << 16 | 255u << 24;
    const uint32_t specular = ((b * 3u + row) & 255u) | ((b ^ 0x5au) << 8) | (b << 16) | (b << 24);
    uint32_t normal = rng();
    if (row == 0)
      normal = uint16_t(extremes[b & 7]) | uint32_t(uint16_t(extremes[(b >> 3) & 7])) << 16;
    std::memcpy(&e.diffuse[i * 4], &diffuse, 4);
    std::memcpy(&e.specular[i * 4], &specular, 4);
    std::memcpy(&e.normal[i * 4], &normal, 4);
    for (int c = 0; c < 4; ++c) {
      const uint32_t magnitude = rng();  // one draw per statement (random_draws.h)
      const uint32_t sign = rng();
      uint16_t h = uint16_t(magnitude & 0x7bffu) | uint16_t(sign & 0x8000u);  // finite halves
      std::memcpy(&e.emissive[i * 8 + size_t(c) * 2], &h, 2);
    }
  }
  SceneCamera cam;
  cam.yfov = 0.9f;
  const CameraIntrinsics in = CameraIntrinsics::from(cam, W, H);
  ViewLights lights;
  DeviceFrame frame = DeviceFrame::upload(test::context(), e, in, lights, glm::vec3(0.0f));
  const std::vector<float> d =
      decodeOnDevice(test::context(), frame, GBufferFormat::PACKED, TechniqueConfig().features);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const float* o = &d[(size_t(y) * W + x) * 17];
      SurfaceD s;
      ASSERT_TRUE(decodeSurface(e, in, x, y, s));
      ASSERT_EQ(o[16], 1.0f);
      for (int c = 0; c < 3; ++c) {
        ASSERT_NEAR(o[3 + c], s.N[c], 1e-6) << x << "," << y;
        ASSERT_EQ(o[6 + c], float(s.kd[c])) << x << "," << y;  // colours decode exactly
        ASSERT_EQ(o[9 + c], float(s.ks[c])) << x << "," << y;
        ASSERT_EQ(o[13 + c], float(s.ke[c])) << x << "," << y;
      }
      // exp2 of the shininess byte: the same float (OpenCL's exp2 may be 3 ulp off in general;
      // docs/accuracy.md), checked for all 256 codes.
      ASSERT_NEAR(o[12], float(s.gloss), 3.0 * std::ldexp(double(s.gloss), -23)) << x;
      if (y == 0)
        RecordProperty(
            "shininess_" + std::to_string(x) + "_ulps_off",
            std::to_string(std::abs(double(o[12]) - s.gloss) / std::ldexp(s.gloss, -23)));
    }
}

// Tile size and cluster slicing only regroup the same lights: the image is the reference's up to
// fp32 rounding and no light is missed, whatever the grid.
TEST(AccuracyKnobs, TileSizeAndSlicingNeverChangeTheImage) {
  PreparedFrame f = prepareFrame(scene("street", "many"), 50, kWidth, kHeight, GBufferFormat::FP32);
  ReferenceImage ref = shadeReference(f.encoded, f.intrinsics, f.lights, f.ambient, 0);
  std::vector<Knobs> grids;
  for (int tile : {8, 64}) {  // the default 16 is checked by every other test
    Knobs k;
    k.tile = tile;
    grids.push_back(k);
  }
  for (int slices : {1, 64}) {
    Knobs k;
    k.technique = "clustered";
    k.slices = slices;
    grids.push_back(k);
  }
  for (const Knobs& k : grids) {
    FrameResult r = renderTiled(f, k, true);
    std::string what =
        k.technique + " tile " + std::to_string(k.tile) + " slices " + std::to_string(k.slices);
    double e = compareToReference(r.image, ref, 0.0).maxRelPeak;
    RecordProperty(k.technique + "_" + std::to_string(k.tile) + "_" + std::to_string(k.slices),
                   sci(e));
    EXPECT_LE(e, kExact) << what;
    EXPECT_EQ(countMissedContributions(*r.assignment, f.encoded, f.intrinsics, f.lights, 0), 0u)
        << what;
  }
}

// Shading arithmetic: against the windowed reference from the same stored values.
TEST(AccuracyKnobs, RelaxedArithmeticWithinItsBound) {
  PreparedFrame f = prepareFrame(scene("street", "many"), 0, kWidth, kHeight, GBufferFormat::FP32);
  ReferenceImage ref = shadeReference(f.encoded, f.intrinsics, f.lights, f.ambient, 0);
  // docs/accuracy.md: -cl-fast-relaxed-math <= 2.5e-4 and native_ functions (whose accuracy OpenCL
  // leaves to the implementation) <= 1e-3 of the peak (checked on the test device).
  for (const auto& [math, bound] :
       {std::pair{"fast", kFastMathBound}, std::pair{"native", kNativeMathBound}}) {
    Knobs k;
    k.math = mathModeNames().parse(math);
    double e = compareToReference(renderTiled(f, k).image, ref, 0.0).maxRelPeak;
    RecordProperty(math, sci(e));
    EXPECT_LE(e, bound) << math;
  }
  EXPECT_THROW(mathModeNames().parse("sloppy"), Error);
}

// The same bounds on every built-in scene, light set and variant, each in its own model and
// features (as `render` runs it): relaxed arithmetic's error depends on the shading terms the
// scene uses (metallic-roughness's distribution term most), so one scene does not stand for all.
TEST(AccuracyKnobs, RelaxedArithmeticWithinItsBoundOnEveryBuiltin) {
  const char* const variants[] = {"",
                                  "diffuse",
                                  "no-emission",
                                  "metallic-roughness",
                                  "spot",
                                  "sun",
                                  "spot,sun,metallic-roughness"};
  std::map<std::string, double> worst;
  for (const auto& name : builtinSceneNames())
    for (const auto& set : builtinLightSets(name))
      for (const char* variant : variants) {
        const std::string what = name + "/" + set + " variant '" + variant + "'";
        SCOPED_TRACE(what);
        SceneOptions options;
        options.lightSet = set;
        options.variant = variant;
        const Scene s = loadScene("builtin:" + name, options);
        const SceneFeatures features = analyzeScene(s, nativeShadingModel(s));
        const PreparedFrame f = prepareFrame(s, 0, 96, 54, GBufferFormat::FP32, features);
        const ReferenceImage ref = shadeReference(f.encoded, f.intrinsics, f.lights, f.ambient, 0);
        for (const auto& [math, bound] :
             {std::pair{"fast", kFastMathBound}, std::pair{"native", kNativeMathBound}}) {
          TechniqueConfig config;
          config.features = features;
          config.math = mathModeNames().parse(math);
          const FrameResult r = test::renderOnly(f, test::cachedTechnique("tiled", config), false);
          const double e = compareToReference(r.image, ref, 0.0).maxRelPeak;
          worst[math] = std::max(worst[math], e);
          EXPECT_LE(e, bound) << math;
        }
      }
  for (const auto& [math, e] : worst) RecordProperty(math, sci(e));
}

// Light range from an attenuation threshold: against the physical model (no range cut), a larger
// threshold (shorter ranges) is faster and less exact, monotonically.
TEST(AccuracyKnobs, ThresholdRangesTradeErrorForWork) {
  Scene s = scene("street", "few");
  double lastError = 0.0;
  uint64_t lastWork = UINT64_MAX;
  for (float t : {1.0f / 256.0f, 5.0f / 256.0f, 20.0f / 256.0f}) {
    Scene cut = s;
    applyThresholdRanges(cut.lights, t);
    PreparedFrame f = prepareFrame(cut, 10, kWidth, kHeight, GBufferFormat::FP32);
    ReferenceImage physical =
        shadeReference(f.encoded, f.intrinsics, f.lights, f.ambient, TS_MODEL_PHYSICAL);
    FrameResult r = renderTiled(f, {});
    double e = compareToReference(r.image, physical, 0.0).maxRelPeak;
    EXPECT_GT(e, lastError) << "t = " << t;
    EXPECT_LT(r.counters.lightingComputations, lastWork) << "t = " << t;
    lastError = e;
    lastWork = r.counters.lightingComputations;
  }
  EXPECT_FLOAT_EQ(rangeFromThreshold(glm::vec3(4.0f, 1.0f, 0.0f), 1.0f / 25.0f), 10.0f);
  EXPECT_FLOAT_EQ(rangeFromThreshold(glm::vec3(1e-6f), 1.0f), float(TS_DMIN));  // at least dmin
  EXPECT_THROW(rangeFromThreshold(glm::vec3(1.0f), 0.0f), Error);
}

// The threshold's bound: with r = sqrt(max(C)/t), a light's windowed falloff differs from the
// physical 1/d^2 by C (1 - w(d)) / d^2 <= max_x(2x - x^3) t C/max(C) = 1.089 t C/max(C) inside
// the range (x = d^2/r^2) and by C/d^2 <= t C/max(C) beyond it. Times (kd N.l + ks (N.h)^s) <=
// kd + ks, summed over the lights: per pixel and channel c,
//   |image - physical| <= 1.089 t (kd_c + ks_c) sum_l C_lc / max(C_l)   (docs/accuracy.md),
// plus fp32 rounding. Checked pixel by pixel; the ratio to that bound is recorded.
TEST(AccuracyKnobs, ThresholdRangesWithinTheirBound) {
  const float t = 5.0f / 256.0f;
  Scene cut = scene("atrium", "small");
  applyThresholdRanges(cut.lights, t);
  PreparedFrame f = prepareFrame(cut, 25, kWidth, kHeight, GBufferFormat::FP32);
  ReferenceImage physical =
      shadeReference(f.encoded, f.intrinsics, f.lights, f.ambient, TS_MODEL_PHYSICAL);
  FrameResult r = renderTiled(f, {});
  glm::dvec3 lightSum(0.0);
  for (size_t l = 0; l < f.lights.size(); ++l) {
    glm::dvec3 c(glm::vec3(f.lights.color[l]));
    lightSum += c / std::max({c.x, c.y, c.z});
  }
  double worstRatio = 0.0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      SurfaceD s;
      if (!decodeSurface(f.encoded, f.intrinsics, x, y, s)) continue;
      const size_t i = size_t(y) * kWidth + x;
      for (int c = 0; c < 3; ++c) {
        double bound = 1.089 * t * (s.kd[c] + s.ks[c]) * lightSum[c];
        double err = std::abs(double(r.image[i][c]) - physical.rgb[i][c]);
        ASSERT_LE(err, bound + kExact * physical.peak) << x << "," << y << " channel " << c;
        if (bound > 0.0) worstRatio = std::max(worstRatio, err / bound);
      }
    }
  RecordProperty("worst_ratio_to_bound", sci(worstRatio));
  RecordProperty("max_rel_peak_vs_physical",
                 sci(compareToReference(r.image, physical, 0.0).maxRelPeak));
  EXPECT_GT(worstRatio, 0.05);  // the bound is not vacuous on this scene
}

}  // namespace
}  // namespace ts
