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

}  // namespace
}  // namespace ts
