// `render --raster gl` with shadow-casting lights: OpenGL draws the maps (stats.json says so), and
// the image shaded from them passes --check against the reference that samples the same maps.
// Skips where no OpenGL context can be made.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include <nlohmann/json.hpp>

#include "require_gl.h"
#include "test_support.h"

namespace ts {
namespace {

using test::CliRun;
using test::runTileshade;

TEST(GlShadowMapsCli, RasterGlDrawsTheMapsAndTheImagePassesTheCheck) {
  if (!std::filesystem::exists(TILESHADE_BINARY)) GTEST_SKIP() << "tileshade binary not built";
  REQUIRE_GL();
  const auto tmp = test::freshDir("cli", "gl_shadow_maps");
  const CliRun r = runTileshade(
      "render --scene builtin:atrium --width 96 --height 54 --device cpu --raster gl "
      "--shadows 3 --shadow-map-size 64 --shadow-filter pcf3 --technique tiled --check --out " +
      tmp.string());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("ms (gl, depth only)"), std::string::npos) << r.output;
  const nlohmann::json stats = nlohmann::json::parse(std::ifstream(tmp / "stats.json"));
  const nlohmann::json& s = stats.at("shadow_maps");
  ASSERT_TRUE(s.is_object()) << stats.dump();
  EXPECT_EQ(s.at("rasterizer"), "gl");
  EXPECT_EQ(s.at("faces"), 18);
  EXPECT_GT(s.at("triangles_drawn").get<uint64_t>(), 0u);
  EXPECT_GE(s.at("read_ms").get<double>(), 0.0);
  for (const auto& t : stats.at("techniques")) {
    EXPECT_EQ(t.at("missed_contributions"), 0) << t.at("technique");
    EXPECT_LE(t.at("error").at("max_rel_peak").get<double>(), 1e-4) << t.at("technique");
  }
  // The software rasterizer's maps say so too.
  const CliRun soft = runTileshade(
      "render --scene builtin:atrium --width 96 --height 54 --device cpu --shadows 3 "
      "--shadow-map-size 64 --technique tiled --out " +
      tmp.string());
  ASSERT_EQ(soft.status, 0) << soft.output;
  const nlohmann::json softStats = nlohmann::json::parse(std::ifstream(tmp / "stats.json"));
  EXPECT_EQ(softStats.at("shadow_maps").at("rasterizer"), "software");
  EXPECT_EQ(softStats.at("shadow_maps").at("read_ms"), 0.0);
  EXPECT_EQ(softStats.at("shadow_maps").at("triangles_drawn"), s.at("triangles_drawn"));
  std::filesystem::remove_all(tmp);
}

// bench --raster gl draws each frame's maps with OpenGL too: shadow_ms and shadow_bytes in its
// rows, the same atlas as the software rasterizer's, and within 1e-4 of the reference.
TEST(GlShadowMapsCli, BenchDrawsTheMapsWithTheConfigurationsRasterizer) {
  if (!std::filesystem::exists(TILESHADE_BINARY)) GTEST_SKIP() << "tileshade binary not built";
  REQUIRE_GL();
  const auto tmp = test::freshDir("cli", "gl_shadow_maps_bench");
  const CliRun r = runTileshade(
      "bench --scene builtin:atrium --raster software,gl --shadows 2 --shadow-map-size 32 "
      "--resolution 96x54 --technique tiled --frames 1 --no-calibrate --error --quiet --device "
      "cpu --out " +
      tmp.string());
  ASSERT_EQ(r.status, 0) << r.output;
  const nlohmann::json bench = nlohmann::json::parse(std::ifstream(tmp / "bench.json"));
  std::map<std::string, uint64_t> bytes;
  for (const auto& row : bench.at("rows")) {
    const std::string raster = row.at("config").at("raster");
    EXPECT_GT(row.at("shadow_ms").get<double>(), 0.0) << raster;
    EXPECT_LE(row.at("error").at("max_rel_peak").get<double>(), 1e-4) << raster;
    bytes[raster] = row.at("shadow_bytes").get<uint64_t>();
  }
  ASSERT_EQ(bytes.size(), 2u) << bench.dump();
  EXPECT_GT(bytes["gl"], 0u);
  EXPECT_EQ(bytes["gl"], bytes["software"]);
  std::filesystem::remove_all(tmp);
}

}  // namespace
}  // namespace ts
