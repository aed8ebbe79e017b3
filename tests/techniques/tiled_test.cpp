// Multi-kernel tiled deferred end to end: scene -> software G-buffer -> tiled on PoCL -> compared
// with the double-precision reference; culling conservativeness on random cameras, with
// --depth-split, and with a light list that overflows its buffer.
#include <gtest/gtest.h>

#include <string>

#include "render/frame_setup.h"
#include "techniques/technique.h"
#include "reference_check.h"
#include "test_support.h"
#include "tiled_technique.h"

namespace ts {
namespace {

using test::builtinScene;
using test::Checked;
using test::kFp32RelativeTolerance;
using test::renderAndCheck;
using test::tiledTechnique;

struct Case {
  std::string scene, lights;
  int frame, tile, width, height;
  GBufferFormat format;
};

// Keeps CTest's names readable (GoogleTest would print the parameter's bytes).
void PrintTo(const Case& k, std::ostream* os) {
  *os << k.scene << "/" << k.lights << " frame " << k.frame << " tile " << k.tile << " " << k.width
      << "x" << k.height << " " << toString(k.format);
}

class TiledMatchesReference : public ::testing::TestWithParam<Case> {};

TEST_P(TiledMatchesReference, WithinFp32RoundingAndNoMissedLight) {
  const Case& k = GetParam();
  PreparedFrame f =
      prepareFrame(builtinScene(k.scene, k.lights), k.frame, k.width, k.height, k.format);
  ASSERT_GT(f.gbuffer.geometryPixels(), f.gbuffer.pixelCount() / 4) << "camera sees little";
  Checked c = renderAndCheck(f, tiledTechnique(k.format, k.tile));
  EXPECT_EQ(c.missed, 0u);
  EXPECT_LE(c.error.maxRelPeak, kFp32RelativeTolerance)
      << "max abs " << c.error.maxAbs << " peak " << c.error.peak;
  EXPECT_GT(c.result.counters.evaluations, 0u);
}

INSTANTIATE_TEST_SUITE_P(
    Builtins, TiledMatchesReference,
    ::testing::Values(Case{"street", "many", 0, 16, 200, 120, GBufferFormat::FP32},
                      Case{"street", "many", 60, 8, 200, 120, GBufferFormat::FP16},
                      Case{"street", "few", 30, 32, 203, 117, GBufferFormat::FP32},
                      Case{"atrium", "small", 0, 16, 200, 120, GBufferFormat::FP16},
                      Case{"atrium", "big", 45, 32, 203, 117, GBufferFormat::FP32},
                      Case{"atrium", "mixed", 90, 64, 200, 120, GBufferFormat::FP32}),
    [](const auto& info) {
      const Case& k = info.param;
      return k.scene + "_" + k.lights + "_f" + std::to_string(k.frame) + "_t" +
             std::to_string(k.tile) + "_" + toString(k.format);
    });

// Random cameras inside the scene (looking anywhere, lights behind and around the camera, near
// plane through light volumes): the tile lists must hold every contributing light.
TEST(TiledCulling, ConservativeOnRandomCameras) {
  for (const auto& [label, f] : test::randomCameraFrames(11)) {
    Checked c = renderAndCheck(f, tiledTechnique(GBufferFormat::FP32, 16));
    EXPECT_EQ(c.missed, 0u) << label;
    EXPECT_LE(c.error.maxRelPeak, kFp32RelativeTolerance) << label;
  }
}

// --depth-split only drops lights that no pixel of a tile can see: on random cameras and on the
// atrium's lights between its columns and the far wall, no missed light, the same error bound,
// and never more lighting computations than one range per tile.
TEST(TiledCulling, DepthSplitIsConservativeAndNeverCullsLess) {
  auto frames = test::randomCameraFrames(5);
  frames.push_back(test::LabelledFrame{
      "atrium/small frame 0",
      prepareFrame(builtinScene("atrium", "small"), 0, 200, 120, GBufferFormat::FP32)});
  uint64_t plain = 0, split = 0;
  for (const auto& [label, f] : frames) {
    TechniqueConfig config;
    config.depthSplit = true;
    auto tiled = createTechnique("tiled", test::context(), config);
    Checked c = renderAndCheck(f, *tiled);
    EXPECT_EQ(c.missed, 0u) << label;
    EXPECT_LE(c.error.maxRelPeak, kFp32RelativeTolerance) << label;
    Checked d = renderAndCheck(f, tiledTechnique(GBufferFormat::FP32, 16));
    EXPECT_LE(c.result.counters.lightingComputations, d.result.counters.lightingComputations)
        << label;
    split += c.result.counters.lightingComputations;
    plain += d.result.counters.lightingComputations;
  }
  EXPECT_LT(split, plain) << "the split culled nothing anywhere";
}

// Far more list entries than the initial buffer holds: the list grows and the frame re-runs,
// nothing is dropped, and the run says so.
TEST(TiledCulling, OverflowingListGrowsInsteadOfDropping) {
  // 300 huge lights: every tile lists all of them.
  PreparedFrame f = test::hugeLightsFrame(300);
  TechniqueConfig config;
  config.tileWidth = config.tileHeight = 8;
  config.presizeLists = false;  // start from the small default buffer so it has to grow
  auto tiled = createTechnique("tiled", test::context(), config);
  Checked c = renderAndCheck(f, *tiled);
  EXPECT_EQ(c.missed, 0u);
  EXPECT_LE(c.error.maxRelPeak, kFp32RelativeTolerance);
  EXPECT_EQ(c.result.counters.listMax, 300u);
  ASSERT_FALSE(c.result.counters.notes.empty());
  EXPECT_NE(c.result.counters.notes[0].find("grown"), std::string::npos);

  // Presized from the host's rectangle bound (the default), the same frame needs no re-run.
  config.presizeLists = true;
  Checked p = renderAndCheck(f, *createTechnique("tiled", test::context(), config));
  EXPECT_TRUE(p.result.counters.notes.empty());
  EXPECT_EQ(p.missed, 0u);
  EXPECT_EQ(p.result.counters.lightingComputations, c.result.counters.lightingComputations);
}

}  // namespace
}  // namespace ts
