// The knobs' name tables (util/enum_names.h): every value reads back from its name, an unknown
// name is one line listing the known ones, and `render`, `bench` and `check` --help list exactly
// the table's names; PipelineOptions makes the TechniqueConfig; bench sweeps --depth-split.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "bench/bench_cli.h"
#include "bench/bench_config.h"
#include "bench/bench_resume.h"
#include "bench/bench_run.h"
#include "bench/bench_stats.h"
#include "gbuffer/gbuffer_layout.h"
#include "raster/raster_backend.h"
#include "cli/render_job.h"
#include "scene/scene.h"
#include "techniques/technique_knobs.h"
#include "test_support.h"
#include "util/enum_names.h"
#include "util/error.h"

namespace fs = std::filesystem;

namespace ts {
namespace {

// Each name once, and each value read back from its name.
template <typename E>
void expectRoundTrip(const EnumNames<E>& table) {
  SCOPED_TRACE(table.what());
  ASSERT_FALSE(table.entries().empty());
  std::set<std::string> names;
  for (const auto& e : table.entries()) {
    EXPECT_TRUE(names.insert(e.name).second) << e.name;
    EXPECT_EQ(table.parse(e.name), e.value) << e.name;
    EXPECT_EQ(table.parseOption("--knob", std::string(" ") + e.name + " "), e.value) << e.name;
    EXPECT_EQ(table.name(e.value), std::string(e.name));
  }
}

// An unknown name: one line naming the value and every known name (with the option, if given).
template <typename E>
void expectUnknownListsNames(const EnumNames<E>& table) {
  SCOPED_TRACE(table.what());
  for (bool asOption : {false, true}) {
    try {
      asOption ? table.parseOption("--knob", "no-such-value") : table.parse("no-such-value");
      ADD_FAILURE() << "no ts::Error";
    } catch (const Error& e) {
      const std::string m = e.what();
      EXPECT_EQ(m.find('\n'), std::string::npos) << m;
      EXPECT_NE(m.find("no-such-value"), std::string::npos) << m;
      EXPECT_NE(m.find(table.list()), std::string::npos) << m;
      if (asOption) {
        EXPECT_EQ(m.rfind("--knob:", 0), 0u) << m;
      }
    }
  }
}

template <typename E>
void expectWellFormed(const EnumNames<E>& table) {
  expectRoundTrip(table);
  expectUnknownListsNames(table);
}

TEST(ConfigKnobs, EveryTableRoundTripsAndNamesTheKnownValues) {
  expectWellFormed(cullTestNames());
  expectWellFormed(spotCullingNames());
  expectWellFormed(mathModeNames());
  expectWellFormed(rangeModelNames());
  expectWellFormed(laneNames());
  expectWellFormed(gbufferFormatNames());
  expectWellFormed(shadingModelNames());
  expectWellFormed(rasterBackendNames());
  expectWellFormed(switchNames());
}

// The names files and kernels were written with before the tables: bench.csv, stats.json and the
// kernel build options keep them.
TEST(ConfigKnobs, NamesAndKernelNumbersAreTheEstablishedOnes) {
  EXPECT_EQ(cullTestNames().list(), "rect, frustum, aabb");
  EXPECT_EQ(spotCullingNames().list(), "cone, bound-sphere, range-sphere");
  EXPECT_EQ(mathModeNames().list(), "precise, fast, native");
  EXPECT_EQ(laneNames().list(), "auto, 1, 2, 4, 8, 16");
  EXPECT_EQ(gbufferFormatNames().list(), "fp32, fp16, packed");
  EXPECT_EQ(shadingModelNames().list(), "blinn-phong, metallic-roughness");
  EXPECT_EQ(rasterBackendNames().list(), "software, gl");
  TechniqueConfig c;
  c.features.spot = true;
  c.rangeModel = RangeModel::Physical;
  c.culling = CullTest::Aabb;
  c.spotCulling = SpotCulling::RangeSphere;
  c.math = MathMode::Native;
  const std::string options = c.kernelOptions();
  for (const char* want :
       {" -DTS_MODEL=1", " -DTS_CULL=2", " -DTS_SPOT_CULL=2", " -DTS_NATIVE_MATH"})
    EXPECT_NE(options.find(want), std::string::npos) << want << " in " << options;
  c.math = MathMode::Fast;
  EXPECT_NE(c.kernelOptions().find(" -cl-fast-relaxed-math"), std::string::npos);
}

// The entry of `option` in a --help text ("  --culling TEXT=rect   per-tile light test: ..."),
// with the description CLI11 puts on the next line after a long option column.
std::string helpLine(const std::string& help, const std::string& option) {
  std::istringstream in(help);
  std::string entry;
  for (std::string line; std::getline(in, line);) {
    if (!entry.empty()) {
      if (line.rfind("  -", 0) == 0 || line.find_first_not_of(' ') == std::string::npos) break;
      entry += " " + line.substr(line.find_first_not_of(' '));
    } else if (line.rfind("  " + option + " ", 0) == 0) {
      entry = line;
    }
  }
  return entry;
}

template <typename E>
void expectHelpLists(const std::string& help, const std::string& option, const EnumNames<E>& table,
                     bool withHelp) {
  const std::string line = helpLine(help, option);
  ASSERT_FALSE(line.empty()) << option << " not in:\n" << help;
  EXPECT_NE(line.find(withHelp ? table.help() : table.list()), std::string::npos)
      << option << ": " << line;
}

TEST(ConfigCli, HelpListsTheTablesNames) {
  if (!fs::exists(TILESHADE_BINARY)) GTEST_SKIP() << "tileshade binary not built";
  const test::CliRun render = test::runTileshade("render --help");
  ASSERT_EQ(render.status, 0) << render.output;
  expectHelpLists(render.output, "--culling", cullTestNames(), true);
  expectHelpLists(render.output, "--spot-culling", spotCullingNames(), true);
  expectHelpLists(render.output, "--math", mathModeNames(), true);
  expectHelpLists(render.output, "--lanes", laneNames(), true);
  expectHelpLists(render.output, "--gbuffer", gbufferFormatNames(), true);
  expectHelpLists(render.output, "--raster", rasterBackendNames(), true);
  expectHelpLists(render.output, "--shading-model", shadingModelNames(), false);

  const test::CliRun bench = test::runTileshade("bench --help");
  ASSERT_EQ(bench.status, 0) << bench.output;
  expectHelpLists(bench.output, "--culling", cullTestNames(), false);
  expectHelpLists(bench.output, "--spot-culling", spotCullingNames(), false);
  expectHelpLists(bench.output, "--math", mathModeNames(), false);
  expectHelpLists(bench.output, "--lanes", laneNames(), true);
  expectHelpLists(bench.output, "--gbuffer", gbufferFormatNames(), false);
  expectHelpLists(bench.output, "--raster", rasterBackendNames(), false);
  expectHelpLists(bench.output, "--shading-model", shadingModelNames(), false);
  expectHelpLists(bench.output, "--depth-split", switchNames(), false);

  const test::CliRun check = test::runTileshade("check --help");
  ASSERT_EQ(check.status, 0) << check.output;
  expectHelpLists(check.output, "--gbuffer", gbufferFormatNames(), false);
}

TEST(ConfigCli, UnknownKnobValueIsOneLineNamingTheOption) {
  if (!fs::exists(TILESHADE_BINARY)) GTEST_SKIP() << "tileshade binary not built";
  for (const char* option :
       {"--culling", "--spot-culling", "--math", "--lanes", "--gbuffer", "--raster"}) {
    const test::CliRun r =
        test::runTileshade(std::string("render --width 8 --height 8 ") + option + " bogus");
    EXPECT_EQ(r.exitCode(), 1) << option;
    EXPECT_EQ(r.output.rfind(std::string("tileshade: error: ") + option + ": expected one of ", 0),
              0u)
        << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  }
}

// render and bench turn the same pipeline into the same technique configuration.
TEST(PipelineOptions, MakesTheTechniqueConfigAndSceneOptions) {
  PipelineOptions p;
  p.format = GBufferFormat::FP16;
  p.tileWidth = 32;
  p.tileHeight = 8;
  p.clusterSlices = 24;
  p.culling = CullTest::Frustum;
  p.spotCulling = SpotCulling::BoundSphere;
  p.depthSplit = true;
  p.math = MathMode::Fast;
  p.lanes = 4;
  p.lightSet = "few";
  p.seed = 9;
  p.lightCount = 12;
  p.lightRange = 2.5f;
  p.variant = "spot";
  const SceneFeatures features = SceneFeatures::general(ShadingModel::MetallicRoughness);
  const TechniqueConfig t = p.techniqueConfig(features);
  TechniqueConfig want;
  want.format = GBufferFormat::FP16;
  want.features = features;
  want.tileWidth = 32;
  want.tileHeight = 8;
  want.clusterSlices = 24;
  want.culling = CullTest::Frustum;
  want.spotCulling = SpotCulling::BoundSphere;
  want.depthSplit = true;
  want.math = MathMode::Fast;
  want.lanes = 4;
  EXPECT_EQ(t.key(), want.key());
  RenderOptions render;
  static_cast<PipelineOptions&>(render) = p;
  BenchConfig bench;
  static_cast<PipelineOptions&>(bench) = p;
  EXPECT_EQ(render.techniqueConfig(features).key(), bench.techniqueConfig(features).key());
  const SceneOptions s = p.sceneOptions();
  EXPECT_EQ(s.lightSet, "few");
  EXPECT_EQ(s.seed, 9u);
  EXPECT_EQ(s.lightCount, 12);
  EXPECT_EQ(s.lightRange, 2.5f);
  EXPECT_EQ(s.variant, "spot");
}

TEST(BenchDepthSplit, SweepGivesTwoConfigurationsWithOtherKernels) {
  BenchSweep sweep;
  sweep.set("depth_split", {"false,true"});
  const std::vector<BenchConfig> configs = expandSweep(sweep);
  ASSERT_EQ(configs.size(), 2u);
  EXPECT_FALSE(configs[0].depthSplit);
  EXPECT_TRUE(configs[1].depthSplit);
  EXPECT_NE(configs[0].key(), configs[1].key());
  EXPECT_NE(configs[0].id(), configs[1].id());
  const SceneFeatures features = SceneFeatures::general(ShadingModel::BlinnPhong);
  const std::string off = configs[0].techniqueConfig(features).kernelOptions();
  const std::string on = configs[1].techniqueConfig(features).kernelOptions();
  EXPECT_EQ(off.find("-DTS_DEPTH_SPLIT"), std::string::npos) << off;
  EXPECT_NE(on.find("-DTS_DEPTH_SPLIT=1"), std::string::npos) << on;
  // Off is the default: its key (so the id of every earlier sweep's configuration) is the one
  // written before the dimension existed.
  EXPECT_EQ(configs[0].key(), BenchConfig{}.key());
  EXPECT_EQ(configs[0].key().find("depth_split"), std::string::npos) << configs[0].key();
  EXPECT_NE(configs[1].key().find("depth_split=true"), std::string::npos) << configs[1].key();
  // Its column: between culling and math, the others in their order.
  const std::vector<std::string> columns = benchCsvColumns();
  auto at = [&](const char* name) {
    return std::find(columns.begin(), columns.end(), name) - columns.begin();
  };
  EXPECT_EQ(at("depth_split"), at("culling") + 1);
  EXPECT_EQ(at("math"), at("depth_split") + 1);
}

TEST(BenchDepthSplit, ConfigFileTakesBooleansAndOptionRefusesOtherValues) {
  BenchOptions o;
  applyBenchConfig(R"({"depth_split": [false, true]})", "test", o,
                   [](const std::string&) { return false; });
  EXPECT_EQ(expandSweep(o.sweep).size(), 2u);
  BenchSweep bad;
  bad.set("depth_split", {"maybe"});
  try {
    expandSweep(bad);
    ADD_FAILURE() << "no ts::Error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), "--depth-split: expected one of false, true, got 'maybe'");
  }
}

// A bench.csv of the version before the column is not resumed: one clear line, as for any file
// with other columns.
TEST(BenchDepthSplit, ResumeOfAFileWithoutTheColumnIsOneClearError) {
  const fs::path dir =
      fs::temp_directory_path() / ("tileshade_depth_split_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::vector<std::string> old = benchCsvColumns();
  old.erase(std::find(old.begin(), old.end(), "depth_split"));
  const std::string path = (dir / "bench.csv").string();
  std::ofstream(path) << csvLine(old) << "\n";
  try {
    scanBenchCsv(path, {}, 1, 1);
    ADD_FAILURE() << "no ts::Error";
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    EXPECT_NE(m.find("other columns"), std::string::npos) << m;
  }
  fs::remove_all(dir);
}

// stats.json names every knob of a render as bench names it: the same value text as the bench
// dimension of that name (bench.csv's column), for values other than the defaults.
TEST(ConfigKnobs, StatsJsonNamesTheKnobsAsBenchDoes) {
  const fs::path dir = test::freshDir("config_knobs", "stats");
  const std::map<std::string, std::string> knobs = {
      {"culling", "aabb"}, {"spot_culling", "range-sphere"},
      {"math", "fast"},    {"depth_split", "true"},
      {"slices", "8"},     {"gbuffer", "packed"}};
  std::string args = "render --width 32 --height 18 --technique tiled --out " + dir.string();
  for (const auto& [name, value] : knobs) {
    args += " " + findDimension(name).optionName();
    if (name != "depth_split") args += " " + value;  // a flag on render's command line
  }
  test::CliRun r = test::runTileshade(args);
  ASSERT_EQ(r.exitCode(), 0) << r.output;
  std::ifstream in(dir / "stats.json");
  const nlohmann::json stats = nlohmann::json::parse(in);
  for (const auto& [name, value] : knobs) {
    ASSERT_TRUE(stats.contains(name)) << name;
    const nlohmann::json& v = stats[name];
    EXPECT_EQ(v.is_string() ? v.get<std::string>() : v.dump(), value) << name;
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace ts
