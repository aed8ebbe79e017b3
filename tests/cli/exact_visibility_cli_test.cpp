// `render --exact-visibility`: stats.json's exact_visibility against the visibility_exact.exr it
// describes, a directional light that reaches every surface pixel, and the refusals.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "gbuffer/image_io.h"
#include "test_support.h"

namespace ts {
namespace {

using test::CliRun;
using test::runTileshade;

const std::string kFrame = "render --scene builtin:atrium --width 64 --height 36 --device cpu ";

TEST(ExactVisibilityCli, StatsMatchTheImage) {
  if (!std::filesystem::exists(TILESHADE_BINARY)) GTEST_SKIP() << "tileshade binary not built";
  const auto tmp = std::filesystem::temp_directory_path() / "tileshade_cli_exact_visibility";
  std::filesystem::remove_all(tmp);
  // The sun variant's directional light is the first --shadows picks.
  CliRun r = runTileshade(kFrame + "--variant sun --lights big --shadows 3 --exact-visibility " +
                          "--dump --out " + tmp.string());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("exact visibility: 3 shadow-casting light(s)"), std::string::npos)
      << r.output;
  const nlohmann::json stats = nlohmann::json::parse(std::ifstream(tmp / "stats.json"));
  const nlohmann::json& e = stats["exact_visibility"];
  ASSERT_TRUE(e.is_object()) << stats.dump();
  for (const char* key :
       {"library", "triangles", "build_ms", "query_ms", "applicable", "occluded", "lights"})
    EXPECT_TRUE(e.contains(key)) << key;
  EXPECT_EQ(e["triangles"], stats["triangles"]);
  ASSERT_EQ(e["lights"].size(), 3u);
  // A sun reaches every surface pixel: each is a pair, occluded or not.
  size_t suns = 0;
  for (const nlohmann::json& l : e["lights"])
    if (l["type"] == "directional") {
      EXPECT_EQ(l["applicable"], stats["geometry_pixels"]);
      ++suns;
    }
  EXPECT_EQ(suns, 1u);

  const FloatImage image = readImage((tmp / "visibility_exact.exr").string());
  ASSERT_EQ(image.channels.size(), 3u);
  ASSERT_EQ(image.width, 64);
  uint64_t applicableAll = 0, occludedAll = 0;
  for (const nlohmann::json& l : e["lights"]) {
    // OpenEXR keeps its channels sorted by name: found by name.
    const std::string name = "light" + std::to_string(l["light"].get<int>());
    const size_t c = size_t(std::find(image.channels.begin(), image.channels.end(), name) -
                            image.channels.begin());
    ASSERT_LT(c, image.channels.size()) << name;
    uint64_t applicable = 0, occluded = 0, other = 0;
    for (size_t i = 0; i < size_t(image.width) * size_t(image.height); ++i) {
      const float v = image.data[i * 3 + c];
      applicable += v == 0.0f || v == 1.0f;
      occluded += v == 0.0f;
      other += v != 0.0f && v != 1.0f && v != 2.0f;
    }
    EXPECT_EQ(other, 0u);
    EXPECT_EQ(l["applicable"].get<uint64_t>(), applicable) << l.dump();
    EXPECT_EQ(l["occluded"].get<uint64_t>(), occluded) << l.dump();
    applicableAll += applicable;
    occludedAll += occluded;
  }
  EXPECT_EQ(e["applicable"].get<uint64_t>(), applicableAll);
  EXPECT_EQ(e["occluded"].get<uint64_t>(), occludedAll);
  EXPECT_GT(occludedAll, 0u);  // the atrium's columns and galleries shadow something
  EXPECT_LT(occludedAll, applicableAll);

  // An imported G-buffer has no triangles to cast rays against.
  r = runTileshade("render --device cpu --exact-visibility --gbuffer-in " +
                   (tmp / "gbuffer.json").string() + " --out " + (tmp / "imported").string());
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("--exact-visibility needs the scene's triangles"), std::string::npos)
      << r.output;
  EXPECT_FALSE(std::filesystem::exists(tmp / "imported" / "stats.json"));
}

TEST(ExactVisibilityCli, NeedsAShadowCastingLight) {
  if (!std::filesystem::exists(TILESHADE_BINARY)) GTEST_SKIP() << "tileshade binary not built";
  const auto tmp = std::filesystem::temp_directory_path() / "tileshade_cli_exact_visibility_none";
  std::filesystem::remove_all(tmp);
  CliRun r = runTileshade(kFrame + "--exact-visibility --out " + tmp.string());
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("--exact-visibility: no light casts a shadow"), std::string::npos)
      << r.output;
  EXPECT_FALSE(std::filesystem::exists(tmp / "stats.json"));
  // Without the flag the key is there, null.
  r = runTileshade(kFrame + "--shadows 2 --out " + tmp.string());
  ASSERT_EQ(r.status, 0) << r.output;
  const nlohmann::json stats = nlohmann::json::parse(std::ifstream(tmp / "stats.json"));
  ASSERT_TRUE(stats.contains("exact_visibility"));
  EXPECT_TRUE(stats["exact_visibility"].is_null());
  EXPECT_FALSE(std::filesystem::exists(tmp / "visibility_exact.exr"));
}

// Every light casting on a big frame would need gigabytes of per-pair planes: one line, before
// any ray or file.
TEST(ExactVisibilityCli, RefusesPairPlanesBeyondItsMemoryLimit) {
  if (!std::filesystem::exists(TILESHADE_BINARY)) GTEST_SKIP() << "tileshade binary not built";
  const auto tmp = std::filesystem::temp_directory_path() / "tileshade_cli_exact_visibility_big";
  std::filesystem::remove_all(tmp);
  const CliRun r = runTileshade(
      "render --device cpu --width 1280 --height 720 --shadows all --shadow-map-size 16 "
      "--technique tiled --exact-visibility --out " +
      tmp.string());
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("--exact-visibility: 924 shadow-casting light(s) x 921600 pixels need "),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(std::filesystem::exists(tmp / "stats.json"));
}

// The maps against exact visibility (wrong pairs, image error) on the atrium: one run per bias.
nlohmann::json shadowErrorRun(const std::string& bias, const std::string& name) {
  const auto tmp = std::filesystem::temp_directory_path() / ("tileshade_cli_shadow_error_" + name);
  std::filesystem::remove_all(tmp);
  const CliRun r = runTileshade(
      "render --scene builtin:atrium --width 160 --height 90 --device cpu --lights big "
      "--shadows 2 --shadow-map-size 1024 --shadow-filter none --technique tiled "
      "--exact-visibility --shadow-bias " +
      bias + " --out " + tmp.string());
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("shadow maps vs exact: "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("vs exact visibility (the perfect shadow): max err/peak "),
            std::string::npos)
      << r.output;
  nlohmann::json stats = nlohmann::json::parse(std::ifstream(tmp / "stats.json"));
  nlohmann::json e = stats["exact_visibility"];
  e["technique"] = stats["techniques"][0];
  // shadow_error.exr is the map-vs-exact image difference the image error summarises.
  const FloatImage error = readImage((tmp / "shadow_error.exr").string());
  EXPECT_EQ(error.channels, (std::vector<std::string>{"error", "wrong"}));
  float largest = 0.0f;
  uint64_t wrong = 0, agreeingButDifferent = 0;
  for (size_t i = 0; i < size_t(error.width) * size_t(error.height); ++i) {
    largest = std::max(largest, error.data[2 * i]);
    wrong += uint64_t(error.data[2 * i + 1]);
    // Filter none: factors are 0 or 1, so a pixel whose pairs all agree is shaded identically.
    agreeingButDifferent += error.data[2 * i + 1] == 0.0f && error.data[2 * i] != 0.0f;
  }
  EXPECT_EQ(agreeingButDifferent, 0u);
  EXPECT_EQ(wrong, e["wrong_pairs"]["false_shadow"].get<uint64_t>() +
                       e["wrong_pairs"]["light_leak"].get<uint64_t>());
  EXPECT_NEAR(double(largest), e["image_error"]["max_abs"].get<double>(),
              1e-6 * e["image_error"]["max_abs"].get<double>() + 1e-30);
  return e;
}

TEST(ExactVisibilityCli, MapsAgainstExact) {
  if (!std::filesystem::exists(TILESHADE_BINARY)) GTEST_SKIP() << "tileshade binary not built";
  const nlohmann::json usual = shadowErrorRun("1.5,1.5", "usual");
  const nlohmann::json& w = usual["wrong_pairs"];
  for (const char* key :
       {"pairs", "false_shadow", "light_leak", "fraction", "mean_abs_factor_error", "per_type"})
    EXPECT_TRUE(w.contains(key)) << key;
  for (const char* key : {"max_rel_peak", "rmse", "p99_rel_peak"})
    EXPECT_TRUE(usual["image_error"].contains(key)) << key;
  EXPECT_TRUE(usual["technique"].contains("error_vs_exact"));
  // The per-light counts add up to the totals, and a pair is an applicable one.
  uint64_t pairs = 0, falseShadow = 0, leak = 0;
  for (const nlohmann::json& l : usual["lights"]) {
    EXPECT_LE(l["wrong_pairs"]["pairs"].get<uint64_t>(), l["applicable"].get<uint64_t>());
    pairs += l["wrong_pairs"]["pairs"].get<uint64_t>();
    falseShadow += l["wrong_pairs"]["false_shadow"].get<uint64_t>();
    leak += l["wrong_pairs"]["light_leak"].get<uint64_t>();
  }
  EXPECT_EQ(w["pairs"].get<uint64_t>(), pairs);
  EXPECT_EQ(w["false_shadow"].get<uint64_t>(), falseShadow);
  EXPECT_EQ(w["light_leak"].get<uint64_t>(), leak);
  EXPECT_GT(pairs, 0u);
  // A big map with the usual bias: few wrong pairs.
  EXPECT_LT(w["fraction"].get<double>(), 0.02) << w.dump();
  // An absurd constant bias lifts every shadow off its occluder: light leaks (peter-panning).
  const nlohmann::json far = shadowErrorRun("200,0", "far");
  EXPECT_GT(far["wrong_pairs"]["light_leak"].get<uint64_t>(), 10 * leak + 100) << far.dump();
  EXPECT_GT(far["image_error"]["rmse"].get<double>(), usual["image_error"]["rmse"].get<double>());
  // No bias: lit surfaces shadow themselves (acne).
  const nlohmann::json none = shadowErrorRun("0,0", "none");
  EXPECT_GT(none["wrong_pairs"]["false_shadow"].get<uint64_t>(), 10 * falseShadow + 100)
      << none.dump();
}

}  // namespace
}  // namespace ts
