// `tileshade bench`: sweep expansion, value parsing, shards, statistics, CSV, calibration, and a
// tiny end-to-end run (64x36, two frames) with resume; plus a smoke test of bench/plot.py.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <tuple>

#include <nlohmann/json.hpp>

#include "bench/bench_config.h"
#include "bench/bench_run.h"
#include "bench/bench_stats.h"
#include "bench/calibrate.h"
#include "test_support.h"
#include "util/error.h"

namespace fs = std::filesystem;

namespace {

using ts::BenchSweep;

// A fresh folder per test (tests run in parallel processes).
std::string tempDir(const std::string& name) {
  fs::path p = fs::temp_directory_path() /
               ("tileshade_bench_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(p);
  fs::create_directories(p);
  return p.string();
}

// Expects a ts::Error whose message is one line containing every needle.
template <typename F>
void expectOneLineError(F&& f, std::vector<std::string> needles) {
  try {
    f();
    ADD_FAILURE() << "no ts::Error thrown";
  } catch (const ts::Error& e) {
    std::string m = e.what();
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    for (const auto& n : needles) EXPECT_NE(m.find(n), std::string::npos) << m << " lacks " << n;
  }
}

size_t csvRows(const std::string& path, std::vector<std::string>* header = nullptr,
               std::vector<std::map<std::string, std::string>>* out = nullptr) {
  std::vector<std::string> h;
  std::vector<std::map<std::string, std::string>> rows;
  EXPECT_TRUE(ts::readCsv(path, h, rows)) << path;
  if (header) *header = h;
  if (out) *out = rows;
  return rows.size();
}

ts::BenchOptions tinyOptions(const std::string& out) {
  ts::BenchOptions o;
  o.sweep.set("device", {"cpu"});
  o.sweep.set("resolution", {"64x36"});
  o.sweep.set("technique", {"tiled"});
  o.sweep.set("tile", {"16,32x16"});
  o.frames.text = "0:40:20";  // frames 0 and 20
  o.warmup = 1;
  o.outDir = out;
  o.calibration.copyBytes = size_t(1) << 20;
  o.calibration.repeats = 2;
  o.calibration.minFmaMs = 1.0;
  o.progress = false;
  o.printTable = false;
  return o;
}

TEST(BenchSweep, CartesianProductInDimensionOrder) {
  BenchSweep s;
  s.set("tile", {"8,32x16"});
  s.set("gbuffer", {"fp32", "fp16"});
  s.set("resolution", {"64x36"});
  s.set("light_count", {"1,10,100"});
  auto configs = ts::expandSweep(s);
  ASSERT_EQ(configs.size(), 2u * 2u * 3u);
  // light_count is outermost of these, then gbuffer, then tile (benchDimensions() order).
  EXPECT_EQ(configs[0].lightCount, 1);
  EXPECT_EQ(configs[0].format, ts::GBufferFormat::FP32);
  EXPECT_EQ(configs[0].tileWidth, 8);
  EXPECT_EQ(configs[0].tileHeight, 8);
  EXPECT_EQ(configs[1].tileWidth, 32);
  EXPECT_EQ(configs[1].tileHeight, 16);
  EXPECT_EQ(configs[2].format, ts::GBufferFormat::FP16);
  EXPECT_EQ(configs[4].lightCount, 10);
  std::set<std::string> keys, ids;
  for (const auto& c : configs) {
    EXPECT_EQ(c.width, 64);
    EXPECT_EQ(c.height, 36);
    keys.insert(c.key());
    ids.insert(c.id());
  }
  EXPECT_EQ(keys.size(), configs.size());
  EXPECT_EQ(ids.size(), configs.size());
}

TEST(BenchSweep, DefaultsDuplicatesAndAll) {
  auto one = ts::expandSweep(BenchSweep{});
  ASSERT_EQ(one.size(), 1u);
  EXPECT_EQ(one[0].technique, "tiled");
  EXPECT_EQ(one[0].width, 1280);
  BenchSweep s;
  s.set("tile", {"16", "16x16", " 16 "});
  EXPECT_EQ(ts::expandSweep(s).size(), 1u);  // the same configuration
  BenchSweep all;
  all.set("technique", {"all"});
  EXPECT_EQ(ts::expandSweep(all).size(), ts::techniqueNames().size());
  // The key is stable and names every dimension.
  std::string key = one[0].key();
  for (const auto& d : ts::benchDimensions()) EXPECT_NE(key.find(d.name + "="), std::string::npos);
  EXPECT_EQ(one[0].id(), ts::expandSweep(BenchSweep{})[0].id());
}

TEST(BenchSweep, TileSizesIncludingNonSquare) {
  EXPECT_EQ(ts::parseTileSize("16"), std::make_pair(16, 16));
  EXPECT_EQ(ts::parseTileSize("32x16"), std::make_pair(32, 16));
  EXPECT_EQ(ts::parseTileSize("8X64"), std::make_pair(8, 64));
  EXPECT_EQ(ts::parseTileSize(" 64 "), std::make_pair(64, 64));
  for (const char* bad : {"0", "abc", "16x", "x16", "300", "16x0", "-8", "16x16x2", ""})
    expectOneLineError([&] { ts::parseTileSize(bad); }, {"--tile"});
  EXPECT_EQ(ts::parseResolution("1920x1080"), std::make_pair(1920, 1080));
  expectOneLineError([] { ts::parseResolution("1920"); }, {"--resolution", "'1920'"});
}

TEST(BenchSweep, InvalidValuesGiveOneClearLine) {
  auto expand = [](const std::string& dim, const std::string& value) {
    BenchSweep s;
    s.set(dim, {value});
    ts::expandSweep(s);
  };
  expectOneLineError([&] { expand("gbuffer", "fp8"); }, {"--gbuffer", "fp8", "fp16"});
  expectOneLineError([&] { expand("technique", "nope"); }, {"--technique", "nope", "tiled"});
  expectOneLineError([&] { expand("tile", "16,abc"); }, {"--tile", "abc"});
  expectOneLineError([&] { expand("light_count", "many"); }, {"--light-count", "many"});
  expectOneLineError([&] { expand("light_range", "-3"); }, {"--light-range", "-3"});
  expectOneLineError([&] { expand("culling", "sphere"); }, {"--culling", "sphere"});
  expectOneLineError([&] { expand("tile", ","); }, {"--tile", "empty"});
  expectOneLineError([] { BenchSweep s; s.set("colour", {"red"}); }, {"colour", "technique"});
}

TEST(BenchSweep, OptionsAndColumnsAreUnique) {
  std::set<std::string> options;
  for (const auto& d : ts::benchDimensions()) {
    EXPECT_TRUE(options.insert(d.optionName()).second) << d.optionName();
    EXPECT_TRUE(d.matchesKey(d.name));
  }
  EXPECT_EQ(ts::findDimension("lights").name, "light_set");  // the option stem works as a key
  for (const auto& cols : {ts::benchCsvColumns(), ts::summaryCsvColumns()}) {
    std::set<std::string> unique(cols.begin(), cols.end());
    EXPECT_EQ(unique.size(), cols.size());
  }
}

TEST(BenchSweep, FrameSpecs) {
  EXPECT_EQ(ts::FrameSpec{"0:120:10"}.resolve(240),
            (std::vector<int>{0, 10, 20, 30, 40, 50, 60, 70, 80, 90, 100, 110}));
  EXPECT_EQ(ts::FrameSpec{"5:8"}.resolve(240), (std::vector<int>{5, 6, 7}));
  EXPECT_EQ(ts::FrameSpec{"4"}.resolve(240), (std::vector<int>{0, 60, 120, 180}));
  EXPECT_EQ(ts::FrameSpec{"3"}.resolve(1), (std::vector<int>{0, 1, 2}));  // a one-camera path
  EXPECT_EQ(ts::FrameSpec{"all"}.resolve(5), (std::vector<int>{0, 1, 2, 3, 4}));
  EXPECT_EQ(ts::FrameSpec{"7;1;3;3"}.resolve(240), (std::vector<int>{1, 3, 7}));
  for (const char* bad : {"5:2", "x", "0:10:0", "0", "1,2", ""})
    expectOneLineError([&] { ts::FrameSpec{bad}.validate(); }, {"--frames"});
  std::vector<int> timed{0, 20, 40, 60, 80, 100};
  EXPECT_EQ(ts::selectErrorFrames("all", timed), timed);
  EXPECT_EQ(ts::selectErrorFrames("2", timed), (std::vector<int>{0, 60}));
  EXPECT_EQ(ts::selectErrorFrames("40:200", timed), (std::vector<int>{40, 60, 80, 100}));
  EXPECT_EQ(ts::selectErrorFrames("20;21", timed), (std::vector<int>{20}));
  expectOneLineError([&] { ts::selectErrorFrames("soon", timed); }, {"--error-frames"});
}

TEST(BenchSweep, ShardsPartitionTheConfigurationsExactly) {
  BenchSweep s;
  s.set("tile", {"8,16,32,64,32x16"});
  s.set("gbuffer", {"fp32,fp16"});
  s.set("light_count", {"1,2,3"});
  auto configs = ts::expandSweep(s);
  ASSERT_EQ(configs.size(), 30u);
  for (int n : {1, 2, 3, 4, 7, 31}) {
    std::vector<int> owners(configs.size(), 0);
    std::vector<size_t> perShard(size_t(n), 0);
    for (int k = 0; k < n; ++k) {
      ts::Shard sh = ts::Shard::parse(std::to_string(k) + "/" + std::to_string(n));
      for (size_t i = 0; i < configs.size(); ++i)
        if (sh.selects(i)) {
          ++owners[i];
          ++perShard[size_t(k)];
          EXPECT_EQ(int(i % size_t(n)), k);
        }
    }
    for (int o : owners) EXPECT_EQ(o, 1) << "n=" << n;
    for (size_t c : perShard) EXPECT_LE(c, (configs.size() + size_t(n) - 1) / size_t(n));
  }
  for (const char* bad : {"3/3", "1", "a/b", "-1/2", "0/0"})
    expectOneLineError([&] { ts::Shard::parse(bad); }, {"--shard"});
}

TEST(BenchStats, MedianMinMaxOnKnownInputs) {
  ts::Summary s = ts::summarize({3.0, 1.0, 2.0});
  EXPECT_EQ(s.n, 3u);
  EXPECT_DOUBLE_EQ(s.median, 2.0);
  EXPECT_DOUBLE_EQ(s.min, 1.0);
  EXPECT_DOUBLE_EQ(s.max, 3.0);
  EXPECT_DOUBLE_EQ(s.mean, 2.0);
  s = ts::summarize({4.0, 1.0, 3.0, 2.0, 100.0, 0.5});
  EXPECT_DOUBLE_EQ(s.median, 2.5);
  EXPECT_DOUBLE_EQ(s.min, 0.5);
  EXPECT_DOUBLE_EQ(s.max, 100.0);
  s = ts::summarize({7.0});
  EXPECT_DOUBLE_EQ(s.median, 7.0);
  s = ts::summarize({1.0, std::nan(""), 5.0, INFINITY});
  EXPECT_EQ(s.n, 2u);
  EXPECT_DOUBLE_EQ(s.median, 3.0);
  EXPECT_EQ(ts::summarize({}).n, 0u);

  // summarizeRows: per configuration over frames, the last row of a repeated frame wins.
  nlohmann::json rows = nlohmann::json::array();
  auto row = [](const std::string& id, int frame, double ms) {
    return nlohmann::json{{"config_id", id}, {"config", {{"technique", "t"}}}, {"frame", frame},
                          {"total_ms", ms}, {"wall_ms", ms + 1},
                          {"kernels", {{{"name", "k"}, {"ms", ms}}}}};
  };
  rows.push_back(row("a", 0, 10));
  rows.push_back(row("a", 1, 30));
  rows.push_back(row("b", 0, 5));
  rows.push_back(row("a", 2, 20));
  rows.push_back(row("a", 1, 40));  // re-measured frame 1
  auto sum = ts::summarizeRows(rows);
  ASSERT_EQ(sum.size(), 2u);
  EXPECT_EQ(sum[0]["config_id"], "a");
  EXPECT_EQ(sum[0]["frames"], 3);
  EXPECT_DOUBLE_EQ(sum[0]["total_ms"]["median"].get<double>(), 20.0);
  EXPECT_DOUBLE_EQ(sum[0]["total_ms"]["min"].get<double>(), 10.0);
  EXPECT_DOUBLE_EQ(sum[0]["total_ms"]["max"].get<double>(), 40.0);
  EXPECT_DOUBLE_EQ(sum[0]["kernels"][0]["median"].get<double>(), 20.0);
  EXPECT_DOUBLE_EQ(sum[1]["wall_ms"]["median"].get<double>(), 6.0);
}

TEST(BenchStats, CsvQuotingRoundTripsAndRepeatedHeadersAreSkipped) {
  std::vector<std::string> f = {"plain", "a,b", "say \"hi\"", "", "x;y=1"};
  std::vector<std::string> back;
  EXPECT_TRUE(ts::parseCsvRecord(ts::csvLine(f), back));
  EXPECT_EQ(back, f);
  std::string dir = tempDir("csv");
  std::ofstream(dir + "/cat.csv") << "a,b\n1,2\na,b\n3,\"4,5\"\n";
  std::vector<std::string> header;
  std::vector<std::map<std::string, std::string>> rows;
  ASSERT_TRUE(ts::readCsv(dir + "/cat.csv", header, rows));
  EXPECT_EQ(header, (std::vector<std::string>{"a", "b"}));
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[1]["b"], "4,5");
  EXPECT_FALSE(ts::readCsv(dir + "/missing.csv", header, rows));
  fs::remove_all(dir);
}

TEST(BenchCalibration, ReturnsPositiveFiniteRates) {
  ts::CalibrationOptions o;
  o.copyBytes = size_t(4) << 20;
  o.repeats = 3;
  o.minFmaMs = 2.0;
  ts::Calibration c = ts::calibrate(ts::test::context(), o);
  EXPECT_TRUE(std::isfinite(c.bandwidthGBs));
  EXPECT_TRUE(std::isfinite(c.peakGflops));
  EXPECT_GT(c.bandwidthGBs, 0.0);
  EXPECT_GT(c.peakGflops, 0.0);
  EXPECT_EQ(c.copyMs.size(), 3u);
  EXPECT_EQ(c.fmaMs.size(), 3u);
  EXPECT_EQ(c.copyBytes, size_t(4) << 20);
  // The limit is the slower of the two bounds.
  EXPECT_DOUBLE_EQ(ts::limitMs(c, c.bandwidthGBs * 1e9, 0.0), 1000.0);
  EXPECT_DOUBLE_EQ(ts::limitMs(c, 0.0, c.peakGflops * 1e9 * 2), 2000.0);
  EXPECT_EQ(ts::limitMs(ts::Calibration{}, 1e9, 1e9), 0.0);
}

TEST(BenchRun, WritesOneRowPerConfigurationAndFrameThenResumes) {
  std::string dir = tempDir("run");
  ts::BenchOptions o = tinyOptions(dir);
  o.error = true;
  o.errorFrames = "1";  // frame 0 only
  ts::BenchRunResult r = ts::runBench(o);
  EXPECT_TRUE(r.failures.empty());
  EXPECT_EQ(r.configurations, 2u);
  EXPECT_EQ(r.measuredRows, 4u);

  std::vector<std::string> header;
  std::vector<std::map<std::string, std::string>> rows;
  ASSERT_EQ(csvRows(dir + "/bench.csv", &header, &rows), 4u);
  EXPECT_EQ(header, ts::benchCsvColumns());
  for (const char* col : {"config_id", "technique", "tile", "gbuffer", "resolution", "frame",
                          "total_ms", "kernels", "wall_ms", "compile_ms", "raster_ms",
                          "lighting_computations", "evaluations", "gbuffer_bytes_read",
                          "limit_ms", "limit_pct", "flops_basis", "err_rmse", "err_psnr_db",
                          "err_shading_max_rel_peak"})
    EXPECT_NE(std::find(header.begin(), header.end(), col), header.end()) << col;
  std::set<std::pair<std::string, std::string>> keys;
  for (auto& row : rows) {
    keys.insert({row["config_id"], row["frame"]});
    EXPECT_EQ(row["technique"], "tiled");
    EXPECT_GT(std::stod(row["total_ms"]), 0.0);
    EXPECT_GE(std::stod(row["wall_ms"]), std::stod(row["upload_ms"]));
    EXPECT_GT(std::stod(row["limit_pct"]), 0.0);
    EXPECT_NE(row["kernels"].find("shade="), std::string::npos);
    bool errorFrame = row["frame"] == "0";
    EXPECT_EQ(row["flops_basis"], errorFrame ? "reference" : "evaluations");
    EXPECT_EQ(row["err_rmse"].empty(), !errorFrame);
    EXPECT_EQ(row["err_shading_max_rel_peak"].empty(), !errorFrame);
  }
  EXPECT_EQ(keys.size(), 4u);
  std::set<std::string> tiles;
  for (auto& row : rows) tiles.insert(row["tile"]);
  EXPECT_EQ(tiles, (std::set<std::string>{"16x16", "32x16"}));

  nlohmann::json doc = nlohmann::json::parse(std::ifstream(dir + "/bench.json"));
  ASSERT_EQ(doc["rows"].size(), 4u);
  ASSERT_EQ(doc["summaries"].size(), 2u);
  const auto& j = doc["rows"][0];
  for (const char* k : {"technique", "kernels", "total_ms", "lighting_computations", "evaluations",
                        "gbuffer_bytes_read", "config", "frame", "wall_ms", "limit", "error",
                        "error_shading"})
    EXPECT_TRUE(j.contains(k)) << k;
  // The shading-only error (the kernels' float positions) is the fp32 arithmetic's alone.
  EXPECT_LE(j["error_shading"]["max_rel_peak"].get<double>(), 2e-5);
  EXPECT_GT(doc["runs"][0]["devices"][0]["calibration"]["copy_bandwidth_gbs"].get<double>(), 0.0);
  const auto& s = doc["summaries"][0];
  EXPECT_EQ(s["frames"], 2);
  EXPECT_LE(s["total_ms"]["min"].get<double>(), s["total_ms"]["median"].get<double>());
  EXPECT_LE(s["total_ms"]["median"].get<double>(), s["total_ms"]["max"].get<double>());
  EXPECT_EQ(csvRows(dir + "/summary.csv"), 2u);

  // Without --resume or --overwrite the existing output is not touched.
  expectOneLineError([&] { ts::runBench(o); }, {"--resume"});

  // Resume: nothing left to do; the files keep one row per configuration x frame.
  o.resume = true;
  o.calibrate = false;
  r = ts::runBench(o);
  EXPECT_EQ(r.measuredRows, 0u);
  EXPECT_EQ(r.skippedRows, 4u);
  EXPECT_EQ(csvRows(dir + "/bench.csv"), 4u);

  // Resume with one more frame: only the two new rows run.
  o.frames.text = "0:60:20";
  o.error = false;
  r = ts::runBench(o);
  EXPECT_EQ(r.measuredRows, 2u);
  EXPECT_EQ(r.skippedRows, 4u);
  EXPECT_EQ(csvRows(dir + "/bench.csv"), 6u);
  doc = nlohmann::json::parse(std::ifstream(dir + "/bench.json"));
  EXPECT_EQ(doc["rows"].size(), 6u);
  EXPECT_EQ(doc["runs"].size(), 3u);
  EXPECT_EQ(doc["summaries"][0]["frames"], 3);
  fs::remove_all(dir);
}

TEST(BenchRun, ShardsTogetherMakeTheWholeSweep) {
  std::string dir = tempDir("shards");
  std::set<std::pair<std::string, std::string>> all;
  size_t total = 0;
  for (int k = 0; k < 2; ++k) {
    ts::BenchOptions o = tinyOptions(dir + "/s" + std::to_string(k));
    o.sweep.set("gbuffer", {"fp32,fp16"});
    o.frames.text = "0:1";
    o.warmup = 0;
    o.calibrate = false;
    o.shard = ts::Shard::parse(std::to_string(k) + "/2");
    ts::BenchRunResult r = ts::runBench(o);
    EXPECT_EQ(r.configurations, 4u);
    EXPECT_EQ(r.selected, 2u);
    std::vector<std::map<std::string, std::string>> rows;
    total += csvRows(o.outDir + "/bench.csv", nullptr, &rows);
    for (auto& row : rows) all.insert({row["config_id"], row["frame"]});
  }
  EXPECT_EQ(total, 4u);
  EXPECT_EQ(all.size(), 4u);
  fs::remove_all(dir);
}

// ---- --resume keeps only rows it can use (issue #16 item 7) -----------------------------------

std::vector<std::string> fileLines(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::vector<std::string> out;
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

void writeLines(const std::string& path, const std::vector<std::string>& lines) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  for (const auto& l : lines) out << l << "\n";
}

// Replaces field `column` of a CSV line written by the runner (no quoted fields).
std::string withField(const std::string& line, const std::string& column, const std::string& value) {
  auto cols = ts::benchCsvColumns();
  std::vector<std::string> fields;
  EXPECT_TRUE(ts::parseCsvRecord(line, fields)) << line;
  size_t i = size_t(std::find(cols.begin(), cols.end(), column) - cols.begin());
  EXPECT_LT(i, fields.size()) << column;
  if (i < fields.size()) fields[i] = value;
  return ts::csvLine(fields);
}

// One finished run (2 configurations x 2 frames), copied for each case of junk.
class BenchResume : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    ts::BenchOptions o = tinyOptions(baseDir());
    o.calibrate = false;
    o.warmup = 0;
    ts::BenchRunResult r = ts::runBench(o);
    ASSERT_TRUE(r.failures.empty());
    ASSERT_EQ(r.measuredRows, 4u);
  }
  static void TearDownTestSuite() { fs::remove_all(baseDir()); }
  static const std::string& baseDir() {
    static const std::string dir = tempDir("resume_base");
    return dir;
  }
  ts::BenchOptions resumeOptions(const std::string& name) {
    std::string dir = tempDir("resume_" + name);
    fs::remove_all(dir);
    fs::copy(baseDir(), dir, fs::copy_options::recursive);
    ts::BenchOptions o = tinyOptions(dir);
    o.calibrate = false;
    o.warmup = 0;
    o.resume = true;
    return o;
  }
  std::vector<std::string> lines(const ts::BenchOptions& o) { return fileLines(o.outDir + "/bench.csv"); }

  // Resumes; returns stderr. Then every line of bench.csv parses with every column, and
  // bench.json and summary.csv hold what bench.csv holds.
  std::string resume(const ts::BenchOptions& o, size_t measured, size_t rowsAfter) {
    ::testing::internal::CaptureStderr();
    ts::BenchRunResult r = ts::runBench(o);
    std::string err = ::testing::internal::GetCapturedStderr();
    EXPECT_TRUE(r.failures.empty());
    EXPECT_EQ(r.measuredRows, measured) << err;
    auto after = lines(o);
    EXPECT_EQ(after.size(), rowsAfter + 1) << err;
    for (size_t i = 1; i < after.size(); ++i) {
      std::vector<std::string> f;
      EXPECT_TRUE(ts::parseCsvRecord(after[i], f)) << after[i];
      EXPECT_EQ(f.size(), ts::benchCsvColumns().size()) << after[i].substr(0, 200);
    }
    nlohmann::json doc = nlohmann::json::parse(std::ifstream(o.outDir + "/bench.json"));
    EXPECT_EQ(doc["rows"].size(), rowsAfter);
    size_t frames = 0;
    for (const auto& s : doc["summaries"]) frames += s["frames"].get<size_t>();
    EXPECT_EQ(frames, rowsAfter);
    fs::remove_all(o.outDir);
    return err;
  }
};

// Exactly one warning line, naming the count and the reason; never the row itself.
void expectDropped(const std::string& err, size_t rows, const std::string& reason) {
  std::string lead = "tileshade: warning: bench --resume: dropped " + std::to_string(rows) + " row(s) of ";
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err.substr(0, 500);
  EXPECT_EQ(err.rfind(lead, 0), 0u) << err.substr(0, 500);
  EXPECT_NE(err.find(reason), std::string::npos) << err.substr(0, 500);
  EXPECT_LT(err.size(), 400u);
}

TEST_F(BenchResume, NothingDroppedFromItsOwnOutput) {
  ts::BenchOptions o = resumeOptions("own");
  EXPECT_EQ(resume(o, 0, 4), "");
}

TEST_F(BenchResume, TruncatedRowIsDroppedAndMeasuredAgain) {
  ts::BenchOptions o = resumeOptions("truncated");
  auto l = lines(o);
  l.back() = l.back().substr(0, l.back().size() / 2);  // a run killed mid-write
  writeLines(o.outDir + "/bench.csv", l);
  expectDropped(resume(o, 1, 4), 1, "fewer fields than the header");
}

TEST_F(BenchResume, UnterminatedQuoteIsDropped) {
  ts::BenchOptions o = resumeOptions("quote");
  auto l = lines(o);
  ASSERT_EQ(l.back().find('"'), std::string::npos);
  l.back() = "\"" + l.back();  // a quote that never closes
  writeLines(o.outDir + "/bench.csv", l);
  expectDropped(resume(o, 1, 4), 1, "a quote that is not closed");
}

TEST_F(BenchResume, MegabyteJunkLineIsDroppedNotEchoed) {
  ts::BenchOptions o = resumeOptions("junk");
  auto l = lines(o);
  l.push_back(std::string(1 << 20, 'x'));
  l.push_back(std::string(1 << 20, ','));
  writeLines(o.outDir + "/bench.csv", l);
  std::string err = resume(o, 0, 4);
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 2) << err.substr(0, 500);
  EXPECT_NE(err.find("dropped 1 row(s) of " + o.outDir + "/bench.csv: fewer fields"), std::string::npos) << err.substr(0, 500);
  EXPECT_NE(err.find("dropped 1 row(s) of " + o.outDir + "/bench.csv: more fields"), std::string::npos) << err.substr(0, 500);
  EXPECT_LT(err.size(), 600u);
}

TEST_F(BenchResume, ValuesNotOfTheirColumnsTypeAreDropped) {
  ts::BenchOptions o = resumeOptions("types");
  auto l = lines(o);
  l[1] = withField(l[1], "total_ms", "fast");
  l[2] = withField(l[2], "wall_ms", "-3");
  l[3] = withField(l[3], "kernels", "shade");
  l[4] = withField(l[4], "lights", "");
  writeLines(o.outDir + "/bench.csv", l);
  expectDropped(resume(o, 4, 4), 4, "not of its column's type");
}

TEST_F(BenchResume, EditedValuesThatDisagreeWithBenchJsonAreDropped) {
  ts::BenchOptions o = resumeOptions("edited");
  auto l = lines(o);
  l[1] = withField(l[1], "total_ms", "0.000123");  // plausible, well-typed, not what was measured
  writeLines(o.outDir + "/bench.csv", l);
  expectDropped(resume(o, 1, 4), 1, "differ from its record in bench.json");
}

TEST_F(BenchResume, RowsOfAnotherSweepAreDropped) {
  ts::BenchOptions o = resumeOptions("sweep");
  o.sweep.set("tile", {"16"});  // the 32x16 rows are another sweep's now
  expectDropped(resume(o, 0, 2), 2, "a configuration this sweep (or shard) does not run");
}

TEST_F(BenchResume, RowsOfAnotherShardAreDropped) {
  ts::BenchOptions o = resumeOptions("shard");
  o.shard = ts::Shard::parse("1/2");
  expectDropped(resume(o, 0, 2), 2, "does not run");
}

TEST_F(BenchResume, DimensionsThatContradictTheConfigIdAreDropped) {
  ts::BenchOptions o = resumeOptions("dims");
  auto l = lines(o);
  // The row keeps its config_id and claims the other tile size.
  std::string other = withField(l[1], "tile", "16x16") == l[1] ? "32x16" : "16x16";
  l[1] = withField(l[1], "tile", other);
  writeLines(o.outDir + "/bench.csv", l);
  expectDropped(resume(o, 1, 4), 1, "do not match the row's config_id");
}

TEST_F(BenchResume, RowsOfAnotherDeviceAreDropped) {
  ts::BenchOptions o = resumeOptions("device");
  auto l = lines(o);
  l[1] = withField(l[1], "device_name", "Some Other / GPU");
  writeLines(o.outDir + "/bench.csv", l);
  expectDropped(resume(o, 1, 4), 1, "another device");
}

TEST_F(BenchResume, FramesNotTimedNowAreDropped) {
  ts::BenchOptions o = resumeOptions("frames");
  o.frames.text = "0:1";  // frame 0 only
  expectDropped(resume(o, 0, 2), 2, "a frame that --frames does not time");
}

TEST_F(BenchResume, OtherWarmupOrRepeatIsDropped) {
  ts::BenchOptions o = resumeOptions("repeat");
  o.frames.text = "0:1";
  o.repeat = 2;
  std::string err = resume(o, 2, 2);
  EXPECT_NE(err.find("dropped 2 row(s)"), std::string::npos) << err;
  EXPECT_NE(err.find("another --warmup or --repeat"), std::string::npos) << err;
}

TEST_F(BenchResume, RowsWithoutErrorColumnsAreMeasuredAgainWithError) {
  ts::BenchOptions o = resumeOptions("error");
  o.error = true;
  o.errorFrames = "1";  // frame 0
  expectDropped(resume(o, 2, 4), 2, "no error columns where --error wants them");
}

TEST_F(BenchResume, RepeatedRowsKeepTheLast) {
  ts::BenchOptions o = resumeOptions("repeated");
  auto l = lines(o);
  l.push_back(l[1]);
  l.push_back(ts::csvLine(ts::benchCsvColumns()));  // `cat` of two files: skipped, not counted
  writeLines(o.outDir + "/bench.csv", l);
  expectDropped(resume(o, 0, 4), 1, "measured again later");
}

TEST_F(BenchResume, BrokenBenchJsonIsSaidAndTheRowsComeFromTheCsv) {
  ts::BenchOptions o = resumeOptions("json");
  std::ofstream(o.outDir + "/bench.json", std::ios::trunc) << "{\"rows\": [";
  std::string err = resume(o, 0, 4);
  EXPECT_EQ(err, "tileshade: warning: bench --resume: " + o.outDir +
                     "/bench.json is not a bench.json; its rows come back from bench.csv, its "
                     "earlier runs are lost\n");
}

TEST_F(BenchResume, RowsRebuiltFromTheCsvAgreeWithTheirRecordNextTime) {
  ts::BenchOptions o = resumeOptions("rebuilt");
  o.error = true;
  o.errorFrames = "1";
  fs::remove(o.outDir + "/bench.csv");
  ts::runBench(o);  // with error columns, so that they round-trip too
  fs::remove(o.outDir + "/bench.json");  // lost: the rows come back from bench.csv
  o.printTable = false;
  ::testing::internal::CaptureStderr();
  EXPECT_EQ(ts::runBench(o).measuredRows, 0u);
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
  EXPECT_EQ(resume(o, 0, 4), "");  // their rebuilt records agree with bench.csv
}

TEST_F(BenchResume, OtherColumnsAreOneLineError) {
  ts::BenchOptions o = resumeOptions("header");
  auto l = lines(o);
  l[0] += ",extra";
  writeLines(o.outDir + "/bench.csv", l);
  expectOneLineError([&] { ts::runBench(o); }, {"other columns"});
  EXPECT_EQ(lines(o), l);  // not touched
  fs::remove_all(o.outDir);
}

TEST(BenchCsv, StrictRecordsRefuseStrayQuotes) {
  std::vector<std::string> f;
  EXPECT_TRUE(ts::parseCsvRecord("a,\"b,\"\"c\"\"\",", f));
  EXPECT_EQ(f, (std::vector<std::string>{"a", "b,\"c\"", ""}));
  for (const char* bad : {"\"a", "a\"b\",c", "\"a\"b,c", "a,\"b"})
    EXPECT_FALSE(ts::parseCsvRecord(bad, f)) << bad;
}

TEST(BenchRun, UnknownDeviceWritesNothing) {
  std::string dir = tempDir("nodevice");
  ts::BenchOptions o = tinyOptions(dir + "/out");
  o.sweep.set("device", {"cpu,no-such-device"});
  expectOneLineError([&] { ts::runBench(o); }, {"no-such-device"});
  EXPECT_FALSE(fs::exists(dir + "/out"));
  fs::remove_all(dir);
}

TEST(BenchShard, LimitIsTheOneStated) {
  EXPECT_EQ(ts::Shard::parse("999999/1000000").count, 1000000);
  expectOneLineError([] { ts::Shard::parse("0/1000001"); }, {"n <= 1000000", "'0/1000001'"});
  expectOneLineError([] { ts::Shard::parse("0/99999999999999999999"); }, {"n <= 1000000"});
  expectOneLineError([] { ts::Shard::parse("3/3"); }, {"0 <= k < n"});
}

// bench/plot.py on a small generated CSV, when a python3 with matplotlib is available.
TEST(BenchPlot, PlotScriptRunsOnASmallCsv) {
  std::string python;
  for (const char* candidate : {"python3", "/usr/bin/python3"}) {
    std::string probe = std::string(candidate) + " -c 'import matplotlib' >/dev/null 2>&1";
    if (std::system(probe.c_str()) == 0) {
      python = candidate;
      break;
    }
  }
  if (python.empty()) GTEST_SKIP() << "no python3 with matplotlib";
  std::string script = ts::test::sourceDir() + "/bench/plot.py";
  ASSERT_TRUE(fs::exists(script)) << script;

  std::string dir = tempDir("plot");
  std::ofstream csv(dir + "/bench.csv");
  csv << ts::csvLine(ts::benchCsvColumns()) << "\n";
  auto cols = ts::benchCsvColumns();
  for (const char* technique : {"tiled", "deferred"})
    for (const char* tile : {"16x16", "32x16"})
      for (int frame : {0, 10, 20}) {
        std::map<std::string, std::string> v = {
            {"config_id", std::string(technique) + tile}, {"device", "cpu"},
            {"scene", "builtin:street"}, {"light_set", "many"}, {"light_count", "-1"},
            {"light_range", "0"}, {"light_threshold", "0"}, {"seed", "1"},
            {"resolution", "64x36"}, {"gbuffer", "fp32"}, {"technique", technique},
            {"tile", tile}, {"culling", "rect"}, {"math", "precise"}, {"slices", "16"},
            {"device_name", "Test / cpu"}, {"frame", std::to_string(frame)}, {"lights", "924"},
            {"total_ms", std::to_string(1.0 + frame * 0.1 + (technique[0] == 'd' ? 2 : 0))},
            {"kernels", "bin=0.5;shade=" + std::to_string(0.5 + frame * 0.1)},
            {"wall_ms", "3"}, {"compile_ms", "100"}, {"raster_ms", "2"},
            {"lighting_computations", std::to_string(1000 + frame)}, {"evaluations", "900"},
            {"limit_ms", "0.1"}, {"limit_pct", "10"}, {"flops_basis", "evaluations"}};
        std::vector<std::string> fields;
        for (const auto& c : cols) fields.push_back(v.count(c) ? v[c] : "");
        csv << ts::csvLine(fields) << "\n";
      }
  csv.close();
  std::string cmd = python + " '" + script + "' '" + dir + "/bench.csv' --out '" + dir +
                    "/plots' >'" + dir + "/log.txt' 2>&1";
  int rc = std::system(cmd.c_str());
  std::ifstream logIn(dir + "/log.txt");
  std::string log((std::istreambuf_iterator<char>(logIn)), std::istreambuf_iterator<char>());
  ASSERT_EQ(rc, 0) << log;
  EXPECT_TRUE(fs::exists(dir + "/plots/report.md")) << log;
  size_t png = 0;
  for (const auto& e : fs::directory_iterator(dir + "/plots")) png += e.path().extension() == ".png";
  EXPECT_GE(png, 2u) << log;
  fs::remove_all(dir);
}

// bench/plot.py on input it cannot use: one line "plot.py: error: ...", exit status 1, no
// traceback. The input is read before matplotlib is imported, so any python3 will do.
TEST(BenchPlot, BadInputIsOneLineError) {
  if (std::system("python3 -c '' >/dev/null 2>&1") != 0) GTEST_SKIP() << "no python3";
  std::string script = ts::test::sourceDir() + "/bench/plot.py";
  std::string dir = tempDir("plot_bad");
  auto cols = ts::benchCsvColumns();
  std::vector<std::string> good(cols.size(), "1");
  auto set = [&](std::vector<std::string> f, const std::string& column, const std::string& v) {
    f[size_t(std::find(cols.begin(), cols.end(), column) - cols.begin())] = v;
    return ts::csvLine(f);
  };
  std::vector<std::string> noFrame;
  for (const auto& c : cols)
    if (c != "frame") noFrame.push_back(c);
  const std::string header = ts::csvLine(cols);
  const std::vector<std::tuple<std::string, std::string, std::string>> cases = {
      {"missing.csv", "", "no such file"},
      {"empty.csv", "\n", "empty"},
      {"nocolumn.csv", ts::csvLine(noFrame) + "\n", "no column frame"},
      {"text.csv", header + "\n" + set(good, "total_ms", "fast") + "\n", "total_ms is not a number: 'fast'"},
      {"kernels.csv", header + "\n" + set(good, "kernels", "shade=x") + "\n", "kernel time is not a number"},
      {"truncated.csv", header + "\n1,2,3\n", "line 2: 3 field(s)"},
      {"noid.csv", header + "\n" + set(good, "config_id", "") + "\n", "no config_id"},
      {"junk.csv", header + "\n" + std::string(1 << 20, 'x') + "\n", "junk.csv"},
      {"bad.json", "{\"rows\": [", "not JSON"},
      {"rows.json", "{\"rows\": 5}", "no \"rows\" list"},
      {"row.json", "{\"rows\": [{\"config\": {\"technique\": \"tiled\", \"tile\": \"16x16\"}, \"config_id\": \"a\", \"frame\": 0, \"total_ms\": \"x\"}]}",
       "total_ms is not a number"},
  };
  for (const auto& [name, text, needle] : cases) {
    std::string path = dir + "/" + name;
    if (name != "missing.csv") std::ofstream(path, std::ios::binary) << text;
    std::string cmd = "python3 '" + script + "' '" + path + "' --out '" + dir + "/plots' >'" + dir +
                      "/log.txt' 2>&1";
    int rc = std::system(cmd.c_str());
    std::ifstream logIn(dir + "/log.txt");
    std::string log((std::istreambuf_iterator<char>(logIn)), std::istreambuf_iterator<char>());
    EXPECT_TRUE(WIFEXITED(rc) && WEXITSTATUS(rc) == 1) << name << ": " << log;
    EXPECT_EQ(log.rfind("plot.py: error: ", 0), 0u) << name << ": " << log;
    EXPECT_EQ(std::count(log.begin(), log.end(), '\n'), 1) << name << ": " << log;
    EXPECT_NE(log.find(needle), std::string::npos) << name << ": " << log;
    EXPECT_LT(log.size(), 300u) << name;
  }
  EXPECT_FALSE(fs::exists(dir + "/plots"));
  fs::remove_all(dir);
}

}  // namespace
