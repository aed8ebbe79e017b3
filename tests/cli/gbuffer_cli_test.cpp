// The command line of --raster and --gbuffer-in: what stats.json and the bench record, a dump
// read back by every technique with --check and --heatmap, and one-line errors.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "test_support.h"

namespace ts {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;
using test::runTileshade;

fs::path fresh(const std::string& name) {
  fs::path p = fs::temp_directory_path() / ("tileshade_gbuffer_cli_" + name);
  fs::remove_all(p);
  return p;
}

json readJson(const fs::path& p) {
  std::ifstream in(p);
  return json::parse(in);
}

bool glAvailable(std::string& why) {
  test::CliRun r = runTileshade("render --raster gl --width 8 --height 8 --device cpu --out " +
                                fresh("probe").string());
  why = r.output;
  return r.status == 0;
}

TEST(GBufferCli, RenderRecordsWhichRasterizerRanAndItsTime) {
  if (!fs::exists(TILESHADE_BINARY)) GTEST_SKIP() << "tileshade binary not built";
  for (const char* raster : {"software", "gl"}) {
    const fs::path out = fresh(std::string("render_") + raster);
    test::CliRun r =
        runTileshade(std::string("render --raster ") + raster +
                     " --lights few --width 96 --height 54 --device cpu --out " + out.string());
    if (r.status != 0 && std::string(raster) == "gl" &&
        r.output.find("no OpenGL context") != std::string::npos)
      GTEST_SKIP() << r.output;
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find(std::string("raster: ") + raster), std::string::npos) << r.output;
    const json stats = readJson(out / "stats.json");
    EXPECT_EQ(stats.at("raster"), raster);
    EXPECT_GT(stats.at("raster_ms").get<double>(), 0.0);
    EXPECT_GE(stats.at("raster_setup_ms").get<double>(), 0.0);
  }
}

TEST(GBufferCli, DumpReadBackByEveryTechniqueWithCheckAndHeatmap) {
  if (!fs::exists(TILESHADE_BINARY)) GTEST_SKIP() << "tileshade binary not built";
  const fs::path dumped = fresh("dumped"), again = fresh("again");
  test::CliRun r = runTileshade(
      "render --scene builtin:atrium --width 80 --height 48 --gbuffer "
      "packed --device cpu --dump --out " +
      dumped.string());
  ASSERT_EQ(r.status, 0) << r.output;
  for (const char* f : {"gbuffer.exr", "gbuffer.json", "lights.json"})
    EXPECT_TRUE(fs::exists(dumped / f)) << f;
  r = runTileshade("render --gbuffer-in " + dumped.string() +
                   " --technique all --check --heatmap --device cpu --out " + again.string());
  ASSERT_EQ(r.status, 0) << r.output;
  const json stats = readJson(again / "stats.json");
  EXPECT_EQ(stats.at("raster"), "import");
  EXPECT_EQ(stats.at("gbuffer"), "packed");  // the dump's layout unless --gbuffer says otherwise
  EXPECT_EQ(stats.at("width"), 80);
  for (const auto& t : stats.at("techniques")) {
    EXPECT_EQ(t.at("missed_contributions"), 0) << t.at("technique");
    EXPECT_LE(t.at("error").at("max_rel_peak").get<double>(), 2e-5) << t.at("technique");
    EXPECT_TRUE(fs::exists(again / t.at("technique").get<std::string>() / "error.png"));
  }
  // The bench takes it as a scene.
  const fs::path bench = fresh("bench");
  r = runTileshade("bench --scene gbuffer:" + dumped.string() +
                   " --resolution 80x48 --technique tiled --gbuffer fp32,packed --frames 1 "
                   "--no-calibrate --quiet --device cpu --out " +
                   bench.string());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("raster ms"), std::string::npos) << r.output;
}

TEST(GBufferCli, BenchSweepsTheRasterizer) {
  if (!fs::exists(TILESHADE_BINARY)) GTEST_SKIP() << "tileshade binary not built";
  std::string why;
  if (!glAvailable(why)) GTEST_SKIP() << why;
  const fs::path bench = fresh("bench_raster");
  test::CliRun r = runTileshade(
      "bench --raster software,gl --lights few --resolution 96x54 "
      "--technique tiled --frames 2 --no-calibrate --quiet --device cpu "
      "--out " +
      bench.string());
  ASSERT_EQ(r.status, 0) << r.output;
  const json doc = readJson(bench / "bench.json");
  int rows[2] = {0, 0};
  for (const auto& row : doc.at("rows")) {
    const std::string raster = row.at("config").at("raster");
    ++rows[raster == "gl" ? 1 : 0];
    EXPECT_GT(row.at("raster_ms").get<double>(), 0.0);
  }
  EXPECT_EQ(rows[0], 2);
  EXPECT_EQ(rows[1], 2);
}

TEST(GBufferCli, BadInputFailsWithOneLine) {
  if (!fs::exists(TILESHADE_BINARY)) GTEST_SKIP() << "tileshade binary not built";
  const fs::path dumped = fresh("bad_dump");
  ASSERT_EQ(
      runTileshade("render --width 32 --height 18 --device cpu --dump --out " + dumped.string())
          .status,
      0);
  json lights = readJson(dumped / "lights.json");
  lights["lights"][0].erase("range");
  std::ofstream(dumped / "lights.json") << lights.dump();
  const std::string out = " --device cpu --out " + fresh("bad_out").string();
  for (const std::string& args : std::vector<std::string>{
           "render --raster vulkan", "render --gbuffer-in /nonexistent/folder",
           "render --gbuffer-in " + dumped.string(),
           "render --gbuffer-in " + dumped.string() + " --width 64",
           "render --gbuffer-in " + dumped.string() + " --raster gl",
           "bench --raster vulkan --no-calibrate --quiet",
           "bench --scene gbuffer:" + dumped.string() + " --no-calibrate --quiet"}) {
    test::CliRun r = runTileshade(args + out);
    EXPECT_NE(r.status, 0) << args;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << args << ": " << r.output;
    EXPECT_NE(r.output.find("error"), std::string::npos) << args << ": " << r.output;
  }
}

// bench on an imported G-buffer refuses the options only a scene's geometry serves (the files
// hold the surfaces and any shadow maps), in one line, rather than timing them as no-ops.
TEST(GBufferCli, BenchRefusesSceneOptionsOnAnImportedGBuffer) {
  if (!fs::exists(TILESHADE_BINARY)) GTEST_SKIP() << "tileshade binary not built";
  const fs::path dumped = fresh("scene_options_dump");
  ASSERT_EQ(runTileshade("render --width 32 --height 18 --device cpu --technique tiled --dump "
                         "--out " +
                         dumped.string())
                .status,
            0);
  const std::string bench = "bench --scene gbuffer:" + dumped.string() +
                            " --resolution 32x18 --technique tiled --frames 1 --no-calibrate "
                            "--quiet --device cpu --out " +
                            fresh("scene_options_out").string();
  for (const char* option : {"--shadows all", "--shadow-map-size 64", "--shadow-filter pcf3",
                             "--shadow-bias 1:2", "--blend as-opaque"}) {
    test::CliRun r = runTileshade(bench + " " + std::string(option));
    EXPECT_NE(r.status, 0) << option;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << option << ": " << r.output;
    EXPECT_NE(r.output.find("imported G-buffer"), std::string::npos) << option << ": " << r.output;
  }
}

// A GL driver that draws nothing (Mesa's softpipe here: 0 geometry pixels against the software
// rasterizer's thousands, and --check "max err 0") must not pass for a frame: either it drew,
// or the render fails naming the driver.
TEST(GBufferCli, GlDriverThatDrawsNothingIsAnError) {
  if (!fs::exists(TILESHADE_BINARY)) GTEST_SKIP() << "tileshade binary not built";
  const fs::path out = fresh("softpipe");
  const char* before = std::getenv("GALLIUM_DRIVER");
  const std::string saved = before ? before : "";
  setenv("GALLIUM_DRIVER", "softpipe", 1);
  test::CliRun r = runTileshade(
      "render --raster gl --lights few --width 96 --height 54 "
      "--device cpu --check --out " +
      out.string());
  if (before) setenv("GALLIUM_DRIVER", saved.c_str(), 1);
  else unsetenv("GALLIUM_DRIVER");
  if (r.output.find("no OpenGL context") != std::string::npos) GTEST_SKIP() << r.output;
  if (r.status == 0) {
    EXPECT_GT(readJson(out / "stats.json").at("geometry_pixels").get<int>(), 0) << r.output;
    return;
  }
  EXPECT_EQ(r.exitCode(), 1) << r.output;
  EXPECT_NE(r.output.find("tileshade: error: --raster gl: the OpenGL driver"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("drew no pixel"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace ts
