// tiled-forward and tiled-forward-prez (src/techniques/tiled_forward.cpp): the scene drawn in
// OpenGL with tiled's OpenCL light grid, against the double reference shaded from the G-buffer
// the same OpenGL rasterizer draws for the same camera (the same surfaces). Skips, saying why,
// where no OpenGL context can be made.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>

#include "gl_frame.h"
#include "raster/egl_context.h"
#include "raster/raster_backend.h"
#include "reference_check.h"
#include "require_gl.h"
#include "util/error.h"

namespace ts {
namespace {

// The bound. The forward pass shades the position its vertices interpolate (float), the
// reference the position rebuilt from the stored depth (double, from the same fragment's
// interpolated depth): the same point up to float rounding of the transform and the
// interpolation, |dP| <= ~1e-6 |P| (docs/opengl.md measures the rasterizers' attribute
// differences). A light's term moves by ~2 |dP| / d relative (the inverse square dominates), so
// a surface at 30 units with a light at d = 0.5 gives ~1e-4 of that term; on top, the fp32 sums
// (2e-5 of the peak, every kernel's bound). Measured: below 4e-6 of the peak on these frames.
// 1e-4 of the peak (issue #17's target) covers both with margin, and a missed or doubled light
// (>= 1e-3 of the peak here) still fails.
constexpr double kForwardBound = 1e-4;

const Scene& forwardScene(const std::string& name) {
  static std::map<std::string, Scene> cache;
  auto it = cache.find(name);
  if (it != cache.end()) return it->second;
  SceneOptions options;
  if (name == "dungeon") {  // normal maps on 10 of its 11 materials: the forward pass applies them
    std::vector<std::string> warnings;
    return cache.emplace(name, loadGltf(test::sharedScene("dungeon/level-dungeon.gltf"), &warnings))
        .first->second;
  }
  if (name == "atrium-mr") {
    options.lightSet = "small";
    options.variant = "metallic-roughness,spot,sun";  // spot and directional lights, glTF terms
    return cache.emplace(name, loadScene("builtin:atrium", options)).first->second;
  }
  options.lightSet = name == "atrium" ? "small" : "few";
  return cache.emplace(name, loadScene("builtin:" + name, options)).first->second;
}

void checkForward(const std::string& technique, const std::string& name) {
  SCOPED_TRACE(technique + " on " + name);
  test::GlFrame g(forwardScene(name), 1, 96, 54);
  ASSERT_NE(g.forward, nullptr);
  const PreparedFrame& f = g.prepared;
  const FrameResult r = g.render(technique);
  const ErrorStats e = test::expectMatchesReference(g, r, kForwardBound);
  // Every geometry pixel is shaded at least once (at least its tile's list), so the count is at
  // least the tiled count over geometry pixels; the passes have their own rows.
  EXPECT_GT(r.counters.lightingComputations, 0u);
  auto has = [&](const char* name) {
    return std::any_of(r.kernels.begin(), r.kernels.end(),
                       [&](const KernelTime& k) { return k.name == name; });
  };
  EXPECT_TRUE(has("grid_copy"));
  EXPECT_TRUE(has("forward"));
  EXPECT_EQ(has("depth_prepass"), technique == "tiled-forward-prez");
  EXPECT_EQ(has("depth_bounds"), technique == "tiled-forward-prez");
  std::cout << "[ forward ] " << technique << " " << name << ": " << f.lights.size()
            << " lights, max error " << e.maxRelPeak << " of the peak, "
            << r.counters.lightingComputations << " lighting computations\n";
}

TEST(TiledForward, MatchesTheReferenceOfTheSameRasterization) {
  REQUIRE_GL();
  for (const char* name : {"atrium", "street", "atrium-mr"})
    for (const char* technique : {"tiled-forward", "tiled-forward-prez"})
      checkForward(technique, name);
}

TEST(TiledForward, AppliesNormalMapsAsTheGBufferPassDoes) {
  REQUIRE_GL();
  if (test::sharedScene("dungeon/level-dungeon.gltf").empty())
    GTEST_SKIP() << "../shared/scenes/dungeon absent";
  ASSERT_TRUE(analyzeScene(forwardScene("dungeon"), ShadingModel::MetallicRoughness).normalMaps);
  checkForward("tiled-forward", "dungeon");
}

// The pre-pass shades each pixel once: no more lighting computations than without it, where
// every fragment that passes the depth test at its turn is shaded.
TEST(TiledForward, PrepassShadesNoMoreThanTheSinglePass) {
  REQUIRE_GL();
  test::GlFrame g(test::builtinScene("street", "few"), 0, 96, 54,
                  SceneFeatures::general(ShadingModel::BlinnPhong));
  uint64_t counts[2] = {0, 0};
  int i = 0;
  for (const char* technique : {"tiled-forward", "tiled-forward-prez"})
    counts[i++] = g.render(technique).counters.lightingComputations;
  EXPECT_LE(counts[1], counts[0]);
}

// A frame with no scene to draw (software raster, imported G-buffer) is refused in one line.
TEST(TiledForward, RefusesAFrameWithoutAScene) {
  const PreparedFrame f =
      prepareFrame(test::builtinScene("atrium", "small"), 0, 32, 18, GBufferFormat::FP32);
  DeviceFrame frame = f.upload(test::context());
  for (const char* technique : {"tiled-forward", "tiled-forward-prez"}) {
    try {
      createTechnique(technique, test::context(), TechniqueConfig{})->render(frame, FrameRequest{});
      ADD_FAILURE() << technique << " rendered a frame without a scene";
    } catch (const Error& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("--raster gl"), std::string::npos) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
  }
}

// The command line: without --raster gl a forward technique is refused before any file is
// written, and `all` says what it leaves out; with it, `all` renders the forward ones too.
TEST(TiledForward, CommandLineRefusesOrIncludes) {
  const std::filesystem::path dir = test::freshDir("tiled_forward", "cli");
  const std::string size = " --width 32 --height 18 --out " + (dir / "out").string();
  test::CliRun r = test::runTileshade("render --technique tiled tiled-forward" + size);
  EXPECT_EQ(r.exitCode(), 1) << r.output;
  EXPECT_NE(r.output.find("tiled-forward draws the scene: it needs a frame rasterized with "
                          "--raster gl"),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "out"));
  r = test::runTileshade("render --technique all" + size);
  EXPECT_EQ(r.exitCode(), 0) << r.output;
  EXPECT_NE(r.output.find("--technique all leaves out tiled-forward-prez"), std::string::npos)
      << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "out" / "tiled-forward"));
  REQUIRE_GL();
  r = test::runTileshade("render --raster gl --technique all --check" + size);
  EXPECT_EQ(r.exitCode(), 0) << r.output;
  EXPECT_EQ(r.output.find("leaves out"), std::string::npos) << r.output;
  EXPECT_TRUE(std::filesystem::exists(dir / "out" / "tiled-forward-prez" / "image.png"))
      << r.output;
  std::filesystem::remove_all(dir);
}

// `all` without a scene: the G-buffer techniques, every one but the forward family.
TEST(TiledForward, GbufferTechniquesLeaveOutTheForwardFamily) {
  const std::vector<std::string> all = techniqueNames(), gbuffer = gbufferTechniqueNames();
  EXPECT_EQ(all.size(), gbuffer.size() + 5);
  for (const char* t :
       {"tiled-forward", "tiled-forward-prez", "clustered-forward", "forward", "forward-single"}) {
    EXPECT_NE(std::find(all.begin(), all.end(), t), all.end());
    EXPECT_EQ(std::find(gbuffer.begin(), gbuffer.end(), t), gbuffer.end());
  }
}

}  // namespace
}  // namespace ts
