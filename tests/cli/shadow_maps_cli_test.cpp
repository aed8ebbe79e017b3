// `render` with shadow-casting lights: the shadow atlas in stats.json and --dump, the budget's
// note, the images (a shadow only takes light away), and bad shadow-map options.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "gbuffer/image_io.h"
#include "require_gl.h"
#include "test_support.h"

namespace ts {
namespace {

using test::CliRun;
using test::runTileshade;

const std::string kFrame = "render --scene builtin:atrium --width 64 --height 36 --device cpu ";

TEST(ShadowMapsCli, StatsAndDumpHoldTheAtlas) {
  if (!std::filesystem::exists(TILESHADE_BINARY)) GTEST_SKIP() << "tileshade binary not built";
  const auto tmp = std::filesystem::temp_directory_path() / "tileshade_cli_shadow_maps";
  const auto plain = std::filesystem::temp_directory_path() / "tileshade_cli_shadow_maps_none";
  std::filesystem::remove_all(tmp);
  std::filesystem::remove_all(plain);
  CliRun r = runTileshade(kFrame + "--shadows 3 --shadow-map-size 64 --dump --out " + tmp.string());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("shadow maps: 18 face(s) of 3 light(s)"), std::string::npos) << r.output;
  const nlohmann::json stats = nlohmann::json::parse(std::ifstream(tmp / "stats.json"));
  const nlohmann::json& s = stats["shadow_maps"];
  ASSERT_TRUE(s.is_object()) << stats.dump();
  EXPECT_EQ(s["map_size"], 64);
  EXPECT_EQ(s["budget_mb"], 64.0);
  ASSERT_EQ(s["lights"].size(), 3u);
  uint64_t faces = 0, area = 0;
  for (const auto& l : s["lights"]) {
    EXPECT_EQ(l["size"], 64);
    faces += l["faces"].get<uint64_t>();
    area += l["faces"].get<uint64_t>() * 64 * 64;
  }
  EXPECT_EQ(s["faces"].get<uint64_t>(), faces);
  const int w = s["atlas_width"], h = s["atlas_height"];
  EXPECT_EQ(s["bytes"].get<uint64_t>(), uint64_t(w) * uint64_t(h) * 4u);
  EXPECT_GE(uint64_t(w) * uint64_t(h), area);
  EXPECT_GT(s["triangles_drawn"].get<uint64_t>(), 0u);
  EXPECT_TRUE(s["notes"].empty());

  // The dumped atlas: its size, and per face depths within (0, zfar]; some faces see geometry
  // within their light's range (the atrium's lights are small: not every face does).
  const FloatImage atlas = readImage((tmp / "shadow_atlas.exr").string());
  ASSERT_EQ(atlas.width, w);
  ASSERT_EQ(atlas.height, h);
  ASSERT_EQ(atlas.channels.size(), 1u);
  EXPECT_EQ(atlas.channels[0], "depth");
  const nlohmann::json layout = nlohmann::json::parse(std::ifstream(tmp / "shadow_atlas.json"));
  ASSERT_EQ(layout["faces"].size(), faces);
  size_t near = 0;
  for (const auto& f : layout["faces"]) {
    const int x0 = f["x"], y0 = f["y"], size = f["size"];
    const float zfar = f["zfar"];
    size_t bad = 0;
    for (int y = y0; y < y0 + size; ++y)
      for (int x = x0; x < x0 + size; ++x) {
        const float d = atlas.data[size_t(y) * size_t(w) + size_t(x)];
        bad += !(d > 0.0f && d <= zfar);
        near += d < zfar;
      }
    EXPECT_EQ(bad, 0u) << f.dump();
  }
  EXPECT_GT(near, 0u);

  // A shadow factor in [0, 1] multiplies each contribution and the sums are taken in the same
  // order, so (rounding being monotonic) no pixel gains light; some lose it (with every light
  // casting: the three of largest range darken none of these 64x36 pixels).
  r = runTileshade(kFrame + "--shadows none --out " + plain.string());
  ASSERT_EQ(r.status, 0) << r.output;
  r = runTileshade(kFrame + "--shadows all --out " + tmp.string());
  ASSERT_EQ(r.status, 0) << r.output;
  // (Pixels, not bytes: the EXR header holds the time it was written.)
  const FloatImage shadowed = readImage((tmp / "image.exr").string());
  const FloatImage unshadowed = readImage((plain / "image.exr").string());
  EXPECT_GT(shadowed.data.size(), 0u);
  ASSERT_EQ(shadowed.data.size(), unshadowed.data.size());
  size_t darker = 0, brighter = 0;
  for (size_t i = 0; i < shadowed.data.size(); ++i) {
    darker += shadowed.data[i] < unshadowed.data[i];
    brighter += shadowed.data[i] > unshadowed.data[i];
  }
  EXPECT_EQ(brighter, 0u);
  EXPECT_GT(darker, 0u);
  const nlohmann::json none = nlohmann::json::parse(std::ifstream(plain / "stats.json"));
  EXPECT_TRUE(none["shadow_maps"].is_null());
  EXPECT_FALSE(std::filesystem::exists(plain / "shadow_atlas.exr"));
}

TEST(ShadowMapsCli, TheBudgetShrinksMapsWithANote) {
  if (!std::filesystem::exists(TILESHADE_BINARY)) GTEST_SKIP() << "tileshade binary not built";
  const auto tmp = std::filesystem::temp_directory_path() / "tileshade_cli_shadow_budget";
  std::filesystem::remove_all(tmp);
  CliRun r = runTileshade(kFrame + "--shadows 20 --shadow-budget 1 --out " + tmp.string(),
                          test::Streams::StderrOnly);
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("tileshade: note: shadow maps: "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("lost resolution to --shadow-budget 1 MB"), std::string::npos)
      << r.output;
  const nlohmann::json s = nlohmann::json::parse(std::ifstream(tmp / "stats.json"))["shadow_maps"];
  EXPECT_LE(s["bytes"].get<uint64_t>(), uint64_t(1) << 20);
  ASSERT_EQ(s["notes"].size(), 1u);
  size_t lost = 0;
  for (const auto& l : s["lights"]) lost += l["size"] < l["requested_size"];
  EXPECT_GT(lost, 0u);
}

TEST(ShadowMapsCli, BadOptionsFailWithOneLine) {
  if (!std::filesystem::exists(TILESHADE_BINARY)) GTEST_SKIP() << "tileshade binary not built";
  const auto tmp = std::filesystem::temp_directory_path() / "tileshade_cli_shadow_bad";
  for (const char* args :
       {"--shadows 20 --shadow-budget 0.001", "--shadow-map-size 100", "--shadow-map-size 8",
        "--shadow-map-size 16384", "--shadow-budget 0", "--shadow-budget -3",
        "--shadow-budget 5000", "--shadow-budget nan", "--shadow-filter pcf4", "--shadow-bias 1",
        "--shadow-bias 1,x", "--shadow-bias 1,-2", "--shadow-bias 1,2,3", "--shadow-bias inf,1",
        "--shadow-bias receiver", "--shadow-bias receiver,1,2", "--shadow-bias receiver,-1",
        "--shadow-bias 1,receiver"}) {
    CliRun r = runTileshade(kFrame + args + " --out " + tmp.string());
    EXPECT_NE(r.status, 0) << args;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << args << ": " << r.output;
    EXPECT_NE(r.output.find("error"), std::string::npos) << args << ": " << r.output;
    EXPECT_NE(r.output.find("--shadow-"), std::string::npos) << args << ": " << r.output;
  }
}

// The forward techniques shade shadows too (kernels/shadows.h as GLSL): `all` with --raster gl
// renders every technique of a shadowed frame, and --check holds each forward image within 1e-4
// of the reference that samples the same maps, 0 missed, with the maps' upload as its own row.
TEST(ShadowMapsCli, ForwardTechniquesShadeShadowCastingLights) {
  if (!std::filesystem::exists(TILESHADE_BINARY)) GTEST_SKIP() << "tileshade binary not built";
  REQUIRE_GL();
  const auto tmp = std::filesystem::temp_directory_path() / "tileshade_cli_shadow_forward";
  std::filesystem::remove_all(tmp);
  const CliRun r = runTileshade(kFrame + "--raster gl --technique all --shadows 2 --check --out " +
                                tmp.string());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(r.output.find("leaves out"), std::string::npos) << r.output;
  const nlohmann::json stats = nlohmann::json::parse(std::ifstream(tmp / "stats.json"));
  size_t forward = 0;
  for (const auto& t : stats["techniques"]) {
    const std::string name = t["technique"];
    EXPECT_TRUE(std::filesystem::exists(tmp / name / "image.exr")) << name;
    EXPECT_LE(t["error"]["max_rel_peak"].get<double>(), 1e-4) << name;
    EXPECT_EQ(t["missed_contributions"], 0) << name;
    bool upload = false;
    for (const auto& k : t["kernels"]) upload = upload || k["name"] == "shadow_upload";
    const bool drawsScene = name.rfind("forward") != std::string::npos;
    EXPECT_EQ(upload, drawsScene) << name;
    forward += drawsScene;
  }
  // tiled-forward, tiled-forward-prez, clustered-forward, forward, forward-single
  EXPECT_EQ(forward, 5u);
}

// A G-buffer dumped with shadow-casting lights, imported: shaded with the maps it carries (the
// same image as the render it was dumped from, also with the receiver-plane bias, whose flag
// the dump's shadow_atlas.json carries), and stats.json counts its casters.
TEST(ShadowMapsCli, AnImportedShadowedDumpKeepsItsShadows) {
  if (!std::filesystem::exists(TILESHADE_BINARY)) GTEST_SKIP() << "tileshade binary not built";
  const auto tmp = std::filesystem::temp_directory_path() / "tileshade_cli_shadow_import";
  for (const std::string bias : {"1.5,1.5", "receiver,0.5"}) {
    std::filesystem::remove_all(tmp);
    CliRun r = runTileshade(kFrame + "--shadows 2 --shadow-filter pcf3 --shadow-bias " + bias +
                            " --technique tiled --dump --out " + (tmp / "dump").string());
    ASSERT_EQ(r.status, 0) << r.output;
    r = runTileshade("render --device cpu --technique tiled --gbuffer-in " +
                         (tmp / "dump").string() + " --out " + (tmp / "again").string(),
                     test::Streams::StderrOnly);
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_EQ(r.output.find("without shadows"), std::string::npos) << r.output;
    const nlohmann::json atlas =
        nlohmann::json::parse(std::ifstream(tmp / "dump" / "shadow_atlas.json"));
    EXPECT_EQ(atlas.contains("receiver_plane"), bias != "1.5,1.5") << bias;
    const nlohmann::json stats = nlohmann::json::parse(std::ifstream(tmp / "again" / "stats.json"));
    EXPECT_EQ(stats["shadow_casting_lights"], 2);
    const FloatImage a = readImage((tmp / "dump" / "image.exr").string());
    const FloatImage b = readImage((tmp / "again" / "image.exr").string());
    EXPECT_TRUE(a.data == b.data) << bias;
  }
}

// bench draws the maps of a scene's own shadow-casting lights (extras castsShadow) every frame:
// the shadows column says "default" (the scene's marks) and the atlas's bytes are in the row.
TEST(ShadowMapsCli, BenchDrawsTheScenesOwnShadowCasters) {
  if (!std::filesystem::exists(TILESHADE_BINARY)) GTEST_SKIP() << "tileshade binary not built";
  const auto tmp = std::filesystem::temp_directory_path() / "tileshade_cli_shadow_bench";
  std::filesystem::remove_all(tmp);
  std::filesystem::create_directories(tmp);
  const std::string scene = (tmp / "casting.gltf").string();
  CliRun r = runTileshade("scene export builtin:atrium " + scene + " --shadows 2");
  ASSERT_EQ(r.status, 0) << r.output;
  r = runTileshade("bench --scene " + scene +
                   " --technique tiled --resolution 64x36 --frames 1 --warmup 0 --repeat 1 "
                   "--no-calibrate --shadow-map-size 32 --device cpu --out " +
                   (tmp / "out").string());
  ASSERT_EQ(r.status, 0) << r.output;
  const nlohmann::json doc = nlohmann::json::parse(std::ifstream(tmp / "out" / "bench.json"));
  ASSERT_EQ(doc["rows"].size(), 1u) << doc.dump();
  const nlohmann::json& row = doc["rows"][0];
  // Two point lights' six 32x32 float faces, at least.
  EXPECT_GE(row["shadow_bytes"].get<uint64_t>(), 2u * 6u * 32u * 32u * 4u) << row.dump();
  EXPECT_GT(row["shadow_ms"].get<double>(), 0.0) << row.dump();
  EXPECT_NE(row["features_used"].get<std::string>().find("shadows"), std::string::npos);
}

// --shadow-storage per-light: deferred draws each light's maps just before its pass into one
// reused atlas; its image is the atlas path's bit for bit (--check passes), its stats.json says
// what it drew and kept resident; a technique that needs every map resident refuses, and `all`
// leaves those out with a line.
TEST(ShadowMapsCli, PerLightStorageGivesTheAtlasImageWithLessResident) {
  if (!std::filesystem::exists(TILESHADE_BINARY)) GTEST_SKIP() << "tileshade binary not built";
  const auto tmp = std::filesystem::temp_directory_path() / "tileshade_cli_shadow_per_light";
  std::filesystem::remove_all(tmp);
  const std::string frame = kFrame + "--shadows 3 --shadow-map-size 64 --shadow-filter pcf3 ";
  CliRun r = runTileshade(frame + "--technique deferred deferred-stencil --check --out " +
                          (tmp / "atlas").string());
  ASSERT_EQ(r.status, 0) << r.output;
  r = runTileshade(frame +
                   "--technique deferred deferred-stencil --check --shadow-storage per-light "
                   "--out " +
                   (tmp / "own").string());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("shadow maps per light: "), std::string::npos) << r.output;
  const nlohmann::json atlas = nlohmann::json::parse(std::ifstream(tmp / "atlas" / "stats.json"));
  const nlohmann::json own = nlohmann::json::parse(std::ifstream(tmp / "own" / "stats.json"));
  EXPECT_EQ(atlas["shadow_storage"], "atlas");
  EXPECT_EQ(own["shadow_storage"], "per-light");
  const uint64_t atlasBytes = own["shadow_maps"]["bytes"];
  for (size_t t = 0; t < 2; ++t) {
    const std::string name = own["techniques"][t]["technique"];
    EXPECT_TRUE(atlas["techniques"][t]["shadow_use"].is_null()) << name;
    const nlohmann::json& use = own["techniques"][t]["shadow_use"];
    ASSERT_TRUE(use.is_object()) << own.dump();
    // Three point lights of 6 faces at 64^2 (each drawn only if its rectangle is on screen).
    EXPECT_EQ(use["resident_bytes"].get<uint64_t>(), 6u * 64u * 64u * 4u) << name;
    EXPECT_LT(use["resident_bytes"].get<uint64_t>(), atlasBytes) << name;
    EXPECT_EQ(use["written_bytes"].get<uint64_t>(),
              use["passes"].get<uint64_t>() * use["resident_bytes"].get<uint64_t>())
        << name;
    EXPECT_GE(use["passes"].get<int>(), 1) << name;
    EXPECT_LE(own["techniques"][t]["error"]["max_rel_peak"].get<double>(), 1e-4) << name;
    const FloatImage a = readImage((tmp / "atlas" / name / "image.exr").string());
    const FloatImage b = readImage((tmp / "own" / name / "image.exr").string());
    EXPECT_EQ(a.data, b.data) << name;
  }
  // Tiled needs every map resident: one line, before any file.
  r = runTileshade(frame + "--technique tiled --shadow-storage per-light --out " +
                   (tmp / "tiled").string());
  EXPECT_NE(r.status, 0) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  EXPECT_NE(r.output.find("tiled: --shadow-storage per-light is for deferred and "
                          "deferred-stencil"),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(std::filesystem::exists(tmp / "tiled"));
  r = runTileshade(frame + "--technique all --shadow-storage per-light --out " +
                   (tmp / "all").string());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("--technique all leaves out clustered (--shadow-storage per-light"),
            std::string::npos)
      << r.output;
  EXPECT_TRUE(std::filesystem::exists(tmp / "all" / "deferred-stencil" / "image.exr"));
  EXPECT_FALSE(std::filesystem::exists(tmp / "all" / "tiled"));
  r = runTileshade(frame + "--shadow-storage per-tile --out " + (tmp / "bad").string());
  EXPECT_NE(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("--shadow-storage: expected one of atlas, per-light"), std::string::npos)
      << r.output;
  // An imported G-buffer has no geometry to draw maps from: the option does not apply.
  r = runTileshade("render --device cpu --gbuffer-in " + (tmp / "none").string() +
                   " --shadow-storage per-light --technique deferred --out " +
                   (tmp / "imported").string());
  EXPECT_NE(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("--shadow-storage"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(tmp / "imported"));
}

}  // namespace
}  // namespace ts
