// Hostile use of the command line and its outputs (issue #12): options that make no sense, every
// failed or truncated write, images with NaN/inf pixels (never reported as exact), bench configs
// with absurd values. The expected outcome is one line "tileshade: error: ..." and exit status 1
// before any file is written, or an honest report. The same subjects in-process, without the
// binary: util/hostile_values_test.cpp, reference/hostile_stats_test.cpp,
// bench/hostile_bench_test.cpp.

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include <gtest/gtest.h>

#include <algorithm>
#include <nlohmann/json.hpp>

#include "bench/bench_cli.h"
#include "bench/bench_config.h"
#include "bench/bench_run.h"
#include "util/progress.h"
#include "gltf_builder.h"
#include "reference/error_metrics.h"
#include "render/stats.h"
#include "test_support.h"
#include "util/error.h"
#include "util/file_write.h"
#include "util/option_values.h"

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

using ts::test::CliRun;
using ts::test::runTileshade;
using ts::test::Streams;

// A fresh folder per test (CTest runs tests in parallel processes).
fs::path freshDir(const std::string& name) { return ts::test::freshDir("hostile", name); }

size_t lines(const std::string& s) { return size_t(std::count(s.begin(), s.end(), '\n')); }

bool binaryBuilt() { return fs::exists(TILESHADE_BINARY); }

// Exit status 1 and exactly one stderr line, "tileshade: error: ..." containing every needle.
void expectOneErrorLine(const std::string& args, const std::vector<std::string>& needles) {
  CliRun r = runTileshade(args, Streams::StderrOnly);
  EXPECT_EQ(r.exitCode(), 1) << args << "\n" << r.output;
  EXPECT_EQ(lines(r.output), 1u) << args << "\n" << r.output;
  EXPECT_EQ(r.output.rfind("tileshade: error: ", 0), 0u) << args << "\n" << r.output;
  for (const auto& n : needles)
    EXPECT_NE(r.output.find(n), std::string::npos) << args << "\n" << r.output;
}

// ---- item 6: options that make no sense ------------------------------------------------------

TEST(HostileOptions, NumbersThatMakeNoSenseAreRefusedWithOneLine) {
  if (!binaryBuilt()) GTEST_SKIP() << "tileshade binary not built";
  fs::path out = freshDir("options");
  std::string common = " --device cpu --width 32 --height 18 --out " + out.string();
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"--light-threshold nan", "--light-threshold"},
      {"--light-threshold -1", "--light-threshold"},
      {"--light-threshold inf", "--light-threshold"},
      {"--exposure nan", "--exposure"},
      {"--exposure -1", "--exposure"},
      {"--exposure 0", "--exposure"},
      {"--light-range -2", "--light-range"},
      {"--light-range inf", "--light-range"},
      {"--light-count 99999999", "--light-count"},
      {"--slices 0", "--slices"},
      {"--frame -1", "--frame"},
      {"--tile 99999999999", "--tile"},
      {"--tile 0x16", "--tile"},
      {"--heatmap", "--heatmap needs --check"},
      {"--width 0", "--width"},
      {"--height 100000", "--height"},
      {"--normal-maps maybe", "--normal-maps"},
  };
  for (const auto& [args, needle] : cases) expectOneErrorLine("render " + args + common, {needle});
  // Once "stoul" was the whole message.
  expectOneErrorLine("render --device 99999999999999999999 --out " + out.string(),
                     {"device index"});
  // Nothing was written: every option is checked before any work.
  EXPECT_TRUE(fs::is_empty(out)) << out;
  fs::remove_all(out);
}

TEST(HostileOptions, BadSlicesFailBeforeAnyImageIsWritten) {
  if (!binaryBuilt()) GTEST_SKIP() << "tileshade binary not built";
  fs::path out = freshDir("slices");
  expectOneErrorLine(
      "render --technique all --slices 0 --device cpu --width 32 --height 18 --out " +
          (out / "run").string(),
      {"--slices"});
  EXPECT_FALSE(fs::exists(out / "run")) << "images written before the error";
  fs::remove_all(out);
}

TEST(HostileOptions, SceneExportRefusesOtherExtensions) {
  if (!binaryBuilt()) GTEST_SKIP() << "tileshade binary not built";
  fs::path out = freshDir("export_ext");
  expectOneErrorLine("scene export builtin:street " + (out / "x.obj").string(), {".gltf or .glb"});
  EXPECT_FALSE(fs::exists(out / "x.obj"));
  EXPECT_THROW(ts::checkExportPath("x.obj"), ts::Error);
  EXPECT_NO_THROW(ts::checkExportPath("x.GLB"));
  fs::remove_all(out);
}

// ---- item 5: every write is checked ----------------------------------------------------------

// Each output file of `render` in turn is a link to /dev/full (a full disk): one error line, exit
// 1, no "wrote DIR/".
TEST(HostileWrites, EveryRenderOutputFileIsChecked) {
  if (!binaryBuilt()) GTEST_SKIP() << "tileshade binary not built";
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  for (const char* file : {"image.png", "image.exr", "stats.json", "lights.json", "gbuffer.exr"}) {
    fs::path out = freshDir(std::string("full_") + file);
    fs::create_symlink("/dev/full", out / file);
    CliRun r = runTileshade(
        "render --lights few --width 32 --height 18 --device cpu --dump --out " + out.string());
    EXPECT_EQ(r.exitCode(), 1) << file << "\n" << r.output;
    EXPECT_NE(r.output.find("tileshade: error: cannot write " + (out / file).string() +
                            ": No space left on device"),
              std::string::npos)
        << file << "\n"
        << r.output;
    EXPECT_EQ(r.output.find("wrote"), std::string::npos) << file << "\n" << r.output;
    EXPECT_EQ(r.output.find("libpng"), std::string::npos) << file << "\n" << r.output;
    fs::remove_all(out);
  }
}

TEST(HostileWrites, UnwritableOutputFolderIsAnError) {
  if (!binaryBuilt()) GTEST_SKIP() << "tileshade binary not built";
  fs::path dir = freshDir("unwritable");
  std::ofstream(dir / "a-file") << "x";  // --out below a regular file: even root cannot create it
  expectOneErrorLine("render --lights few --width 32 --height 18 --device cpu --out " +
                         (dir / "a-file" / "out").string(),
                     {"cannot create output folder"});
  if (::geteuid() != 0) {  // a read-only folder stops everyone but root
    fs::create_directories(dir / "ro");
    fs::permissions(dir / "ro", fs::perms::owner_read | fs::perms::owner_exec);
    expectOneErrorLine(
        "render --lights few --width 32 --height 18 --device cpu --out " + (dir / "ro").string(),
        {"cannot write", "Permission denied"});
    fs::permissions(dir / "ro", fs::perms::owner_all);
  }
  fs::remove_all(dir);
}

TEST(HostileWrites, GltfExportIsChecked) {
  if (!binaryBuilt()) GTEST_SKIP() << "tileshade binary not built";
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  fs::path dir = freshDir("export_full");
  for (const char* name : {"x.gltf", "x.glb"}) {
    fs::create_symlink("/dev/full", dir / name);
    expectOneErrorLine("scene export builtin:atrium " + (dir / name).string(),
                       {"cannot write", "No space left on device"});
  }
  fs::remove_all(dir);
}

TEST(HostileWrites, BenchOutputsAreChecked) {
  if (!binaryBuilt()) GTEST_SKIP() << "tileshade binary not built";
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  // bench.json and summary.csv are written through a .tmp file, then renamed.
  for (const char* tmp : {"bench.json.tmp", "summary.csv.tmp"}) {
    fs::path out = freshDir(std::string("bench_") + tmp);
    fs::create_symlink("/dev/full", out / tmp);
    CliRun r = runTileshade(
        "bench --device cpu --resolution 32x18 --frames 1 --no-calibrate --quiet "
        "--out " +
        out.string());
    EXPECT_EQ(r.exitCode(), 1) << tmp << "\n" << r.output;
    EXPECT_NE(r.output.find("No space left on device"), std::string::npos) << tmp << "\n"
                                                                           << r.output;
    EXPECT_EQ(r.output.find("wrote"), std::string::npos) << tmp << "\n" << r.output;
    fs::remove_all(out);
  }
}

// ---- item 3: NaN/inf pixels are counted, never reported as exact -------------------------------

// A valid scene whose light is as bright as a float allows would overflow the float image (inf
// pixels) where the double reference does not: the pipeline refuses it before any work with one
// line (src/scene/shading_range.h), so no image with inf pixels is written or reported as exact.
// (How NaN/inf pixels are counted when they do occur: NonFinitePixelsAreCountedAndNeverExact.)
TEST(HostileStats, RenderRefusesScenesThatWouldOverflowFp32) {
  if (!binaryBuilt()) GTEST_SKIP() << "tileshade binary not built";
  fs::path dir = freshDir("overflow");
  json doc = ts::test::triangle();
  doc["extensions"]["KHR_lights_punctual"]["lights"][0]["intensity"] = 3e38;
  doc["nodes"][1]["translation"] = {0.25, 0.25, 0.05};  // nearer than dmin: falloff 100
  std::ofstream(dir / "bright.gltf") << doc.dump();
  CliRun r =
      runTileshade("render --scene " + (dir / "bright.gltf").string() +
                   " --width 32 --height 18 --device cpu --check --out " + (dir / "out").string());
  EXPECT_EQ(r.exitCode(), 1) << r.output;
  EXPECT_NE(r.output.find("beyond what fp32 shading holds"), std::string::npos) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  EXPECT_FALSE(fs::exists(dir / "out" / "stats.json"));
  fs::remove_all(dir);
}

// ---- bench configs with absurd values ----------------------------------------------------------

TEST(HostileBenchConfig, ResumeFromACorruptedCsvDropsTheRowInOneLine) {
  if (!binaryBuilt()) GTEST_SKIP() << "tileshade binary not built";
  fs::path out = freshDir("resume");
  // A bench.csv whose one row has a frame beyond int: once "stoi" was the whole message, then a
  // one-line error; now the row is dropped with one warning line and the run goes on.
  const std::vector<std::string> columns = ts::benchCsvColumns();
  std::string header, row;
  for (size_t i = 0; i < columns.size(); ++i) {
    header += (i ? "," : "") + columns[i];
    row += std::string(i ? "," : "") + (columns[i] == "config_id" ? "abc"
                                        : columns[i] == "frame"   ? "99999999999999"
                                                                  : "");
  }
  std::ofstream(out / "bench.csv") << header << "\n" << row << "\n";
  CliRun r = runTileshade(
      "bench --device cpu --resolution 32x18 --technique tiled --frames 1 "
      "--warmup 0 --no-calibrate --quiet --resume --out " +
          out.string(),
      Streams::StderrOnly);
  EXPECT_EQ(r.exitCode(), 0) << r.output;
  EXPECT_EQ(lines(r.output), 1u) << r.output;
  EXPECT_EQ(r.output.rfind("tileshade: warning: bench --resume: dropped 1 row(s)", 0), 0u)
      << r.output;
  std::ifstream in(out / "bench.csv");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(text.find("99999999999999"), std::string::npos) << "the dropped row is still there";
  EXPECT_EQ(lines(text), 2u) << text;  // the header and the one new row
  fs::remove_all(out);
}

// ---- issue #16 item 13: bench and CLI messages ------------------------------------------------

TEST(HostileBenchMessages, UnknownDeviceIsRefusedBeforeAnyFileEvenQuiet) {
  if (!binaryBuilt()) GTEST_SKIP() << "tileshade binary not built";
  fs::path out = freshDir("nodevice");
  expectOneErrorLine(
      "bench --device cpu,no-such-device --resolution 32x18 --technique tiled "
      "--frames 1 --no-calibrate --quiet --out " +
          (out / "run").string(),
      {"no OpenCL device matches 'no-such-device'"});
  EXPECT_FALSE(fs::exists(out / "run")) << "files written before the device was checked";
  fs::remove_all(out);
}

TEST(HostileBenchMessages, ShardStatesTheLimitItApplies) {
  if (!binaryBuilt()) GTEST_SKIP() << "tileshade binary not built";
  CliRun r = runTileshade("bench --shard 0/1000000 --list", Streams::StderrOnly);
  EXPECT_EQ(r.exitCode(), 0) << r.output;
  expectOneErrorLine("bench --shard 0/1000001 --list", {"n <= 1000000", "'0/1000001'"});
}

TEST(HostileCli, UnknownSubcommandIsNamed) {
  if (!binaryBuilt()) GTEST_SKIP() << "tileshade binary not built";
  expectOneErrorLine("renderx", {"unknown subcommand 'renderx'", "render", "bench", "devices"});
  expectOneErrorLine("scene exportx a b", {"unknown subcommand 'exportx'", "export"});
  expectOneErrorLine("", {"subcommand is required"});
}

TEST(HostileCli, NumberErrorsEchoWhatWasTyped) {
  if (!binaryBuilt()) GTEST_SKIP() << "tileshade binary not built";
  fs::path out = freshDir("typed");
  for (const char* option : {"--light-range", "--light-threshold", "--exposure"})
    for (const char* typed : {"1e39", "-1e400", "1e-50", "0x1p200"}) {
      std::string args = std::string("render ") + option + " " + typed + " --out " + out.string();
      expectOneErrorLine(args, {option, std::string("'") + typed + "'"});
      CliRun r = runTileshade(args, Streams::StderrOnly);
      EXPECT_EQ(r.output.find("inf'"), std::string::npos) << r.output;
    }
  EXPECT_TRUE(fs::is_empty(out)) << out;
  EXPECT_EQ(ts::numberTextProblem("1e-50", ts::NumberRule::AtLeastZero),
            "expected a finite number >= 0 that is not 0 as a float, got '1e-50'");
  EXPECT_EQ(ts::numberTextProblem("0.5", ts::NumberRule::AboveZero), "");
  fs::remove_all(out);
}

}  // namespace
