// Shading in lanes (kernels/lanes.h): every lane width gives the image that one work-item per
// pixel gives, for every technique (those without a lanes path must report 1), on frames whose
// size and tiles leave partial vectors, with and without the range cut, and with a light exactly
// on a surface point (a lane with no light direction must not spread NaN to its neighbours).
#include <gtest/gtest.h>

#include <cmath>

#include "shading/shading_cpu.h"
#include "render/frame_setup.h"
#include "scene/scene_loader.h"
#include "techniques/technique.h"
#include "util/error.h"
#include "reference_check.h"
#include "test_support.h"

namespace ts {
namespace {

using test::relativeDifference;

bool allFinite(const std::vector<glm::vec4>& image) {
  for (const auto& p : image)
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return false;
  return true;
}

FrameResult render(const PreparedFrame& f, const std::string& technique, TechniqueConfig config,
                   int lanes, int* lanesUsed = nullptr) {
  config.lanes = lanes;
  auto t = createTechnique(technique, test::context(), config);
  if (lanesUsed) *lanesUsed = t->lanes();
  return test::renderOnly(f, *t, false);
}

// 150x90 is no multiple of 16, and 10x6 tiles make 60-item work-groups: the last vector of a
// group is partly padding and the last groups of the screen partly off it. Every width with the
// range cut (vectors exit early where no lane is in range); 16 also without it (physical model).
TEST(Lanes, EveryWidthGivesThePerPixelImage) {
  PreparedFrame f =
      prepareFrame(test::builtinScene("street", "many"), 20, 150, 90, GBufferFormat::FP32);
  for (RangeModel model : {RangeModel::Windowed, RangeModel::Physical}) {
    TechniqueConfig config;
    config.tileWidth = 10;
    config.tileHeight = 6;
    config.rangeModel = model;
    for (const auto& name : gbufferTechniqueNames()) {
      FrameResult one = render(f, name, config, 1);
      ASSERT_TRUE(allFinite(one.image)) << name;
      for (int lanes : {16, 8, 4, 2}) {
        int used = 0;
        FrameResult many = render(f, name, config, lanes, &used);
        EXPECT_TRUE(allFinite(many.image)) << name << " lanes " << lanes;
        // Each lane does the per-pixel arithmetic; only the compiler's choices may differ.
        EXPECT_LE(relativeDifference(one.image, many.image), 1e-6)
            << name << " lanes " << lanes << " model " << toString(model);
        EXPECT_EQ(many.counters.evaluations, one.counters.evaluations) << name;
        if (used == 1) break;  // no lanes path: the other widths run the same kernels
        EXPECT_EQ(used, lanes) << name;
        if (model == RangeModel::Physical) break;
      }
    }
  }
}

// The lanes path stays within the reference tolerance on its own (not only relative to the
// per-pixel kernels).
TEST(Lanes, MatchReferenceWithNoMissedLight) {
  const PreparedFrame f =
      prepareFrame(test::builtinScene("atrium", "mixed"), 20, 160, 96, GBufferFormat::FP16);
  for (const char* name : {"tiled", "brute", "clustered"}) {
    TechniqueConfig config;
    config.format = GBufferFormat::FP16;
    config.lanes = 16;
    auto t = createTechnique(name, test::context(), config);
    EXPECT_EQ(t->lanes(), 16) << name;
    test::Checked c = test::renderAndCheck(f, *t);
    EXPECT_EQ(c.missed, 0u) << name;
    EXPECT_LE(c.error.maxRelPeak, test::kFp32RelativeTolerance) << name;
  }
}

// A light placed exactly on the surface point of one pixel (the same float arithmetic as the
// kernel's position reconstruction): that lane has d2 = 0 and no light direction. It must
// contribute nothing to that pixel, as per pixel, and nothing undefined to the other lanes of its
// vector.
TEST(Lanes, LightExactlyOnASurfacePointStaysFinite) {
  PreparedFrame f =
      prepareFrame(test::builtinScene("atrium", "big"), 0, 96, 64, GBufferFormat::FP32);
  const int x = 40, y = 30;
  const size_t i = size_t(y) * f.gbuffer.width + x;
  float depth = f.encoded.depth[i];
  ASSERT_GT(depth, 0.0f) << "pick a pixel with geometry";
  glm::vec3 p =
      shading_f::ts_view_position(x, y, depth, f.intrinsics.tanHalfFovX, f.intrinsics.tanHalfFovY,
                                  f.gbuffer.width, f.gbuffer.height);
  TechniqueConfig config;
  FrameResult without = render(f, "brute", config, 1);
  FrameResult manyWithout = render(f, "brute", config, 16);
  f.lights.addPoint(p, 3.0f, {1.0f, 0.5f, 0.25f});
  FrameResult one = render(f, "brute", config, 1);
  FrameResult many = render(f, "brute", config, 16);
  ASSERT_TRUE(allFinite(one.image));
  // The precondition: the kernel saw d2 = 0 at pixel i (the light adds nothing there) while the
  // light does reach the neighbouring pixel.
  ASSERT_EQ(one.image[i], without.image[i]) << "the kernel's position differs from the host's";
  ASSERT_NE(one.image[i + 1], without.image[i + 1]);
  EXPECT_TRUE(allFinite(many.image));
  EXPECT_LE(relativeDifference(one.image, many.image), 1e-6);
  // In lanes too the light adds exactly nothing at that pixel (its lane gets 0, not NaN).
  for (int c = 0; c < 3; ++c)
    EXPECT_EQ(many.image[i][c], manyWithout.image[i][c]) << "channel " << c;
}

// auto: 16 for tiled, tiled-single, clustered and brute on a CPU (measured faster there with many
// lights), 1 for the rest and on GPUs.
TEST(Lanes, AutoPicksTheFasterWidthPerTechniqueAndDevice) {
  bool gpu = test::context().isGpu();
  for (const auto& name : gbufferTechniqueNames()) {
    auto t = createTechnique(name, test::context(), TechniqueConfig{});
    bool lanes =
        name == "tiled" || name == "tiled-single" || name == "clustered" || name == "brute";
    EXPECT_EQ(t->lanes(), !gpu && lanes ? 16 : 1) << name;
  }
  // tiled-single keeps its whole tile in local memory in lanes (19 floats per pixel); a tile that
  // does not fit runs one pixel per work-item and says so.
  TechniqueConfig huge;
  huge.tileWidth = huge.tileHeight = 128;
  huge.lanes = 16;
  size_t localBytes = test::context().device().getInfo<CL_DEVICE_LOCAL_MEM_SIZE>();
  EXPECT_EQ(createTechnique("tiled-single", test::context(), huge)->lanes(),
            19u * 128 * 128 * 4 > localBytes ? 1 : 16);
  EXPECT_EQ(parseLanes("auto"), 0);
  EXPECT_EQ(parseLanes("8"), 8);
  EXPECT_THROW(parseLanes("3"), Error);
  EXPECT_THROW(parseLanes("32"), Error);
  TechniqueConfig bad;
  bad.lanes = 5;
  EXPECT_THROW(createTechnique("tiled", test::context(), bad), Error);
}

}  // namespace
}  // namespace ts
