// `--variant glass` and `--blend blend` on the command line (issue #17): render --check with the
// forward techniques and tiled's hybrid composites the glass and measures them against the
// composited reference; `all` renders those and says what it leaves out; another G-buffer
// technique, the software rasterizer and the default policy refuse in one line.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "require_gl.h"
#include "test_support.h"

namespace ts {
namespace {

using test::CliRun;
using test::runTileshade;

int lines(const std::string& s) { return int(std::count(s.begin(), s.end(), '\n')); }

std::string glassRender(const std::filesystem::path& out) {
  return "render --scene builtin:atrium --variant glass --width 96 --height 54 --out " +
         out.string();
}

TEST(GlassCli, ForwardTechniquesCompositeAndCheck) {
  if (!std::filesystem::exists(TILESHADE_BINARY)) GTEST_SKIP() << "tileshade binary not built";
  REQUIRE_GL();
  const std::filesystem::path dir = test::freshDir("glass", "check");
  const CliRun r = runTileshade(glassRender(dir / "out") +
                                " --blend blend --raster gl --technique tiled-forward-prez "
                                "--technique forward --technique tiled --check");
  ASSERT_EQ(r.exitCode(), 0) << r.output;
  const nlohmann::json stats = nlohmann::json::parse(std::ifstream(dir / "out" / "stats.json"));
  EXPECT_EQ(stats["blend"], "blend");
  ASSERT_EQ(stats["techniques"].size(), 3u);
  for (const nlohmann::json& t : stats["techniques"]) {
    SCOPED_TRACE(t["technique"].get<std::string>());
    EXPECT_LE(t["error"]["max_rel_peak"].get<double>(), 1e-4);
    EXPECT_EQ(t["error"]["nonfinite_pixels"].get<int>(), 0);
    EXPECT_EQ(t["missed_contributions"].get<int>(), 0);
    bool transparent = false;
    for (const nlohmann::json& k : t["kernels"])
      transparent = transparent || (k["name"] == "transparent" && k["launches"].get<int>() > 0);
    EXPECT_TRUE(transparent);
  }
}

TEST(GlassCli, AllRendersTheCompositingTechniquesAndSaysWhatItLeavesOut) {
  if (!std::filesystem::exists(TILESHADE_BINARY)) GTEST_SKIP() << "tileshade binary not built";
  REQUIRE_GL();
  const std::filesystem::path dir = test::freshDir("glass", "all");
  const CliRun r =
      runTileshade(glassRender(dir / "out") + " --blend blend --raster gl --technique all");
  ASSERT_EQ(r.exitCode(), 0) << r.output;
  for (const char* left : {"deferred", "deferred-stencil", "clustered", "tiled-single", "brute"})
    EXPECT_NE(r.output.find(std::string("--technique all leaves out ") + left +
                            " (it shades the G-buffer"),
              std::string::npos)
        << r.output;
  EXPECT_EQ(r.output.find("leaves out tiled "), std::string::npos) << r.output;
  const nlohmann::json stats = nlohmann::json::parse(std::ifstream(dir / "out" / "stats.json"));
  std::vector<std::string> rendered;
  for (const nlohmann::json& t : stats["techniques"]) rendered.push_back(t["technique"]);
  EXPECT_EQ(rendered, (std::vector<std::string>{"tiled", "tiled-forward", "tiled-forward-prez",
                                                "clustered-forward", "forward", "forward-single"}));
}

TEST(GlassCli, RefusedInOneLineWhereItCannotBeComposited) {
  if (!std::filesystem::exists(TILESHADE_BINARY)) GTEST_SKIP() << "tileshade binary not built";
  const std::filesystem::path dir = test::freshDir("glass", "refused");
  struct Case {
    std::string options, expected;
  };
  std::vector<Case> cases = {
      {"", "alphaMode BLEND: --blend blend composites it"},  // the default policy
      {" --blend blend", "the software rasterizer draws none (use --raster gl)"},
  };
  try {
    EglContext::shared();
    cases.push_back({" --blend blend --raster gl --technique deferred",
                     "technique 'deferred' shades the G-buffer, which holds the opaque surfaces"});
  } catch (const Error&) {
    // Without OpenGL the G-buffer technique's refusal cannot be reached.
  }
  for (const Case& c : cases) {
    SCOPED_TRACE(c.options);
    const CliRun r = runTileshade(glassRender(dir / "out") + c.options);
    EXPECT_EQ(r.exitCode(), 1) << r.output;
    EXPECT_EQ(lines(r.output), 1) << r.output;
    EXPECT_NE(r.output.find("tileshade: error: "), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(c.expected), std::string::npos) << r.output;
  }
}

}  // namespace
}  // namespace ts
