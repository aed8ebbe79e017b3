// Every registered technique against the double-precision reference: same tolerance, zero missed
// contributions, for both G-buffer precisions, several tile sizes, scenes and frames. A new
// technique in registry.cpp is picked up here without an edit. Also: tiled and tiled-single build
// the same tile light sets, and tiled-single shades lists longer than its local memory in chunks.
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <map>
#include <memory>
#include <random>
#include <set>

#include "reference/error_metrics.h"
#include "reference/reference.h"
#include "render/frame_setup.h"
#include "scene/scene_loader.h"
#include "techniques/technique.h"
#include "reference_check.h"
#include "test_support.h"

namespace ts {
namespace {

using test::builtinScene;
using test::Checked;
using test::kFp32RelativeTolerance;
using test::renderAndCheck;
using test::renderOnly;

const PreparedFrame& prepared(const std::string& scene, const std::string& lights, int frame,
                              GBufferFormat format) {
  static std::map<std::string, std::unique_ptr<PreparedFrame>> cache;
  auto key = scene + lights + std::to_string(frame) + toString(format);
  auto& p = cache[key];
  if (!p)
    p = std::make_unique<PreparedFrame>(
        prepareFrame(builtinScene(scene, lights), frame, 160, 96, format));
  return *p;
}

struct Case {
  std::string technique, scene, lights;
  int frame, tile;
  GBufferFormat format;
};

void PrintTo(const Case& k, std::ostream* os) {
  *os << k.technique << " " << k.scene << "/" << k.lights << " frame " << k.frame << " tile "
      << k.tile << " " << toString(k.format);
}

class EveryTechnique : public ::testing::TestWithParam<Case> {};

TEST_P(EveryTechnique, MatchesReferenceWithNoMissedLight) {
  const Case& k = GetParam();
  const PreparedFrame& f = prepared(k.scene, k.lights, k.frame, k.format);
  TechniqueConfig config;
  config.format = k.format;
  config.tileWidth = config.tileHeight = k.tile;
  auto technique = createTechnique(k.technique, test::context(), config);
  Checked c = renderAndCheck(f, *technique);
  EXPECT_EQ(c.missed, 0u);
  EXPECT_LE(c.error.maxRelPeak, kFp32RelativeTolerance)
      << "max abs " << c.error.maxAbs << " peak " << c.error.peak;
  EXPECT_GT(c.result.counters.evaluations, 0u);
  // No technique can do with fewer evaluations than the lights that actually contribute.
  ReferenceImage ref = shadeReference(f.encoded, f.intrinsics, f.lights, f.ambient, 0);
  EXPECT_GE(c.result.counters.evaluations, ref.contributing);
  EXPECT_GE(c.result.counters.lightingComputations, c.result.counters.evaluations / 2)
      << "lighting computations should count at least the covered pixels";
  EXPECT_GT(c.result.totalMs, 0.0);
  EXPECT_FALSE(c.result.kernels.empty());
}

std::vector<Case> everyTechniqueCases() {
  // Scenes x light sets x precisions x tile sizes x frames, spread so each technique sees each.
  const std::vector<Case> shapes = {
      {"", "street", "many", 0, 16, GBufferFormat::FP32},
      {"", "street", "few", 40, 32, GBufferFormat::FP16},
      {"", "atrium", "mixed", 20, 8, GBufferFormat::FP32},
      {"", "atrium", "big", 70, 64, GBufferFormat::FP16},
  };
  std::vector<Case> cases;
  for (const auto& name : gbufferTechniqueNames())
    for (Case c : shapes) {
      c.technique = name;
      cases.push_back(c);
    }
  return cases;
}

INSTANTIATE_TEST_SUITE_P(Builtins, EveryTechnique, ::testing::ValuesIn(everyTechniqueCases()),
                         [](const auto& info) {
                           const Case& k = info.param;
                           std::string t = k.technique;
                           std::replace(t.begin(), t.end(), '-', '_');
                           return t + "_" + k.scene + "_" + k.lights + "_f" +
                                  std::to_string(k.frame) + "_t" + std::to_string(k.tile) + "_" +
                                  toString(k.format);
                         });

// Tile sizes that are not powers of two (nor divide the image), square or not: the binned
// techniques launch work-groups that stay inside one tile (tileDividingGroup) and stay exact.
TEST(BinnedTechniques, OddTileSizes) {
  const PreparedFrame& f = prepared("street", "many", 10, GBufferFormat::FP32);
  for (const char* name : {"tiled", "tiled-single", "clustered"})
    for (auto [w, h] :
         {std::pair{24, 24}, std::pair{12, 20}, std::pair{17, 9}, std::pair{48, 40}}) {
      TechniqueConfig config;
      config.tileWidth = w;
      config.tileHeight = h;
      Checked c = renderAndCheck(f, *createTechnique(name, test::context(), config));
      EXPECT_EQ(c.missed, 0u) << name << " " << w << "x" << h;
      EXPECT_LE(c.error.maxRelPeak, kFp32RelativeTolerance) << name << " " << w << "x" << h;
    }
}

// Per tile, the set of listed lights.
std::vector<std::set<uint32_t>> tileSets(const LightAssignment& a) {
  std::vector<std::set<uint32_t>> sets(a.binCount.size());
  for (size_t b = 0; b < sets.size(); ++b)
    sets[b].insert(a.binLights.begin() + a.binOffset[b],
                   a.binLights.begin() + a.binOffset[b] + a.binCount[b]);
  return sets;
}

// Per tile, the listed lights in list order.
std::vector<std::vector<uint32_t>> tileLists(const LightAssignment& a) {
  std::vector<std::vector<uint32_t>> lists(a.binCount.size());
  for (size_t b = 0; b < lists.size(); ++b)
    lists[b].assign(a.binLights.begin() + a.binOffset[b],
                    a.binLights.begin() + a.binOffset[b] + a.binCount[b]);
  return lists;
}

// Both tiled variants run the same per-tile test (culling.h) on the same tile depth range, so
// their tile light lists are identical, for every culling test, order included: both list a
// tile's lights in light index order.
TEST(TiledSingle, SameTileListsAsMultiKernelTiled) {
  const PreparedFrame& f = prepared("street", "many", 30, GBufferFormat::FP32);
  DeviceFrame frame = f.upload(test::context());
  FrameRequest request;
  request.wantAssignment = true;
  for (auto [culling, tile] : {std::pair{CullTest::Rect, 16}, std::pair{CullTest::Frustum, 16},
                               std::pair{CullTest::Aabb, 16}, std::pair{CullTest::Rect, 32}}) {
    TechniqueConfig config;
    config.culling = culling;
    config.tileWidth = config.tileHeight = tile;
    FrameResult a = createTechnique("tiled", test::context(), config)->render(frame, request);
    FrameResult b =
        createTechnique("tiled-single", test::context(), config)->render(frame, request);
    EXPECT_EQ(tileLists(*a.assignment), tileLists(*b.assignment))
        << toString(culling) << " tile " << tile;
    EXPECT_EQ(a.counters.lightingComputations, b.counters.lightingComputations);
    EXPECT_GT(a.counters.lightingComputations, 0u);
  }
}

// A tile accepting far more lights than the local list holds is shaded in chunks: nothing dropped.
TEST(TiledSingle, ListsLongerThanLocalMemoryAreShadedInChunks) {
  // 300 huge lights: every tile lists all of them.
  PreparedFrame f = test::hugeLightsFrame(300);
  TechniqueConfig config;
  config.tileWidth = config.tileHeight = 8;  // 64 work-items
  config.localListCapacity = 64;             // so 300 lights take 5 chunks
  auto single = createTechnique("tiled-single", test::context(), config);
  Checked c = renderAndCheck(f, *single);
  EXPECT_EQ(c.missed, 0u);
  EXPECT_LE(c.error.maxRelPeak, kFp32RelativeTolerance);
  EXPECT_EQ(c.result.counters.listMax, 300u);
  for (const auto& set : tileSets(*c.result.assignment)) {
    if (set.empty()) continue;  // sky-only tiles list nothing
    EXPECT_EQ(set.size(), 300u) << "each light listed once";
  }
}

// Brute force lists every light for every pixel, so its counters are exact products.
TEST(Brute, CountsEveryLightForEveryPixel) {
  const PreparedFrame& f = prepared("street", "few", 0, GBufferFormat::FP32);
  auto brute = createTechnique("brute", test::context(), {});
  Checked c = renderAndCheck(f, *brute);
  uint64_t lights = f.lights.size();
  EXPECT_EQ(c.result.counters.lightingComputations, f.gbuffer.pixelCount() * lights);
  EXPECT_EQ(c.result.counters.evaluations, f.gbuffer.geometryPixels() * lights);
  EXPECT_EQ(c.missed, 0u);
}

}  // namespace
}  // namespace ts
