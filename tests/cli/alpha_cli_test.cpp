// glTF alphaMode BLEND on the command line (issue #17): no technique renders transparency yet, so
// render and bench refuse a scene that draws a BLEND material, in one line naming it, and
// `--blend as-opaque|as-mask` opts in (recorded in stats.json, a bench dimension); scene export
// keeps it.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "gltf_builder.h"
#include "test_support.h"

namespace ts {
namespace {

using test::CliRun;
using test::runTileshade;

// The builder's triangle drawn with a BLEND material called "glass", written to `dir`.
std::string glassFile(const std::filesystem::path& dir) {
  nlohmann::json doc = test::triangle();
  doc["meshes"][0]["primitives"][0]["material"] = 0;
  doc["materials"] = nlohmann::json::parse(
      R"([{"name": "glass", "alphaMode": "BLEND",
           "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.9, 1, 0.3]}}])");
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "glass.gltf").string();
  std::ofstream(path) << doc.dump();
  return path;
}

int lines(const std::string& s) { return int(std::count(s.begin(), s.end(), '\n')); }

TEST(AlphaCli, BlendIsRefusedInOneLineUnlessOptedIn) {
  if (!std::filesystem::exists(TILESHADE_BINARY)) GTEST_SKIP() << "tileshade binary not built";
  const auto tmp = std::filesystem::temp_directory_path() / "tileshade_alpha_cli";
  std::filesystem::remove_all(tmp);
  const std::string scene = glassFile(tmp);
  const std::string common = "render --scene " + scene +
                             " --width 32 --height 18 --device cpu --out " + (tmp / "out").string();
  CliRun refused = runTileshade(common);
  EXPECT_NE(refused.status, 0);
  EXPECT_EQ(lines(refused.output), 1) << refused.output;
  EXPECT_NE(refused.output.find("tileshade: error: "), std::string::npos) << refused.output;
  EXPECT_NE(refused.output.find("material 'glass' is alphaMode BLEND: --blend blend composites "
                                "it"),
            std::string::npos)
      << refused.output;
  EXPECT_NE(refused.output.find("--blend as-opaque"), std::string::npos) << refused.output;
  EXPECT_FALSE(std::filesystem::exists(tmp / "out" / "image.exr"));

  CliRun bad = runTileshade(common + " --blend sometimes");
  EXPECT_NE(bad.status, 0);
  EXPECT_EQ(lines(bad.output), 1) << bad.output;
  EXPECT_NE(bad.output.find("--blend"), std::string::npos) << bad.output;

  for (const char* policy : {"as-opaque", "as-mask"}) {
    SCOPED_TRACE(policy);
    std::filesystem::remove_all(tmp / "out");
    CliRun r = runTileshade(common + " --check --blend " + policy);
    ASSERT_EQ(r.status, 0) << r.output;
    const nlohmann::json stats = nlohmann::json::parse(std::ifstream(tmp / "out" / "stats.json"));
    EXPECT_EQ(stats["blend"], policy);
  }
  // The built-in scenes have no BLEND material: the default renders them as before.
  std::filesystem::remove_all(tmp / "out");
  CliRun street = runTileshade(
      "render --scene builtin:street --lights few --width 32 --height 18 "
      "--device cpu --out " +
      (tmp / "out").string());
  ASSERT_EQ(street.status, 0) << street.output;
  EXPECT_EQ(nlohmann::json::parse(std::ifstream(tmp / "out" / "stats.json"))["blend"], "refuse");
}

TEST(AlphaCli, BenchRefusesBlendAndExportKeepsIt) {
  if (!std::filesystem::exists(TILESHADE_BINARY)) GTEST_SKIP() << "tileshade binary not built";
  const auto tmp = std::filesystem::temp_directory_path() / "tileshade_alpha_bench";
  std::filesystem::remove_all(tmp);
  const std::string scene = glassFile(tmp);
  CliRun bench = runTileshade("bench --scene " + scene +
                              " --resolution 32x18 --frames 1 --warmup 0 --repeat 1 --device cpu "
                              "--out " +
                              (tmp / "bench").string());
  EXPECT_NE(bench.status, 0) << bench.output;
  EXPECT_NE(bench.output.find("material 'glass' is alphaMode BLEND"), std::string::npos)
      << bench.output;
  // The opt-in is a sweep dimension: its column says which policy a row ran with.
  CliRun opted = runTileshade("bench --scene " + scene +
                              " --resolution 32x18 --frames 1 --warmup 0 --repeat 1 --device cpu "
                              "--blend as-opaque,as-mask --out " +
                              (tmp / "opted").string());
  ASSERT_EQ(opted.status, 0) << opted.output;
  std::ifstream csv(tmp / "opted" / "bench.csv");
  std::string header, row;
  std::getline(csv, header);
  EXPECT_NE(header.find(",blend,"), std::string::npos) << header;
  size_t rows = 0, opaque = 0;
  while (std::getline(csv, row)) {
    ++rows;
    opaque += row.find(",as-opaque,") != std::string::npos ? 1 : 0;
  }
  EXPECT_EQ(rows, 2u);
  EXPECT_EQ(opaque, 1u);

  const std::string exported = (tmp / "exported.gltf").string();
  CliRun out = runTileshade("scene export " + scene + " " + exported);
  ASSERT_EQ(out.status, 0) << out.output;
  const nlohmann::json doc = nlohmann::json::parse(std::ifstream(exported));
  EXPECT_EQ(doc["materials"][0]["alphaMode"], "BLEND");
  EXPECT_FLOAT_EQ(doc["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"][3].get<float>(),
                  0.3f);
}

}  // namespace
}  // namespace ts
