// clustered in lanes (kernels/clustered.cl): the pixels of one vector may lie in different
// clusters, so a vector runs the list of each distinct slice among its lanes with the other lanes
// unlit. Each lane must then get exactly its own cluster's lights: the lanes image equals the
// per-pixel image at every width, on frames and tiles of odd sizes (partial vectors, groups that
// are no whole number of vectors), with many slices (vectors holding several of them), for point,
// spot and directional lights, both shading models and every G-buffer layout, and it misses no
// contribution against the reference.
#include <gtest/gtest.h>

#include <set>

#include "render/frame_setup.h"
#include "scene/scene_features.h"
#include "scene/scene_loader.h"
#include "techniques/technique.h"
#include "reference_check.h"
#include "test_support.h"

namespace ts {
namespace {

using test::relativeDifference;

struct LanesCase {
  std::string scene, lights, variant;
  int frame;
  GBufferFormat format;
  std::vector<int> widths;  // besides 1
};

void PrintTo(const LanesCase& k, std::ostream* os) {
  *os << k.scene << "/" << k.lights << " '" << k.variant << "' frame " << k.frame << " "
      << toString(k.format);
}

class ClusteredLanes : public ::testing::TestWithParam<LanesCase> {};

// 157x83 pixels, 7x5 tiles (35-item work-groups: 2 whole vectors of 16 and a partial one),
// 32 slices.
TEST_P(ClusteredLanes, EqualThePerPixelImageAndMissNothing) {
  const LanesCase& k = GetParam();
  SceneOptions options;
  options.lightSet = k.lights;
  options.variant = k.variant;
  Scene scene = loadScene("builtin:" + k.scene, options);
  SceneFeatures features = analyzeScene(scene, nativeShadingModel(scene));
  PreparedFrame f = prepareFrame(scene, k.frame, 157, 83, k.format, features);
  TechniqueConfig config;
  config.format = k.format;
  config.features = features;
  config.tileWidth = 7;
  config.tileHeight = 5;
  config.clusterSlices = 32;
  config.lanes = 1;
  test::Checked one = test::renderAndCheck(f, test::cachedTechnique("clustered", config));
  EXPECT_EQ(one.missed, 0u);
  EXPECT_LE(one.error.maxRelPeak, test::kFp32RelativeTolerance);

  // The precondition: some 7-pixel tile row holds geometry of more than one slice, so some vector
  // runs several cluster lists.
  ASSERT_TRUE(one.result.assignment.has_value());
  const std::vector<int32_t>& bin = one.result.assignment->pixelBin;
  size_t mixedRows = 0;
  for (int y = 0; y < f.gbuffer.height; ++y)
    for (int x0 = 0; x0 < f.gbuffer.width; x0 += config.tileWidth) {
      std::set<int32_t> clusters;
      for (int x = x0; x < std::min(x0 + config.tileWidth, f.gbuffer.width); ++x)
        if (int32_t b = bin[size_t(y) * f.gbuffer.width + x]; b >= 0) clusters.insert(b);
      mixedRows += clusters.size() > 1;
    }
  ASSERT_GT(mixedRows, 20u) << "no vector spans several slices: the test tests nothing";

  for (int lanes : k.widths) {
    config.lanes = lanes;
    Technique& t = test::cachedTechnique("clustered", config);
    EXPECT_EQ(t.lanes(), lanes);
    test::Checked many = test::renderAndCheck(f, t);
    // Each lane does the per-pixel arithmetic; only the compiler's choices may differ.
    EXPECT_LE(relativeDifference(one.result.image, many.result.image), 1e-6) << "lanes " << lanes;
    EXPECT_EQ(many.result.counters.evaluations, one.result.counters.evaluations) << lanes;
    EXPECT_EQ(many.missed, 0u) << "lanes " << lanes;
    EXPECT_LE(many.error.maxRelPeak, test::kFp32RelativeTolerance) << "lanes " << lanes;
    for (const auto& p : many.result.image)
      ASSERT_TRUE(std::isfinite(p.x + p.y + p.z)) << "lanes " << lanes;
  }
}

// Every width once on the plain street; each layout, light type and shading model with 16 and
// one other width (kernel builds are the slow part).
INSTANTIATE_TEST_SUITE_P(
    WidthsLayoutsAndVariants, ClusteredLanes,
    ::testing::Values(
        LanesCase{"street", "many", "", 20, GBufferFormat::FP32, {2, 4, 8, 16}},
        LanesCase{"street", "few", "spot,sun", 100, GBufferFormat::FP16, {4, 16}},
        LanesCase{"street", "many", "spot,sun", 40, GBufferFormat::PACKED, {2, 16}},
        LanesCase{"atrium", "mixed", "metallic-roughness", 20, GBufferFormat::PACKED, {8, 16}},
        LanesCase{"atrium", "big", "sun,metallic-roughness", 70, GBufferFormat::FP32, {16}}),
    [](const auto& info) { return "case" + std::to_string(info.index); });

}  // namespace
}  // namespace ts
