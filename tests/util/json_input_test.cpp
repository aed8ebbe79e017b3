// Every JSON input strict, bounded and clear (issue #16 items 6, 9 and 13): duplicate keys, NUL in
// strings, nesting beyond 64 levels and directories where files go are one short error line in
// every file tileshade reads (gbuffer.json, lights.json, bench configs, bench.json/bench.csv on
// resume, glTF and GLB, kernel sources), and no error line echoes more than a short prefix of
// what the user gave. The readers in-process: json_input_readers_test.cpp; the strict parser and
// the readers' helpers on their own: strict_json_test.cpp.

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "bench/bench_cli.h"
#include "bench/bench_config.h"
#include "bench/bench_run.h"
#include "gltf_builder.h"
#include "json_errors.h"
#include "gbuffer/gbuffer_files.h"
#include "scene/scene_loader.h"
#include "test_support.h"
#include "util/error.h"
#include "util/file_read.h"
#include "util/short_text.h"
#include "util/strict_json.h"

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

using ts::test::CliRun;
using ts::test::errorOf;
using ts::test::expectMessage;
using ts::test::kShortLine;
using ts::test::nested;
using ts::test::readText;
using ts::test::runTileshade;
using ts::test::Streams;
using ts::test::triangleWith;
using ts::test::writeText;

fs::path freshDir(const std::string& name) { return ts::test::freshDir("json_input", name); }

// Exit status 1 and one short stderr line "tileshade: error: ..." with every needle.
void expectOneShortErrorLine(const std::string& args, const std::vector<std::string>& needles) {
  CliRun r = runTileshade(args, Streams::StderrOnly);
  EXPECT_EQ(r.exitCode(), 1) << args << "\n" << r.output.substr(0, 2000);
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << args << "\n"
                                                                   << r.output.substr(0, 2000);
  EXPECT_EQ(r.output.rfind("tileshade: error: ", 0), 0u) << args << "\n"
                                                         << r.output.substr(0, 2000);
  EXPECT_LT(r.output.size(), kShortLine) << args << "\n" << r.output.substr(0, 2000);
  for (const auto& n : needles)
    EXPECT_NE(r.output.find(n), std::string::npos) << args << "\n" << r.output.substr(0, 2000);
}

bool binaryBuilt() { return fs::exists(TILESHADE_BINARY); }

// One small `render --dump` per test process, copied by each test that breaks it.
const fs::path& dumpFolder() {
  static const fs::path dir = [] {
    fs::path d = freshDir("dump");
    CliRun r =
        runTileshade("render --width 64 --height 36 --device cpu --dump --out " + d.string());
    EXPECT_EQ(r.status, 0) << r.output;
    return d;
  }();
  return dir;
}

fs::path copyOfDump(const std::string& name) {
  fs::path d = freshDir(name);
  fs::remove_all(d);
  fs::copy(dumpFolder(), d, fs::copy_options::recursive);
  return d;
}

std::string renderImport(const fs::path& dir) {
  return "render --gbuffer-in " + dir.string() + " --device cpu --out " +
         (dir.parent_path() / (dir.filename().string() + "_out")).string();
}

// ---- duplicate keys and NUL in each file kind ------------------------------------------------

TEST(JsonInput, DuplicateKeysInTheDescriptorAreAnError) {
  const std::string text = R"({"tileshade_gbuffer": 1, "image": "a.exr", "image": "b.exr"})";
  expectMessage(errorOf([&] { ts::parseGBufferDescriptor(text, "d/gbuffer.json"); }),
                {"d/gbuffer.json", "\"image\" appears twice"});
  if (!binaryBuilt()) GTEST_SKIP() << "tileshade binary not built";
  const fs::path d = copyOfDump("dup_descriptor");
  json j = json::parse(readText(d / "gbuffer.json"));
  std::string s = j.dump();
  s.insert(s.size() - 1, ",\"camera\": " + j.at("camera").dump());
  writeText(d / "gbuffer.json", s);
  expectOneShortErrorLine(renderImport(d), {"gbuffer.json", "\"camera\" appears twice"});
}

TEST(JsonInput, DuplicateKeysInABenchConfigAreAnError) {
  ts::BenchOptions o;
  auto apply = [&](const std::string& text) {
    return errorOf(
        [&] { ts::applyBenchConfig(text, "c.json", o, [](const std::string&) { return false; }); });
  };
  expectMessage(apply(R"({"technique": "tiled", "frames": "0", "technique": "brute"})"),
                {"bench config c.json", "\"technique\" appears twice"});
  if (!binaryBuilt()) GTEST_SKIP() << "tileshade binary not built";
  const fs::path dir = freshDir("dup_config");
  writeText(dir / "c.json", R"({"technique": "tiled", /* comments are fine */ "technique": "x"})");
  expectOneShortErrorLine("bench --list --config " + (dir / "c.json").string(),
                          {"c.json", "\"technique\" appears twice"});
}

// ---- deep nesting and long echoes on the command line
// ---------------------------------------------

TEST(JsonInput, DeepNestingInEveryJsonKindIsOneShortLine) {
  if (!binaryBuilt()) GTEST_SKIP() << "tileshade binary not built";
  const std::string deep = nested(100000);
  {
    const fs::path d = copyOfDump("deep_descriptor");
    writeText(d / "gbuffer.json", "{\"scene\": " + deep + "}");
    expectOneShortErrorLine(renderImport(d), {"gbuffer.json", "nested deeper than 64"});
  }
  {
    const fs::path d = copyOfDump("deep_lights");
    writeText(d / "lights.json", "{\"lights\": " + deep + "}");
    expectOneShortErrorLine(renderImport(d), {"lights.json", "nested deeper than 64"});
  }
  {
    const fs::path dir = freshDir("deep_config");
    writeText(dir / "c.json", "{\"technique\": " + deep + "}");
    expectOneShortErrorLine("bench --list --config " + (dir / "c.json").string(),
                            {"c.json", "nested deeper than 64"});
  }
  {
    const fs::path dir = freshDir("deep_gltf");
    writeText(dir / "deep.gltf", triangleWith("\"extras\": " + deep));
    expectOneShortErrorLine("render --scene " + (dir / "deep.gltf").string() +
                                " --width 64 --height 36 --device cpu --out " +
                                (dir / "out").string(),
                            {"deep.gltf", "nested deeper than 64"});
  }
  // At 30,000 levels the old message echoed the whole value.
  const std::string value = nested(30000);
  const fs::path d = copyOfDump("deep_value");
  writeText(d / "lights.json", "{\"dmin\": " + value + "}");
  expectOneShortErrorLine(renderImport(d), {"lights.json"});
}

TEST(JsonInput, AMegabyteUnknownKeyOrValueIsEchoedShort) {
  if (!binaryBuilt()) GTEST_SKIP() << "tileshade binary not built";
  const std::string huge(1 << 20, 'q');
  const fs::path d = copyOfDump("huge_key");
  json j = json::parse(readText(d / "gbuffer.json"));
  j[huge] = 1;
  writeText(d / "gbuffer.json", j.dump());
  expectOneShortErrorLine(renderImport(d), {"is not a known field", "(1048576 bytes)"});

  const fs::path dir = freshDir("huge_config");
  writeText(dir / "key.json", json{{huge, 1}}.dump());
  expectOneShortErrorLine("bench --list --config " + (dir / "key.json").string(),
                          {"unknown field", "(1048576 bytes)"});
  writeText(dir / "value.json", json{{"technique", huge}}.dump());
  expectOneShortErrorLine("bench --list --config " + (dir / "value.json").string(),
                          {"(1048576 bytes)"});
  // An option value (a command line argument is at most 128 KiB).
  expectOneShortErrorLine("render --technique " + std::string(100000, 't') +
                              " --width 64 --height 36 --device cpu --out " + (dir / "o").string(),
                          {"(100000 bytes)"});
  // A channel name the image lacks.
  const fs::path c = copyOfDump("huge_channel");
  j = json::parse(readText(c / "gbuffer.json"));
  j["depth"]["channel"] = huge;
  writeText(c / "gbuffer.json", j.dump());
  expectOneShortErrorLine(renderImport(c), {"no channel", "(1048576 bytes)"});
}

// ---- directories where files go
// --------------------------------------------------------------------

TEST(JsonInput, ADirectoryWhereAFileGoesIsOneLineNamingIt) {
  if (!binaryBuilt()) GTEST_SKIP() << "tileshade binary not built";
  const std::string isDir = ": it is a directory";
  const fs::path dir = freshDir("dirs");
  const std::string out = " --width 64 --height 36 --device cpu --out " + (dir / "out").string();
  // glTF and GLB scenes
  for (const char* name : {"scene.gltf", "scene.glb"}) {
    fs::create_directories(dir / name);
    expectOneShortErrorLine("render --scene " + (dir / name).string() + out,
                            {"glTF file " + (dir / name).string() + isDir});
  }
  // gbuffer.json inside the --gbuffer-in folder, lights.json, the EXR image
  for (const char* file : {"gbuffer.json", "lights.json", "gbuffer.exr"}) {
    const fs::path d = copyOfDump(std::string("dir_") + file);
    fs::remove(d / file);
    fs::create_directories(d / file);
    expectOneShortErrorLine(renderImport(d), {(d / file).string() + isDir});
  }
  // a --gbuffer-in folder without a descriptor
  fs::create_directories(dir / "no_descriptor");
  expectOneShortErrorLine(renderImport(dir / "no_descriptor"),
                          {(dir / "no_descriptor" / "gbuffer.json").string() + " does not exist"});
  // a bench config; bench.csv and bench.json on resume
  fs::create_directories(dir / "config.json");
  expectOneShortErrorLine("bench --list --config " + (dir / "config.json").string(),
                          {"bench config " + (dir / "config.json").string() + isDir});
  const std::string bench =
      "bench --technique brute --resolution 64x36 --frames 1 --no-calibrate "
      "--quiet --device cpu --resume --out ";
  for (const char* file : {"bench.csv", "bench.json"}) {
    const fs::path b = dir / (std::string("resume_") + file);
    fs::create_directories(b / file);
    if (std::string(file) == "bench.json") writeText(b / "bench.csv", "");
    expectOneShortErrorLine(bench + b.string(), {(b / file).string() + isDir});
  }
  // a kernel source
  const fs::path kernels = dir / "kernels";
  for (const auto& e : fs::directory_iterator(ts::test::sourceDir() + "/kernels"))
    fs::create_directories(kernels / e.path().filename());
  ::setenv("TILESHADE_KERNEL_DIR", kernels.c_str(), 1);
  expectOneShortErrorLine("render" + out, {"kernel source " + kernels.string(), isDir});
  ::unsetenv("TILESHADE_KERNEL_DIR");
  // a shader source (where an OpenGL context can be made)
  const CliRun gl = runTileshade("render --raster gl" + out);
  if (gl.status != 0) GTEST_SKIP() << "no OpenGL here: " << gl.output;
  const fs::path shaders = dir / "shaders";
  for (const auto& e : fs::directory_iterator(ts::test::sourceDir() + "/shaders"))
    fs::create_directories(shaders / e.path().filename());
  ::setenv("TILESHADE_SHADER_DIR", shaders.c_str(), 1);
  expectOneShortErrorLine("render --raster gl" + out, {"shader source " + shaders.string(), isDir});
  ::unsetenv("TILESHADE_SHADER_DIR");
}

TEST(JsonInput, DuplicateKeysOrNestingInBenchJsonOnResumeAreAnError) {
  if (!binaryBuilt()) GTEST_SKIP() << "tileshade binary not built";
  const std::string bench =
      "bench --technique brute --resolution 64x36 --frames 1 --no-calibrate "
      "--quiet --device cpu --resume --out ";
  const fs::path dir = freshDir("resume_json");
  for (const std::string& text : {std::string(R"({"rows": [], "rows": []})"), nested(100000)}) {
    writeText(dir / "bench.csv", "");
    writeText(dir / "bench.json", text);
    expectOneShortErrorLine(bench + dir.string(), {"bench.json"});
  }
}

}  // namespace
