// `--msaa` on the command line (issue #17): render --check of a forward technique with 4 samples
// records msaa and passes the per-sample reference; bad counts, the software rasterizer, an
// imported G-buffer, glass and a G-buffer technique are refused in one line.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "raster/gl_rasterizer.h"
#include "require_gl.h"
#include "scene/scene_loader.h"
#include "test_support.h"

namespace ts {
namespace {

using test::CliRun;
using test::runTileshade;

int lines(const std::string& s) { return int(std::count(s.begin(), s.end(), '\n')); }

std::string msaaRender(const std::filesystem::path& out) {
  return "render --scene builtin:street --width 96 --height 54 --out " + out.string();
}

bool glGivesSamples(int samples) {
  try {
    const Scene scene = loadScene("builtin:atrium", {});
    GlRasterizer gl(scene);
    return gl.maxSamples() >= samples;
  } catch (const Error&) {
    return false;  // no context
  }
}

TEST(MsaaCli, ForwardTechniqueChecksAgainstThePerSampleReference) {
  if (!std::filesystem::exists(TILESHADE_BINARY)) GTEST_SKIP() << "tileshade binary not built";
  REQUIRE_GL();
  if (!glGivesSamples(4)) GTEST_SKIP() << "the OpenGL implementation renders fewer than 4 samples";
  const std::filesystem::path dir = test::freshDir("msaa", "check");
  const CliRun r =
      runTileshade(msaaRender(dir / "out") + " --raster gl --msaa 4 --technique all --check");
  ASSERT_EQ(r.exitCode(), 0) << r.output;
  // `all` leaves the G-buffer techniques without it out, saying so.
  EXPECT_NE(r.output.find("--technique all leaves out tiled-single (--msaa 4"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("--technique all leaves out forward-single (--msaa 4"), std::string::npos)
      << r.output;
  const nlohmann::json stats = nlohmann::json::parse(std::ifstream(dir / "out" / "stats.json"));
  EXPECT_EQ(stats["msaa"], 4);
  // tiled, clustered, tiled-forward, tiled-forward-prez
  ASSERT_EQ(stats["techniques"].size(), 4u);
  for (const nlohmann::json& t : stats["techniques"]) {
    SCOPED_TRACE(t["technique"].get<std::string>());
    EXPECT_LE(t["error"]["max_rel_peak"].get<double>(), 1e-4);
    EXPECT_EQ(t["missed_contributions"].get<int>(), 0);
    EXPECT_EQ(t.contains("msaa_gbuffer"),
              t["technique"] == "tiled" || t["technique"] == "clustered");
  }
  // The G-buffer techniques find the same edges (the same per-sample G-buffer, the same rule).
  ASSERT_EQ(stats["techniques"][1]["technique"], "clustered");
  EXPECT_EQ(stats["techniques"][1]["msaa_gbuffer"], stats["techniques"][0]["msaa_gbuffer"]);
  // tiled's multisampled G-buffer: 4x the frame's bytes; edges some of the pixels, in the table.
  const nlohmann::json& tiled = stats["techniques"][0];
  ASSERT_EQ(tiled["technique"], "tiled");
  const uint64_t pixels = 96 * 54;
  EXPECT_EQ(tiled["msaa_gbuffer"]["samples"], 4);
  EXPECT_EQ(tiled["msaa_gbuffer"]["gbuffer_bytes"].get<uint64_t>(),
            4 * pixels * stats["gbuffer_bytes_per_pixel"].get<uint64_t>());
  const uint64_t edges = tiled["msaa_gbuffer"]["pixels_shaded_per_sample"].get<uint64_t>();
  EXPECT_GT(edges, 0u);
  EXPECT_LT(edges, pixels);
  EXPECT_NE(r.output.find("per-sample shading: " + std::to_string(edges) + " of 5184 pixels"),
            std::string::npos)
      << r.output;
}

TEST(MsaaCli, RefusedInOneLine) {
  if (!std::filesystem::exists(TILESHADE_BINARY)) GTEST_SKIP() << "tileshade binary not built";
  const std::filesystem::path dir = test::freshDir("msaa", "refused");
  struct Case {
    std::string options, expected;
  };
  std::vector<Case> cases = {
      {" --msaa 3", "--msaa 3: samples a pixel must be 1, 2, 4 or 8"},
      {" --msaa 0", "--msaa 0: samples a pixel must be 1, 2, 4 or 8"},
      {" --msaa 4", "--msaa 4 needs --raster gl"},
      {" --msaa 4 --raster software --technique tiled", "--msaa 4 needs --raster gl"},
      {" --msaa 4 --raster gl --exact-visibility", "--exact-visibility with --msaa 4"},
  };
  if (glGivesSamples(4)) {
    cases.push_back({" --msaa 4 --raster gl --technique tiled-single",
                     "technique 'tiled-single' shades the G-buffer: --msaa 4"});
    cases.push_back({" --msaa 4 --raster gl --technique forward-single",
                     "technique 'forward-single' with --msaa 4 is not done"});
    cases.push_back(
        {" --msaa 4 --raster gl --variant glass --blend blend --technique "
         "tiled-forward",
         "--msaa 4 with transparent draws (--blend blend) is not done"});
  }
  for (const Case& c : cases) {
    SCOPED_TRACE(c.options);
    const CliRun r = runTileshade(msaaRender(dir / "out") + c.options);
    EXPECT_EQ(r.exitCode(), 1) << r.output;
    EXPECT_EQ(lines(r.output), 1) << r.output;
    EXPECT_NE(r.output.find("tileshade: error: "), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(c.expected), std::string::npos) << r.output;
  }
  const CliRun imported =
      runTileshade("render --gbuffer-in " + (dir / "none").string() + " --msaa 2");
  EXPECT_EQ(imported.exitCode(), 1) << imported.output;
  EXPECT_EQ(lines(imported.output), 1) << imported.output;
}

}  // namespace
}  // namespace ts
