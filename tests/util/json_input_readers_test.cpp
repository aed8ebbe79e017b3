// The JSON readers in-process (issue #16 items 6, 9 and 13): duplicate keys, NUL in strings,
// long names echoed short and directories where files go in gbuffer.json, lights.json, bench
// configs and glTF / GLB, through the readers themselves (no binary, no device). What the binary
// prints for them: json_input_test.cpp; the strict parser on its own: strict_json_test.cpp.
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "bench/bench_cli.h"
#include "bench/bench_config.h"
#include "gbuffer/gbuffer_files.h"
#include "gltf_builder.h"
#include "json_errors.h"
#include "scene/scene_loader.h"
#include "test_support.h"
#include "util/error.h"

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

using ts::test::errorOf;
using ts::test::expectMessage;
using ts::test::kShortLine;
using ts::test::readText;
using ts::test::triangleWith;
using ts::test::writeText;

fs::path freshDir(const std::string& name) { return ts::test::freshDir("json_input", name); }

// A GLB holding `jsonChunk` (and no BIN chunk).
std::string glb(std::string jsonChunk) {
  while (jsonChunk.size() % 4) jsonChunk += ' ';
  auto u32 = [](uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); };
  return "glTF" + u32(2) + u32(uint32_t(12 + 8 + jsonChunk.size())) +
         u32(uint32_t(jsonChunk.size())) + u32(0x4E4F534A) + jsonChunk;
}

std::string loadGltfError(const std::string& bytes, const std::string& name = "hostile.gltf") {
  return errorOf([&] {
    std::vector<std::string> warnings;
    ts::loadGltfFromMemory(reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size(),
                           "/nonexistent", name, &warnings);
  });
}

// The fuzzers' seeds (docs/output-formats.md's forms, real dumps) are valid: the fuzzing starts
// from files that get through every check.
TEST(JsonInput, FuzzSeedsForTheImportFilesAreValid) {
  const fs::path seeds = fs::path(ts::test::sourceDir()) / "tests/fuzz/seeds";
  size_t n = 0;
  // The descriptor fuzzer also feeds its bytes to the shadow atlas reader: its seeds named
  // shadow-atlas* are shadow_atlas.json files.
  size_t atlases = 0;
  for (const auto& e : fs::directory_iterator(seeds / "gbuffer_descriptor")) {
    const std::string text = readText(e.path());
    if (e.path().filename().string().rfind("shadow-atlas", 0) == 0) {
      EXPECT_NO_THROW(ts::parseShadowAtlasFile(text, e.path().string())) << e.path();
      ++atlases;
    } else {
      EXPECT_NO_THROW(ts::parseGBufferDescriptor(text, e.path().string())) << e.path();
    }
    ++n;
  }
  EXPECT_GE(atlases, 1u);
  for (const auto& e : fs::directory_iterator(seeds / "lights")) {
    EXPECT_NO_THROW(ts::parseLightsFile(readText(e.path()), e.path().string())) << e.path();
    ++n;
  }
  EXPECT_GE(n, 6u);
}

// ---- duplicate keys and NUL in each file kind ------------------------------------------------

TEST(JsonInput, DuplicateKeysInLightsJsonAreAnError) {
  // The case of the issue: a second "lights" (empty) silently dropped every light.
  const std::string twice = R"({"ambient": [0, 0, 0], "lights": [{"type": "point",
      "position": [0, 0, -2], "color": [1, 1, 1], "range": 3}], "lights": []})";
  expectMessage(errorOf([&] { ts::parseLightsFile(twice, "x/lights.json"); }),
                {"x/lights.json", "\"lights\" appears twice"});
  const std::string inLight = R"({"lights": [{"type": "point", "position": [0, 0, -2],
      "color": [1, 1, 1], "range": 3, "range": 30}]})";
  expectMessage(errorOf([&] { ts::parseLightsFile(inLight, "lights.json"); }),
                {"\"range\" appears twice"});
}

TEST(JsonInput, DuplicateKeysInGltfAndGlbAreAnError) {
  const std::string text = triangleWith(R"("scene": 0)");  // "scene" is there already
  expectMessage(loadGltfError(text), {"hostile.gltf", "\"scene\" appears twice"});
  expectMessage(loadGltfError(glb(text), "hostile.glb"),
                {"hostile.glb", "\"scene\" appears twice"});
  // A node's translation twice: tinygltf would have kept the last one.
  json doc = ts::test::triangle();
  std::string nodes = doc.dump();
  const std::string t = "\"translation\":[0,0.5,2]";
  ASSERT_NE(nodes.find(t), std::string::npos) << nodes;
  nodes.replace(nodes.find(t), t.size(), t + ",\"translation\":[9,9,9]");
  expectMessage(loadGltfError(nodes), {"\"translation\" appears twice"});
}

TEST(JsonInput, NulInAPathIsAnError) {
  // gbuffer.json's image, a glTF image uri, a bench config's scene.
  expectMessage(errorOf([&] {
                  ts::parseGBufferDescriptor(R"({"image": "gbuffer.exr\u0000.png"})",
                                             "gbuffer.json");
                }),
                {"gbuffer.json", "\\u0000"});
  expectMessage(loadGltfError(triangleWith(R"("images": [{"uri": "a.png\u0000.jpg"}])")),
                {"\\u0000"});
  ts::BenchOptions o;
  expectMessage(errorOf([&] {
                  ts::applyBenchConfig(R"({"scene": "x.gltf\u0000y"})", "c.json", o,
                                       [](const std::string&) { return false; });
                }),
                {"c.json", "\\u0000"});
}

// ---- long echoes

TEST(JsonInput, GltfMessagesEchoLongNamesShort) {
  const std::string huge(1 << 20, 'g');
  auto warningsOf = [](const std::string& text) {
    std::vector<std::string> warnings;
    ts::loadGltfFromMemory(reinterpret_cast<const unsigned char*>(text.data()), text.size(),
                           "/nonexistent", "long.gltf", &warnings);
    return warnings;
  };
  // An unsupported required extension and a material whose factor is clamped (a warning each).
  json doc = ts::test::triangle();
  doc["extensionsRequired"] = {huge};
  doc["extensionsUsed"].push_back(huge);
  doc["materials"] = {
      {{"name", huge}, {"pbrMetallicRoughness", {{"baseColorFactor", {2, 0, 0, 1}}}}}};
  doc["meshes"][0]["primitives"][0]["material"] = 0;
  const std::vector<std::string> warnings = warningsOf(doc.dump());
  ASSERT_GE(warnings.size(), 2u);
  size_t named = 0;
  for (const auto& w : warnings) {
    EXPECT_LT(w.size(), kShortLine) << w.substr(0, 2000);
    named += w.find("(1048576 bytes)") != std::string::npos;
  }
  EXPECT_EQ(named, 1u);  // the extension's
  // A value of the wrong type in the JSON checks.
  doc = ts::test::triangle();
  doc["scene"] = {{huge, 1}};
  expectMessage(loadGltfError(doc.dump()), {"hostile.gltf", "scene: expected", " bytes)"});
}

// ---- directories where files go

TEST(JsonInput, AGltfBufferThatIsADirectoryIsOneLineNamingIt) {
  // tinygltf's own reader sized the directory and reported "out of memory".
  const fs::path dir = freshDir("gltf_buffer_dir");
  fs::create_directories(dir / "buf.bin");
  json doc = ts::test::triangle();
  doc["buffers"][0] = {{"uri", "buf.bin"}, {"byteLength", 44}};
  writeText(dir / "scene.gltf", doc.dump());
  expectMessage(errorOf([&] { ts::loadGltf((dir / "scene.gltf").string()); }),
                {"scene.gltf", (dir / "buf.bin").string() + ": it is a directory"});
}

}  // namespace
