// The command line end to end: bad input gives one line on stderr and a non-zero exit; a render
// writes its images, stats and dump.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "test_support.h"

namespace ts {
namespace {

// The command line: bad input gives one line on stderr and a non-zero exit.
using test::CliRun;
using test::runTileshade;

TEST(CommandLine, BadInputFailsWithOneLine) {
  if (!std::filesystem::exists(TILESHADE_BINARY)) GTEST_SKIP() << "tileshade binary not built";
  auto tmp = std::filesystem::temp_directory_path() / "tileshade_cli_test";
  std::string out = " --out " + tmp.string() + " --width 64 --height 36";
  for (const char* args : {"render --scene builtin:nowhere", "render --technique nonsense",
                           "render --scene /nonexistent/file.gltf", "render --tile 0",
                           "render --gbuffer fp8", "render --device no-such-device",
                           "render --lights nonsense", "render --width", "render --frobnicate"}) {
    std::string a = args;
    CliRun r =
        runTileshade(a + out + (a.find("--device") == std::string::npos ? " --device cpu" : ""));
    EXPECT_NE(r.status, 0) << args;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << args << ": " << r.output;
    EXPECT_NE(r.output.find("error"), std::string::npos) << args << ": " << r.output;
  }
}

TEST(CommandLine, RenderWritesImagesStatsAndDump) {
  if (!std::filesystem::exists(TILESHADE_BINARY)) GTEST_SKIP() << "tileshade binary not built";
  auto tmp = std::filesystem::temp_directory_path() / "tileshade_cli_render";
  std::filesystem::remove_all(tmp);
  CliRun r = runTileshade(
      "render --scene builtin:street --lights few --width 96 --height 54 "
      "--device cpu --check --dump --out " +
      tmp.string());
  ASSERT_EQ(r.status, 0) << r.output;
  for (const char* f : {"image.exr", "image.png", "stats.json", "gbuffer.exr", "lights.json"})
    EXPECT_TRUE(std::filesystem::exists(tmp / f)) << f;
  EXPECT_NE(r.output.find("tiled"), std::string::npos);
  EXPECT_NE(r.output.find("shading err"), std::string::npos) << r.output;
  // Both windowed errors: from depth in double, and from the kernels' float positions.
  const nlohmann::json stats = nlohmann::json::parse(std::ifstream(tmp / "stats.json"));
  const nlohmann::json& t = stats["techniques"][0];
  for (const char* key : {"error", "error_shading", "error_vs_physical"}) {
    ASSERT_TRUE(t.contains(key)) << key;
    EXPECT_LE(t[key]["max_rel_peak"].get<double>(),
              std::string(key) == "error_vs_physical" ? 1.0 : 2e-5)
        << key;
  }
  EXPECT_NE(t["error"]["max_rel_peak"], t["error_shading"]["max_rel_peak"]);
}

}  // namespace
}  // namespace ts
