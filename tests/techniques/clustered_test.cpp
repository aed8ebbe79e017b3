// Clustered deferred shading (src/techniques/clustered.cpp, kernels/clustered.cl): equal to the
// double reference with no missed light across tile sizes, slice counts and G-buffer precisions;
// one slice reproduces tiled's lists; depth slicing saves evaluations where tiles span depth
// discontinuities; conservative on random cameras; an overflowing list grows.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <memory>
#include <random>
#include <tuple>

#include "reference/error_metrics.h"
#include "reference/reference.h"
#include "render/frame_setup.h"
#include "scene/scene_loader.h"
#include "techniques/technique.h"
#include "reference_check.h"
#include "test_support.h"
#include "util/error.h"
#include "util/option_values.h"

namespace ts {
namespace {

using test::builtinScene;
using test::Checked;
using test::kFp32RelativeTolerance;
using test::renderAndCheck;
using test::renderOnly;

Technique& technique(const std::string& name, GBufferFormat format, int tile, int slices,
                     CullTest culling = CullTest::Rect) {
  TechniqueConfig config;
  config.format = format;
  config.tileWidth = config.tileHeight = tile;
  config.clusterSlices = slices;
  config.culling = culling;
  return test::cachedTechnique(name, config);
}

struct Case {
  std::string scene, lights;
  int frame, tile, slices, width, height;
  GBufferFormat format;
};

void PrintTo(const Case& k, std::ostream* os) {
  *os << k.scene << "/" << k.lights << " frame " << k.frame << " tile " << k.tile << " slices "
      << k.slices << " " << k.width << "x" << k.height << " " << toString(k.format);
}

class ClusteredMatchesReference : public ::testing::TestWithParam<Case> {};

TEST_P(ClusteredMatchesReference, WithinFp32RoundingAndNoMissedLight) {
  const Case& k = GetParam();
  PreparedFrame f =
      prepareFrame(builtinScene(k.scene, k.lights), k.frame, k.width, k.height, k.format);
  ASSERT_GT(f.gbuffer.geometryPixels(), f.gbuffer.pixelCount() / 4) << "camera sees little";
  Checked c = renderAndCheck(f, technique("clustered", k.format, k.tile, k.slices));
  EXPECT_EQ(c.missed, 0u);
  EXPECT_LE(c.error.maxRelPeak, kFp32RelativeTolerance)
      << "max abs " << c.error.maxAbs << " peak " << c.error.peak;
  const WorkCounters& w = c.result.counters;
  EXPECT_GT(w.evaluations, 0u);
  EXPECT_EQ(w.lightingComputations, w.evaluations);
  // Conservative lists hold at least every contributing pair.
  EXPECT_GE(w.evaluations, c.contributing);
  EXPECT_LE(w.listMin, w.listMax);
  EXPECT_GT(w.listMax, 0u);
  // Every geometry pixel, and only those, is in a cluster, and the cluster is in range.
  const LightAssignment& a = *c.result.assignment;
  size_t clustered = 0;
  for (int32_t b : a.pixelBin) {
    if (b < 0) continue;
    ++clustered;
    ASSERT_LT(size_t(b), a.binCount.size());
  }
  EXPECT_EQ(clustered, f.gbuffer.geometryPixels());
  int tiles = ((k.width + k.tile - 1) / k.tile) * ((k.height + k.tile - 1) / k.tile);
  EXPECT_EQ(a.binCount.size(), size_t(tiles) * k.slices);
}

INSTANTIATE_TEST_SUITE_P(
    Builtins, ClusteredMatchesReference,
    ::testing::Values(Case{"street", "many", 0, 16, 16, 200, 120, GBufferFormat::FP32},
                      Case{"street", "many", 60, 8, 32, 200, 120, GBufferFormat::FP16},
                      Case{"street", "many", 0, 16, 1, 200, 120, GBufferFormat::FP32},
                      Case{"street", "few", 30, 32, 16, 203, 117, GBufferFormat::FP32},
                      Case{"atrium", "mixed", 90, 16, 16, 200, 120, GBufferFormat::FP32},
                      Case{"atrium", "mixed", 0, 32, 32, 203, 117, GBufferFormat::FP16},
                      Case{"atrium", "mixed", 45, 8, 1, 200, 120, GBufferFormat::FP16}),
    [](const auto& info) {
      const Case& k = info.param;
      return k.scene + "_" + k.lights + "_f" + std::to_string(k.frame) + "_t" +
             std::to_string(k.tile) + "_s" + std::to_string(k.slices) + "_" + toString(k.format);
    });

// The per-tile tests of culling.h (frustum planes, box) are applied per cluster with the
// cluster's depth range: still conservative.
TEST(ClusteredCulling, FrustumAndBoxTestsStayConservative) {
  PreparedFrame f = prepareFrame(builtinScene("street", "many"), 0, 200, 120, GBufferFormat::FP32);
  uint64_t rectEvaluations = 0;
  for (CullTest culling : {CullTest::Rect, CullTest::Frustum, CullTest::Aabb}) {
    Checked c = renderAndCheck(f, technique("clustered", GBufferFormat::FP32, 16, 16, culling));
    EXPECT_EQ(c.missed, 0u) << "culling " << toString(culling);
    EXPECT_LE(c.error.maxRelPeak, kFp32RelativeTolerance) << "culling " << toString(culling);
    if (culling == CullTest::Rect) rectEvaluations = c.result.counters.evaluations;
    else
      EXPECT_LE(c.result.counters.evaluations, rectEvaluations) << "culling " << toString(culling);
  }
}

// With one slice a cluster is its tile's geometry: the same depth range (min/max of the tile's
// geometry pixels) and the same tests as tiled, so every tile lists the same lights (the order
// within a list too: both list a bin's lights in light index order) and each geometry pixel
// makes the same evaluations. Only lightingComputations differs: tiled counts every tile pixel,
// clustered only geometry pixels.
TEST(ClusteredVsTiled, OneSliceListsEqualTiledPerTile) {
  for (const auto& [name, lights, frameIndex] :
       {std::tuple{"street", "many", 0}, std::tuple{"atrium", "mixed", 90}}) {
    PreparedFrame f =
        prepareFrame(builtinScene(name, lights), frameIndex, 200, 120, GBufferFormat::FP32);
    FrameResult clustered = renderOnly(f, technique("clustered", GBufferFormat::FP32, 16, 1), true);
    FrameResult tiled = renderOnly(f, technique("tiled", GBufferFormat::FP32, 16, 1), true);
    const LightAssignment& c = *clustered.assignment;
    const LightAssignment& t = *tiled.assignment;
    ASSERT_EQ(c.binCount.size(), t.binCount.size()) << name;
    EXPECT_EQ(c.binLights.size(), t.binLights.size()) << name;
    size_t emptyTilesWithLights = 0;
    for (size_t b = 0; b < c.binCount.size(); ++b) {
      auto list = [](const LightAssignment& a, size_t b) {
        return std::vector<uint32_t>(a.binLights.begin() + a.binOffset[b],
                                     a.binLights.begin() + a.binOffset[b] + a.binCount[b]);
      };
      EXPECT_EQ(list(c, b), list(t, b)) << name << " tile " << b;
      if (t.binCount[b] > 0 && c.binCount[b] == 0) ++emptyTilesWithLights;
    }
    EXPECT_EQ(emptyTilesWithLights, 0u) << name;
    EXPECT_EQ(clustered.counters.evaluations, tiled.counters.evaluations) << name;
    EXPECT_LE(clustered.counters.lightingComputations, tiled.counters.lightingComputations);
  }
}

// Looking down the street, a tile spans a near facade or robot and the far end of the street; its
// depth range then holds lights its pixels are nowhere near. Slices separate those depths.
TEST(ClusteredVsTiled, FewerEvaluationsAcrossDepthDiscontinuities) {
  for (int frameIndex : {0, 60}) {
    PreparedFrame f =
        prepareFrame(builtinScene("street", "many"), frameIndex, 200, 120, GBufferFormat::FP32);
    uint64_t tiled =
        renderOnly(f, technique("tiled", GBufferFormat::FP32, 16, 1), false).counters.evaluations;
    uint64_t previous = tiled;
    for (int slices : {16, 32}) {
      uint64_t clustered =
          renderOnly(f, technique("clustered", GBufferFormat::FP32, 16, slices), false)
              .counters.evaluations;
      EXPECT_LT(clustered, tiled) << "frame " << frameIndex << " slices " << slices;
      EXPECT_LE(clustered, previous) << "frame " << frameIndex << " slices " << slices;
      previous = clustered;
    }
  }
}

// Random cameras inside the scene (looking anywhere, lights behind and around the camera, near
// plane through light volumes): the cluster lists must hold every contributing light.
TEST(ClusteredCulling, ConservativeOnRandomCameras) {
  for (const auto& [label, f] : test::randomCameraFrames(23)) {
    Checked c = renderAndCheck(f, technique("clustered", GBufferFormat::FP32, 16, 16));
    EXPECT_EQ(c.missed, 0u) << label;
    EXPECT_LE(c.error.maxRelPeak, kFp32RelativeTolerance) << label;
  }
}

// Far more list entries than the initial buffer holds: the list grows and the frame re-runs,
// nothing is dropped, and the run says so.
TEST(ClusteredCulling, OverflowingListGrowsInsteadOfDropping) {
  // 300 huge lights: every non-empty cluster lists all of them.
  PreparedFrame f = test::hugeLightsFrame(300);
  TechniqueConfig config;
  config.tileWidth = config.tileHeight = 8;
  config.clusterSlices = 8;
  config.presizeLists = false;  // start from the small default buffer so it has to grow
  auto clustered = createTechnique("clustered", test::context(), config);
  Checked c = renderAndCheck(f, *clustered);
  EXPECT_EQ(c.missed, 0u);
  EXPECT_LE(c.error.maxRelPeak, kFp32RelativeTolerance);
  EXPECT_EQ(c.result.counters.listMin, 300u);
  EXPECT_EQ(c.result.counters.listMax, 300u);
  ASSERT_FALSE(c.result.counters.notes.empty());
  EXPECT_NE(c.result.counters.notes[0].find("grown"), std::string::npos);
  // The grown buffer is kept: the next frame needs no re-run.
  EXPECT_TRUE(renderOnly(f, *clustered, false).counters.notes.empty());
}

// No lights, and a frame without geometry: nothing binned, nothing evaluated, no failure.
TEST(ClusteredCulling, NoLightsAndNoGeometry) {
  Scene scene = builtinScene("street", "many");
  scene.lights.clear();
  PreparedFrame f = prepareFrame(scene, 0, 64, 40, GBufferFormat::FP32);
  Checked c = renderAndCheck(f, technique("clustered", GBufferFormat::FP32, 16, 16));
  EXPECT_EQ(c.missed, 0u);
  EXPECT_LE(c.error.maxRelPeak, kFp32RelativeTolerance);
  EXPECT_EQ(c.result.counters.evaluations, 0u);

  Scene sky = builtinScene("street", "many");
  Bounds b = sky.bounds();
  glm::vec3 eye(0.0f, b.max.y + 10.0f, 0.0f);
  sky.cameraPath = {
      SceneCamera::lookAt(eye, eye + glm::vec3(0, 1, 0.01f), {0, 0, 1}, 1.0f, 0.1f, 500.0f)};
  PreparedFrame empty = prepareFrame(sky, 0, 64, 40, GBufferFormat::FP32);
  ASSERT_EQ(empty.gbuffer.geometryPixels(), 0u);
  Checked e = renderAndCheck(empty, technique("clustered", GBufferFormat::FP32, 16, 16));
  EXPECT_EQ(e.missed, 0u);
  EXPECT_EQ(e.result.counters.evaluations, 0u);
  EXPECT_EQ(e.result.counters.listMax, 0u);
  for (const auto& p : e.result.image) EXPECT_EQ(p, glm::vec4(0.0f));
}

TEST(ClusteredConfig, RejectsBadSliceCounts) {
  for (int slices : {0, -1, 100000}) {
    TechniqueConfig config;
    config.clusterSlices = slices;
    EXPECT_THROW(createTechnique("clustered", test::context(), config), Error) << slices;
  }
}

// The option check's limit is the technique's: the largest --slices accepted renders exactly, one
// more is refused with the limit named.
TEST(ClusteredConfig, TheLargestAcceptedSliceCountRenders) {
  PreparedFrame f = prepareFrame(builtinScene("street", "few"), 0, 64, 32, GBufferFormat::FP32);
  Checked c = renderAndCheck(f, technique("clustered", GBufferFormat::FP32, 16, kMaxClusterSlices));
  EXPECT_EQ(c.missed, 0u);
  EXPECT_LE(c.error.maxRelPeak, kFp32RelativeTolerance);
  TechniqueConfig config;
  config.clusterSlices = kMaxClusterSlices + 1;
  try {
    createTechnique("clustered", test::context(), config);
    ADD_FAILURE() << "accepted " << config.clusterSlices << " slices";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("1.." + std::to_string(kMaxClusterSlices)),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace ts
