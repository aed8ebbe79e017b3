// Hostile use of the command line and its outputs (issue #12): options that make no sense, every
// failed or truncated write, images with NaN/inf pixels (never reported as exact), bench configs
// with absurd values. The expected outcome is one line "tileshade: error: ..." and exit status 1
// before any file is written, or an honest report.

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
#include "bench/progress.h"
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
fs::path freshDir(const std::string& name) {
  return ts::test::freshDir("hostile", name);
}

size_t lines(const std::string& s) { return size_t(std::count(s.begin(), s.end(), '\n')); }

bool binaryBuilt() { return fs::exists(TILESHADE_BINARY); }

// Exit status 1 and exactly one stderr line, "tileshade: error: ..." containing every needle.
void expectOneErrorLine(const std::string& args, const std::vector<std::string>& needles) {
  CliRun r = runTileshade(args, Streams::StderrOnly);
  EXPECT_EQ(r.exitCode(), 1) << args << "\n" << r.output;
  EXPECT_EQ(lines(r.output), 1u) << args << "\n" << r.output;
  EXPECT_EQ(r.output.rfind("tileshade: error: ", 0), 0u) << args << "\n" << r.output;
  for (const auto& n : needles) EXPECT_NE(r.output.find(n), std::string::npos) << args << "\n" << r.output;
}

// ---- item 6: options that make no sense ------------------------------------------------------

TEST(HostileOptions, NumbersThatMakeNoSenseAreRefusedWithOneLine) {
  if (!binaryBuilt()) GTEST_SKIP() << "tileshade binary not built";
  fs::path out = freshDir("options");
  std::string common = " --device cpu --width 32 --height 18 --out " + out.string();
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"--light-threshold nan", "--light-threshold"}, {"--light-threshold -1", "--light-threshold"},
      {"--light-threshold inf", "--light-threshold"}, {"--exposure nan", "--exposure"},
      {"--exposure -1", "--exposure"},               {"--exposure 0", "--exposure"},
      {"--light-range -2", "--light-range"},         {"--light-range inf", "--light-range"},
      {"--light-count 99999999", "--light-count"},   {"--slices 0", "--slices"},
      {"--frame -1", "--frame"},                     {"--tile 99999999999", "--tile"},
      {"--tile 0x16", "--tile"},                     {"--heatmap", "--heatmap needs --check"},
      {"--width 0", "--width"},                      {"--height 100000", "--height"},
  };
  for (const auto& [args, needle] : cases) expectOneErrorLine("render " + args + common, {needle});
  // Once "stoul" was the whole message.
  expectOneErrorLine("render --device 99999999999999999999 --out " + out.string(), {"device index"});
  // Nothing was written: every option is checked before any work.
  EXPECT_TRUE(fs::is_empty(out)) << out;
  fs::remove_all(out);
}

TEST(HostileOptions, BadSlicesFailBeforeAnyImageIsWritten) {
  if (!binaryBuilt()) GTEST_SKIP() << "tileshade binary not built";
  fs::path out = freshDir("slices");
  expectOneErrorLine("render --technique all --slices 0 --device cpu --width 32 --height 18 --out " +
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

TEST(HostileOptions, SharedValidatorsRefuseNanInfAndRanges) {
  using ts::NumberRule;
  for (const char* bad : {"nan", "inf", "-inf", "-1", "1e39", "abc", "", "1.5x"})
    EXPECT_THROW(ts::parseNumber("--x", bad, NumberRule::AtLeastZero), ts::Error) << bad;
  EXPECT_EQ(ts::parseNumber("--x", " 0.25 ", NumberRule::AtLeastZero), 0.25f);
  EXPECT_THROW(ts::parseNumber("--x", "0", NumberRule::AboveZero), ts::Error);
  EXPECT_THROW(ts::checkNumber("--x", std::nan(""), NumberRule::AtLeastZero), ts::Error);
  EXPECT_THROW(ts::parseInteger("--n", "99999999999999999999", 0, 10), ts::Error);
  try {
    ts::checkNumber("--exposure", -1.0, NumberRule::AboveZero);
    ADD_FAILURE();
  } catch (const ts::Error& e) {
    EXPECT_EQ(std::string(e.what()), "--exposure: expected a finite number > 0, got '-1'");
  }
}

// ---- item 5: every write is checked ----------------------------------------------------------

TEST(HostileWrites, WriteFileReportsAFullDisk) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  try {
    ts::writeFile("/dev/full", std::string(100000, 'x'));
    ADD_FAILURE() << "no error writing /dev/full";
  } catch (const ts::Error& e) {
    EXPECT_NE(std::string(e.what()).find("No space left on device"), std::string::npos) << e.what();
  }
  std::ofstream stream("/dev/full");
  stream << std::string(100000, 'x');
  EXPECT_THROW(ts::flushChecked(stream, "/dev/full"), ts::Error);
  fs::path dir = freshDir("write_into_file");
  std::ofstream(dir / "file") << "x";
  EXPECT_THROW(ts::writeFile((dir / "file" / "stats.json").string(), "{}"), ts::Error);
  fs::remove_all(dir);
}

// Each output file of `render` in turn is a link to /dev/full (a full disk): one error line, exit 1,
// no "wrote DIR/".
TEST(HostileWrites, EveryRenderOutputFileIsChecked) {
  if (!binaryBuilt()) GTEST_SKIP() << "tileshade binary not built";
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  for (const char* file : {"image.png", "image.exr", "stats.json", "lights.json", "gbuffer.exr"}) {
    fs::path out = freshDir(std::string("full_") + file);
    fs::create_symlink("/dev/full", out / file);
    CliRun r = runTileshade("render --lights few --width 32 --height 18 --device cpu --dump --out " +
                            out.string());
    EXPECT_EQ(r.exitCode(), 1) << file << "\n" << r.output;
    EXPECT_NE(r.output.find("tileshade: error: cannot write " + (out / file).string() +
                            ": No space left on device"),
              std::string::npos)
        << file << "\n" << r.output;
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
    expectOneErrorLine("render --lights few --width 32 --height 18 --device cpu --out " +
                           (dir / "ro").string(),
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
    CliRun r = runTileshade("bench --device cpu --resolution 32x18 --frames 1 --no-calibrate --quiet "
                            "--out " + out.string());
    EXPECT_EQ(r.exitCode(), 1) << tmp << "\n" << r.output;
    EXPECT_NE(r.output.find("No space left on device"), std::string::npos) << tmp << "\n" << r.output;
    EXPECT_EQ(r.output.find("wrote"), std::string::npos) << tmp << "\n" << r.output;
    fs::remove_all(out);
  }
}

// ---- item 3: NaN/inf pixels are counted, never reported as exact -------------------------------

TEST(HostileStats, NonFinitePixelsAreCountedAndNeverExact) {
  ts::ReferenceImage ref;
  ref.width = 2;
  ref.height = 1;
  ref.rgb = {glm::dvec3(0.5), glm::dvec3(1.0)};
  ref.peak = 1.0;
  std::vector<glm::vec4> exact = {glm::vec4(0.5f), glm::vec4(1.0f)};
  ts::ErrorStats e = ts::compareToReference(exact, ref, 1e-4);
  EXPECT_TRUE(std::isinf(e.psnr) && e.psnr > 0);  // exact
  EXPECT_EQ(e.nonfinitePixels, 0u);

  std::vector<glm::vec4> broken = {glm::vec4(std::nanf("")), glm::vec4(1.0f)};
  e = ts::compareToReference(broken, ref, 1e-4);
  EXPECT_EQ(e.nonfinitePixels, 1u);
  EXPECT_EQ(e.pixelsAboveTolerance, 1u);
  EXPECT_TRUE(std::isinf(e.maxAbs) && e.maxAbs > 0);
  EXPECT_TRUE(std::isinf(e.psnr) && e.psnr < 0);
  json j = ts::errorJson(e);
  EXPECT_EQ(j["psnr_db"], "-inf");
  EXPECT_EQ(j["max_abs"], "inf");
  EXPECT_EQ(j["rmse"], "inf");
  EXPECT_EQ(j["nonfinite_pixels"], 1);
  for (auto it = j.begin(); it != j.end(); ++it) EXPECT_FALSE(it->is_null()) << it.key();
  EXPECT_EQ(ts::countNonFinitePixels({glm::vec4(INFINITY), glm::vec4(0.0f), glm::vec4(-NAN)}), 2u);
  // The heat map's error of such a pixel is infinite (white), not NaN.
  EXPECT_TRUE(std::isinf(ts::errorMap(broken, ref)[0]));
}

TEST(HostileStats, BenchSummariesKeepInfiniteErrors) {
  auto row = [](int frame, json error) {
    return json{{"config_id", "c"}, {"config", {{"technique", "tiled"}}}, {"technique", "tiled"},
                {"frame", frame}, {"total_ms", 1.0}, {"error", error}, {"nonfinite_pixels", frame}};
  };
  json rows = json::array({row(0, {{"max_abs", 0.0}, {"rmse", 0.0}, {"psnr_db", "inf"}, {"max_rel_peak", 0.0}}),
                           row(1, {{"max_abs", "inf"}, {"rmse", "inf"}, {"psnr_db", "-inf"}, {"max_rel_peak", "inf"}})});
  json s = ts::summarizeRows(rows);
  ASSERT_EQ(s.size(), 1u);
  EXPECT_EQ(s[0]["error"]["psnr_db"], "-inf");  // not "inf" (exact), not the finite frame's
  EXPECT_EQ(s[0]["error"]["max_abs"], "inf");
  EXPECT_EQ(s[0]["nonfinite_pixels_max"], 1);
  json exact = ts::summarizeRows(json::array({rows[0]}));
  EXPECT_EQ(exact[0]["error"]["psnr_db"], "inf");
}

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
  CliRun r = runTileshade("render --scene " + (dir / "bright.gltf").string() +
                          " --width 32 --height 18 --device cpu --check --out " + (dir / "out").string());
  EXPECT_EQ(r.exitCode(), 1) << r.output;
  EXPECT_NE(r.output.find("beyond what fp32 shading holds"), std::string::npos) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  EXPECT_FALSE(fs::exists(dir / "out" / "stats.json"));
  fs::remove_all(dir);
}

// ---- bench configs with absurd values ----------------------------------------------------------

void expectConfigError(const std::string& text, const std::string& needle) {
  ts::BenchOptions o;
  try {
    ts::applyBenchConfig(text, "c.json", o, [](const std::string&) { return false; });
    ts::expandSweep(o.sweep);
    ADD_FAILURE() << "no error for " << text;
  } catch (const ts::Error& e) {
    std::string m = e.what();
    EXPECT_NE(m.find(needle), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  }
}

TEST(HostileBenchConfig, AbsurdValuesAreOneLineErrors) {
  expectConfigError(R"({"calib_mib": -1})", "calib_mib");  // was shifted into a huge size_t
  expectConfigError(R"({"warmup": 4294967297})", "warmup");  // was truncated to 1
  expectConfigError(R"({"repeat": 0})", "repeat");
  expectConfigError(R"({"frames": 1e30})", "frames");
  expectConfigError(R"({"light_threshold": "nan"})", "--light-threshold");
  expectConfigError(R"({"light_range": 1e39})", "--light-range");
  expectConfigError(R"({"slices": 0})", "--slices");
  // A product of lists far beyond what could run: refused before it is built.
  std::string many;
  for (int i = 1; i <= 60; ++i) many += (i > 1 ? "," : "") + std::to_string(i);
  expectConfigError(R"({"seed": [)" + many + R"(], "light_count": [)" + many +
                        R"(], "tile": [)" + many + R"(], "slices": [)" + many + "]}",
                    "configurations");
  // Repeated values do not multiply: 1000 copies of one tile size are one configuration.
  ts::BenchOptions o;
  std::string same;
  for (int i = 0; i < 1000; ++i) same += std::string(i ? "," : "") + "\"16\"";
  ts::applyBenchConfig(R"({"tile": [)" + same + R"(], "seed": [)" + same + "]}", "c.json", o,
                       [](const std::string&) { return false; });
  EXPECT_EQ(ts::expandSweep(o.sweep).size(), 1u);
}

// Bench configs the fuzzer found slow or crashing (tests/data/fuzz/*.json): each is applied and
// expanded, ending in success or one line.
TEST(HostileBenchConfig, FuzzerFindingsParseOrFailCleanly) {
  fs::path dir = fs::path(ts::test::sourceDir()) / "tests" / "data" / "fuzz";
  size_t files = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.path().extension() != ".json") continue;
    ++files;
    std::ifstream in(e.path());
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ts::BenchOptions o;
    try {
      ts::applyBenchConfig(text, e.path().string(), o, [](const std::string&) { return false; });
      ts::expandSweep(o.sweep);
    } catch (const ts::Error& x) {
      EXPECT_EQ(std::string(x.what()).find('\n'), std::string::npos) << x.what();
    }
  }
  EXPECT_GT(files, 0u);
}

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
  CliRun r = runTileshade("bench --device cpu --resolution 32x18 --technique tiled --frames 1 "
                          "--warmup 0 --no-calibrate --quiet --resume --out " + out.string(),
                          Streams::StderrOnly);
  EXPECT_EQ(r.exitCode(), 0) << r.output;
  EXPECT_EQ(lines(r.output), 1u) << r.output;
  EXPECT_EQ(r.output.rfind("tileshade: warning: bench --resume: dropped 1 row(s)", 0), 0u) << r.output;
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
  expectOneErrorLine("bench --device cpu,no-such-device --resolution 32x18 --technique tiled "
                     "--frames 1 --no-calibrate --quiet --out " + (out / "run").string(),
                     {"no OpenCL device matches 'no-such-device'"});
  EXPECT_FALSE(fs::exists(out / "run")) << "files written before the device was checked";
  fs::remove_all(out);
}

TEST(HostileBenchMessages, QuietNeverHidesAFailure) {
  ::testing::internal::CaptureStderr();
  {
    ts::Progress quiet(3, false);
    quiet.step("a");
    quiet.note("bench: configuration failed: why");
  }
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "bench: configuration failed: why\n");
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
