// clustered-forward (src/techniques/clustered_forward.cpp): clustered's grid over the scene's view
// depth, read by the forward fragment shader from each fragment's own depth, against the double
// reference of the same rasterization (opaque and glass), against tiled-forward and clustered,
// and its refusals. Skips, saying why, where no OpenGL context can be made.
#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <iostream>
#include <string>

#include "gl_frame.h"
#include "reference/transparent_composite.h"
#include "reference_check.h"
#include "require_gl.h"
#include "scene/scene_loader.h"
#include "util/error.h"

namespace ts {
namespace {

using test::GlFrame;

// Issue #17's bound for forward images (gl_tiled_forward_test.cpp explains it).
constexpr double kForwardBound = 1e-4;
constexpr const char* kTechnique = "clustered-forward";

bool hasRow(const FrameResult& r, const std::string& name) {
  for (const KernelTime& k : r.kernels)
    if (k.name == name && k.launches > 0) return true;
  return false;
}

Scene builtin(const std::string& name, const std::string& variant = "",
              BlendPolicy blend = BlendPolicy::AsOpaque) {
  SceneOptions options;
  options.lightSet = name == "street" ? "few" : name == "street-many" ? "many" : "small";
  options.variant = variant;
  options.blend = blend;
  return loadScene(name == "street-many" ? "builtin:street" : "builtin:" + name, options);
}

TEST(ClusteredForward, MatchesTheReferenceOfTheSameRasterization) {
  REQUIRE_GL();
  for (const char* name : {"street", "atrium", "street-many"}) {
    SCOPED_TRACE(name);
    const Scene scene = builtin(name);  // outlives g, which draws it
    GlFrame g(scene, 0, 96, 54);
    const FrameResult r = g.render(kTechnique);
    const ErrorStats e = test::expectMatchesReference(g, r, kForwardBound);
    for (const char* row : {"slice_bounds", "bin_count", "grid_copy", "forward"})
      EXPECT_TRUE(hasRow(r, row)) << row;
    EXPECT_GT(r.counters.lightingComputations, 0u);
    EXPECT_EQ(r.counters.gbufferBytesRead, 0u);
    std::cout << "[ clustered-forward ] " << name << ": max error " << e.maxRelPeak
              << " of the peak, " << r.counters.lightingComputations
              << " lighting computations, lights per cluster mean " << r.counters.listMean << "\n";
  }
}

// Spot and directional lights, metallic-roughness terms, at an odd size (partial edge tiles).
TEST(ClusteredForward, MatchesTheReferenceWithSpotsAndSunAtAnOddSize) {
  REQUIRE_GL();
  const Scene scene = builtin("atrium", "metallic-roughness,spot,sun");
  GlFrame g(scene, 1, 67, 37);
  test::expectMatchesReference(g, g.render(kTechnique), kForwardBound);
}

// A real scene (normal maps on most materials), skipped where ../shared/scenes is absent.
TEST(ClusteredForward, MatchesTheReferenceOnARealScene) {
  REQUIRE_GL();
  const std::filesystem::path path = test::sharedScene("dungeon/level-dungeon.gltf");
  if (path.empty()) GTEST_SKIP() << "../shared/scenes/dungeon absent";
  std::vector<std::string> warnings;
  const Scene scene = loadGltf(path, &warnings);
  GlFrame g(scene, 0, 96, 54);
  test::expectMatchesReference(g, g.render(kTechnique), kForwardBound);
}

// The glass variant: each transparent fragment looks its own cluster up from its depth, so its
// list is exact without the opaque depth: within the bound of the composited reference, no NaN,
// no missed contribution on the opaque surfaces, the glass drawn (its row, and far from the
// opaque reference).
TEST(ClusteredForward, GlassMatchesTheCompositedReference) {
  REQUIRE_GL();
  for (const char* name : {"street", "atrium"}) {
    SCOPED_TRACE(name);
    const Scene scene = builtin(name, "glass", BlendPolicy::Blend);
    GlFrame g(scene, 0, 96, 54);
    ASSERT_GT(g.forward->transparentDraws(), 0u);
    const PreparedFrame& f = g.prepared;
    const ReferenceImage opaque = shadeReference(f.encoded, f.intrinsics, f.lights, f.ambient, 0);
    ReferenceImage ref = opaque;
    compositeTransparent(ref, g.forward->captureTransparent(g.features, kCaptureBound), f.lights,
                         f.ambient, 0, f.encoded);
    const FrameResult r = g.render(kTechnique);
    const ErrorStats e = compareToReference(r.image, ref, kForwardBound * ref.peak);
    EXPECT_LE(e.maxRelPeak, kForwardBound);
    EXPECT_EQ(e.nonfinitePixels, 0u);
    EXPECT_GT(compareToReference(r.image, opaque, 1e-3 * opaque.peak).maxRelPeak, 1e-2);
    ASSERT_TRUE(r.assignment.has_value());
    EXPECT_EQ(countMissedContributions(*r.assignment, f.encoded, f.intrinsics, f.lights, 0), 0u);
    EXPECT_TRUE(hasRow(r, "transparent"));
    // The same glass fragments as tiled-forward with the same function, from lists that hold
    // every light reaching them: the same image to fp32 rounding.
    EXPECT_LE(test::relativeDifference(r.image, g.render("tiled-forward").image),
              test::kFp32RelativeTolerance);
    std::cout << "[ clustered-forward ] glass on " << name << ": max error " << e.maxRelPeak
              << " of the peak\n";
  }
}

// Opaque, no MSAA: tiled-forward shades the same fragments with the same function (its tile
// lists hold more lights, which add exactly zero), so fp32 rounding; clustered shades the
// position rebuilt from the G-buffer's depth instead of the interpolated one, within the forward
// bound (as forward against tiled, gl_forward_test.cpp). The clusters cull by depth too: no more
// lighting computations than tiled-forward's tiles.
TEST(ClusteredForward, AgreesWithTiledForwardAndClustered) {
  REQUIRE_GL();
  for (const char* name : {"street-many", "atrium"}) {
    SCOPED_TRACE(name);
    const Scene scene = builtin(name);
    GlFrame g(scene, 2, 128, 72);
    const FrameResult r = g.render(kTechnique);
    const FrameResult tiledForward = g.render("tiled-forward");
    const double toTiledForward = test::relativeDifference(r.image, tiledForward.image);
    const double toClustered = test::relativeDifference(r.image, g.render("clustered").image);
    EXPECT_LE(toTiledForward, test::kFp32RelativeTolerance);
    EXPECT_LE(toClustered, kForwardBound);
    EXPECT_LE(r.counters.lightingComputations, tiledForward.counters.lightingComputations);
    std::cout << "[ clustered-forward ] " << name << ": vs tiled-forward " << toTiledForward
              << ", vs clustered " << toClustered << " of the peak; lighting computations "
              << r.counters.lightingComputations << " vs tiled-forward's "
              << tiledForward.counters.lightingComputations << "\n";
  }
}

// One slice is tiled-forward's grid with the scene's depth range: the same image.
TEST(ClusteredForward, OneSliceIsATiledGrid) {
  REQUIRE_GL();
  const Scene scene = builtin("atrium");
  GlFrame g(scene, 0, 64, 36);
  TechniqueConfig c = g.config();
  c.clusterSlices = 1;
  const FrameResult r = g.render(*createTechnique(kTechnique, test::context(), c));
  test::expectMatchesReference(g, r, kForwardBound);
  EXPECT_LE(test::relativeDifference(r.image, g.render("tiled-forward").image),
            test::kFp32RelativeTolerance);
}

// --msaa is refused in one line, as is a frame with no scene to draw.
TEST(ClusteredForward, RefusesMsaaAndAFrameWithoutAScene) {
  const PreparedFrame f =
      prepareFrame(test::builtinScene("atrium", "small"), 0, 32, 18, GBufferFormat::FP32);
  DeviceFrame frame = f.upload(test::context());
  auto refusal = [](const std::function<void()>& run) {
    try {
      run();
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  std::string what = refusal([&] {
    createTechnique(kTechnique, test::context(), TechniqueConfig{})->render(frame, FrameRequest{});
  });
  EXPECT_NE(what.find("--raster gl"), std::string::npos) << what;
  EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  REQUIRE_GL();
  const Scene scene = builtin("atrium");
  GlFrame g(scene, 0, 32, 18, analyzeScene(scene, ShadingModel::BlinnPhong), 4);
  what = refusal([&] { g.render(kTechnique); });
  EXPECT_NE(what.find("clustered-forward' with --msaa 4 is not done"), std::string::npos) << what;
  EXPECT_EQ(what.find('\n'), std::string::npos) << what;
}

// The command line: refused without --raster gl before any file, left out of `all` with a line;
// with it, `all` renders it and checks it.
TEST(ClusteredForward, CommandLineRefusesOrIncludes) {
  const std::filesystem::path dir = test::freshDir("clustered_forward", "cli");
  const std::string size = " --width 32 --height 18 --out " + (dir / "out").string();
  test::CliRun r = test::runTileshade("render --technique clustered-forward" + size);
  EXPECT_EQ(r.exitCode(), 1) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "out"));
  r = test::runTileshade("render --technique all" + size);
  EXPECT_EQ(r.exitCode(), 0) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "out" / "clustered-forward"));
  EXPECT_NE(r.output.find("--technique all leaves out clustered-forward"), std::string::npos)
      << r.output;
  REQUIRE_GL();
  r = test::runTileshade(
      "render --scene builtin:atrium --variant glass --blend blend --raster gl --technique all "
      "--check" +
      size);
  EXPECT_EQ(r.exitCode(), 0) << r.output;
  EXPECT_TRUE(std::filesystem::exists(dir / "out" / "clustered-forward" / "image.png")) << r.output;
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace ts
