// `tileshade bench` on the device: calibration, a tiny end-to-end run (64x36, two frames) with
// resume and shards; plus a smoke test of bench/plot.py. (The sweep, shards and statistics on
// their own: bench_config_test.cpp, bench_stats_test.cpp.)
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

#include "bench/bench_columns.h"
#include "bench/bench_config.h"
#include "bench/bench_run.h"
#include "bench/bench_stats.h"
#include "bench/calibrate.h"
#include "bench_test_support.h"
#include "scene/mesh_builder.h"
#include "scene/scene_loader.h"
#include "techniques/technique.h"
#include "test_scenes.h"
#include "test_support.h"
#include "util/error.h"

namespace fs = std::filesystem;

namespace {

using ts::BenchSweep;
using ts::test::expectOneLineError;
using ts::test::tempDir;

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

// Paths of a row's values (arrays are one value), for BenchRun's check that every value of a
// measured row is in the table or is said to be bench.json's alone.
void leafPaths(const nlohmann::json& j, const std::string& path, std::set<std::string>& out) {
  if (!j.is_object()) {
    out.insert(path);
    return;
  }
  for (const auto& [k, v] : j.items()) leafPaths(v, path + "/" + k, out);
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
  // Two to five rounds of three launches each; the rate is the best round's.
  size_t rounds = c.bandwidth.rounds.size();
  EXPECT_GE(rounds, 2u);
  EXPECT_LE(rounds, 5u);
  EXPECT_EQ(c.peak.rounds.size(), rounds);
  EXPECT_EQ(c.copyMs.size(), 3 * rounds);
  EXPECT_EQ(c.fmaMs.size(), 3 * rounds);
  EXPECT_EQ(c.bandwidthGBs, c.bandwidth.best);
  EXPECT_EQ(c.peakGflops, c.peak.best);
  EXPECT_GE(c.peak.best, c.peak.median);
  EXPECT_GE(c.peak.median, c.peak.min);
  // Stopping early means the best two agreed.
  if (rounds < 5) {
    EXPECT_TRUE(c.settled);
  }
  EXPECT_EQ(c.toJson()["peak_gflops_spread"]["rounds"].size(), rounds);
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
  for (const char* col : {"config_id",   "technique",
                          "tile",        "gbuffer",
                          "resolution",  "frame",
                          "total_ms",    "kernels",
                          "wall_ms",     "compile_ms",
                          "raster_ms",   "lighting_computations",
                          "evaluations", "gbuffer_bytes_read",
                          "limit_ms",    "limit_pct",
                          "flops_basis", "err_rmse",
                          "err_psnr_db", "err_shading_max_rel_peak"})
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
  for (const char* k :
       {"technique", "kernels", "total_ms", "lighting_computations", "evaluations",
        "gbuffer_bytes_read", "config", "frame", "wall_ms", "limit", "error", "error_shading"})
    EXPECT_TRUE(j.contains(k)) << k;
  // The shading-only error (the kernels' float positions) is the fp32 arithmetic's alone.
  EXPECT_LE(j["error_shading"]["max_rel_peak"].get<double>(), 2e-5);
  const auto& calibration = doc["runs"][0]["devices"][0]["calibration"];
  EXPECT_GT(calibration["copy_bandwidth_gbs"].get<double>(), 0.0);
  // The rate is the best round's, and the spread behind it is recorded.
  EXPECT_EQ(calibration["peak_gflops"], calibration["peak_gflops_spread"]["best"]);
  EXPECT_GE(calibration["rounds"].get<int>(), 2);
  // The row carries the spread: the % from the slowest round's rates is never below the best's.
  EXPECT_GE(j["limit"]["limit_pct_slowest_round"].get<double>(),
            j["limit"]["limit_pct"].get<double>());
  // Every value of a measured row has a bench.csv column, or is bench.json's alone (listed
  // here): a value added to the row without a column in bench_columns.cpp fails here.
  std::set<std::string> columnPaths = {"/technique"};  // the technique dimension's value again
  for (const auto& c : ts::benchColumns()) columnPaths.insert(c.path);
  for (const char* k :
       {"tolerance", "pixels_above_tolerance", "nonfinite_pixels", "reference_peak"})
    columnPaths.insert(std::string("/error/") + k);
  for (const auto& r : doc["rows"]) {
    std::set<std::string> paths;
    leafPaths(r, "", paths);
    for (const auto& p : paths) {
      bool jsonOnly = p.rfind("/error_vs_stored/", 0) == 0 || p.rfind("/error_shading/", 0) == 0;
      EXPECT_TRUE(jsonOnly || columnPaths.count(p)) << p << " has no bench.csv column";
    }
  }
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

// With every light casting, bench draws the maps each frame (shadow_ms, shadow_bytes) and the
// kernels and the references shade with the same maps: the error stays fp32's. Without casters
// the columns say that nothing was drawn.
// The shadow_storage and shadow_budget dimensions: deferred's per-light rows count the maps it
// drew itself (shadow_ms) and keep only the largest light's maps resident (shadow_bytes), less
// than the atlas, with the same error; the atlas rows fit their budget; tiled's per-light points
// are left out (expandSweep's note).
TEST(BenchRun, PerLightShadowStorageKeepsLessResident) {
  std::string dir = tempDir("shadow_storage");
  ts::BenchOptions o = tinyOptions(dir);
  o.sweep.set("scene", {"builtin:atrium"});
  o.sweep.set("tile", {"16"});
  o.sweep.set("technique", {"tiled,deferred"});
  o.sweep.set("shadows", {"4"});
  o.sweep.set("shadow_map_size", {"64"});
  o.sweep.set("shadow_budget", {"64,0.25"});
  o.sweep.set("shadow_storage", {"atlas,per-light"});
  o.frames.text = "1";
  o.error = true;
  o.calibrate = false;
  ts::BenchRunResult r = ts::runBench(o);
  EXPECT_TRUE(r.failures.empty());
  ASSERT_EQ(r.measuredRows, 6u);
  std::vector<std::map<std::string, std::string>> rows;
  ASSERT_EQ(csvRows(dir + "/bench.csv", nullptr, &rows), 6u);
  size_t perLight = 0;
  for (auto& row : rows) {
    const std::string what =
        row["technique"] + " " + row["shadow_storage"] + " " + row["shadow_budget"];
    EXPECT_LE(std::stod(row["err_max_rel_peak"]), 1e-4) << what;
    const uint64_t resident = std::stoull(row["shadow_bytes"]);
    const uint64_t written = std::stoull(row["shadow_bytes_written"]);
    const uint64_t budget = row["shadow_budget"] == "64" ? 64u << 20 : 1u << 18;
    if (row["shadow_storage"] == "atlas") {
      EXPECT_EQ(resident, written) << what;
      EXPECT_LE(resident, budget) << what;
      EXPECT_GE(resident, 6u * 16u * 16u * 4u) << what;
      continue;
    }
    ++perLight;
    EXPECT_EQ(row["technique"], "deferred");
    EXPECT_GT(std::stod(row["shadow_ms"]), 0.0) << what;
    // One point light's six faces at most (64^2, or smaller within the budget).
    EXPECT_LE(resident, 6u * 64u * 64u * 4u) << what;
    EXPECT_GT(resident, 0u) << what;
    EXPECT_GE(written, resident) << what;
  }
  EXPECT_EQ(perLight, 2u);
}

TEST(BenchRun, ShadowsAllDrawsTheMapsAndShadesWithThem) {
  std::string dir = tempDir("shadows");
  ts::BenchOptions o = tinyOptions(dir);
  o.sweep.set("scene", {"builtin:atrium"});
  o.sweep.set("tile", {"16"});
  o.sweep.set("technique", {"tiled,deferred"});
  o.sweep.set("shadows", {"none,all"});
  o.sweep.set("shadow_map_size", {"32"});
  o.sweep.set("shadow_filter", {"pcf3"});
  o.frames.text = "1";  // frame 0
  o.error = true;
  o.calibrate = false;
  ts::BenchRunResult r = ts::runBench(o);
  EXPECT_TRUE(r.failures.empty());
  ASSERT_EQ(r.measuredRows, 4u);
  std::vector<std::map<std::string, std::string>> rows;
  ASSERT_EQ(csvRows(dir + "/bench.csv", nullptr, &rows), 4u);
  std::map<std::string, std::string> bytesOf;
  for (auto& row : rows) {
    const bool casting = row["shadows"] == "all";
    EXPECT_EQ(row["shadow_map_size"], "32");
    EXPECT_EQ(row["shadow_filter"], "pcf3");
    EXPECT_EQ(row["features_used"].find("shadows") != std::string::npos, casting)
        << row["features_used"];
    const double ms = std::stod(row["shadow_ms"]);
    const uint64_t bytes = std::stoull(row["shadow_bytes"]);
    if (casting) {
      EXPECT_GT(ms, 0.0);
      // Every light's six 32x32 faces, in floats, fit in the atlas.
      EXPECT_GE(bytes, std::stoull(row["lights"]) * 6u * 32u * 32u * 4u);
    } else {
      EXPECT_EQ(ms, 0.0);
      EXPECT_EQ(bytes, 0u);
    }
    // Both techniques shade one frame: the same atlas.
    auto [it, inserted] = bytesOf.emplace(row["shadows"], row["shadow_bytes"]);
    if (!inserted) {
      EXPECT_EQ(it->second, row["shadow_bytes"]);
    }
    EXPECT_LE(std::stod(row["err_max_rel_peak"]), 1e-4) << row["technique"] << row["shadows"];
  }
  fs::remove_all(dir);
}

// --shadow-error (issue #18): a box floating over a floor under a shadow-casting sun. The maps
// and exact visibility agree but at the shadow's outline: at a tiny map (16: the sun's is 64^2)
// a few percent of the (pixel, light) pairs are wrong, more than at a fine one (512: 2048^2),
// fewer than 10% at either; the image's median pixel (the floor and box away from the
// outline) has no error against the one shaded with exact visibility. The columns are in
// bench.csv; a frame without a caster gets a note instead.
TEST(BenchRun, ShadowErrorColumnsMeasureTheMapsAgainstExactVisibility) {
  std::string dir = tempDir("shadow_error");
  ts::Scene scene;
  scene.name = "floor-and-box";
  scene.ambient = glm::vec3(0.0f);
  ts::MeshBuilder b(scene);
  const uint32_t m = b.addMaterial(ts::Material{});
  ts::test::addFloor(b, 10.0f, m);
  b.box({-1.0f, 1.0f, -1.0f}, {1.0f, 2.0f, 1.0f}, m, true);
  scene.cameraPath.push_back(ts::SceneCamera::lookAt({0.0, 6.0, 9.0}, {0.0, 0.0, 0.0},
                                                     {0.0, 1.0, 0.0}, 1.2f, 0.1f, 100.0f));
  ts::SceneLight sun = ts::SceneLight::directional({-0.3f, -1.0f, -0.4f}, glm::vec3(1.0f));
  sun.castsShadow = true;
  scene.lights.push_back(sun);
  fs::create_directories(dir);
  const std::string path = dir + "/floor_box.gltf";
  ts::exportGltf(scene, path);
  ts::BenchOptions o = tinyOptions(dir + "/out");
  o.sweep.set("scene", {path});
  o.sweep.set("resolution", {"96x54"});
  o.sweep.set("tile", {"16"});
  o.sweep.set("shadows", {"default,none"});
  o.sweep.set("shadow_map_size", {"16,512"});
  o.frames.text = "1";
  o.shadowError = true;
  o.calibrate = false;
  ts::BenchRunResult r = ts::runBench(o);
  EXPECT_TRUE(r.failures.empty());
  std::vector<std::map<std::string, std::string>> rows;
  ASSERT_EQ(csvRows(dir + "/out/bench.csv", nullptr, &rows), 4u);
  std::map<std::string, double> wrong, errMax;
  for (auto& row : rows) {
    SCOPED_TRACE(row["shadows"] + " " + row["shadow_map_size"]);
    if (row["shadows"] == "none") {
      EXPECT_EQ(row["shadow_wrong_pct"], "");
      EXPECT_NE(row["notes"].find("--shadow-error: no light casts a shadow"), std::string::npos);
      continue;
    }
    const double pct = std::stod(row["shadow_wrong_pct"]);
    wrong[row["shadow_map_size"]] = pct;
    errMax[row["shadow_map_size"]] = std::stod(row["shadow_err_max_rel_peak"]);
    EXPECT_LT(pct, 10.0);
    EXPECT_GE(std::stod(row["shadow_err_max_rel_peak"]), std::stod(row["shadow_err_p99"]));
    EXPECT_GE(std::stod(row["shadow_err_rmse"]), 0.0);
    EXPECT_GT(std::stod(row["shadow_exact_ms"]), 0.0);
  }
  ASSERT_EQ(wrong.size(), 2u);
  EXPECT_GT(wrong["16"], 0.0);
  EXPECT_GT(wrong["16"], wrong["512"]);
  EXPECT_GT(errMax["16"], 1e-3);  // the tiny map's outline
  const nlohmann::json doc = nlohmann::json::parse(std::ifstream(dir + "/out/bench.json"));
  for (const auto& row : doc["rows"])
    if (row.contains("shadow_error")) {
      EXPECT_LT(row["shadow_error"]["err_p50"].get<double>(), 1e-6) << row.dump();
      EXPECT_GT(row["shadow_error"]["pairs"].get<uint64_t>(), 1000u);
    }
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

// Without the calibration there is no device limit: the summary says so (empty, "-") instead of a
// median of 0 % of the limit.
TEST(BenchRun, UncalibratedSummaryHasNoLimitFigures) {
  std::string dir = tempDir("uncalibrated");
  ts::BenchOptions o = tinyOptions(dir);
  o.frames.text = "1";  // frame 0
  o.warmup = 0;
  o.calibrate = false;
  ts::BenchRunResult r = ts::runBench(o);
  EXPECT_TRUE(r.failures.empty());
  std::vector<std::map<std::string, std::string>> rows;
  ASSERT_GT(csvRows(dir + "/summary.csv", nullptr, &rows), 0u);
  for (auto& row : rows) {
    EXPECT_EQ(row["limit_pct_median"], "");
    EXPECT_EQ(row["limit_ms_median"], "");
    EXPECT_GT(std::stod(row["total_ms_median"]), 0.0);
  }
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
std::string withField(const std::string& line, const std::string& column,
                      const std::string& value) {
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
  std::vector<std::string> lines(const ts::BenchOptions& o) {
    return fileLines(o.outDir + "/bench.csv");
  }

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
  std::string lead =
      "tileshade: warning: bench --resume: dropped " + std::to_string(rows) + " row(s) of ";
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
  EXPECT_NE(err.find("dropped 1 row(s) of " + o.outDir + "/bench.csv: fewer fields"),
            std::string::npos)
      << err.substr(0, 500);
  EXPECT_NE(err.find("dropped 1 row(s) of " + o.outDir + "/bench.csv: more fields"),
            std::string::npos)
      << err.substr(0, 500);
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

TEST_F(BenchResume, RowsWithoutShadowErrorAreMeasuredAgainWithIt) {
  ts::BenchOptions o = resumeOptions("shadow_error");
  o.shadowError = true;
  o.errorFrames = "1";  // frame 0
  expectDropped(resume(o, 2, 4), 2, "no shadow-error columns where --shadow-error wants them");
}

TEST_F(BenchResume, RowsWithTheNoShadowNoteAreKept) {
  // The tiny scene casts no shadow: --shadow-error rows carry the note instead of the columns.
  ts::BenchOptions o = resumeOptions("shadow_note");
  o.shadowError = true;
  o.errorFrames = "1";
  o.resume = false;
  o.overwrite = true;
  o.printTable = false;
  ASSERT_EQ(ts::runBench(o).measuredRows, 4u);
  o.resume = true;
  o.overwrite = false;
  EXPECT_EQ(resume(o, 0, 4), "");
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
  ts::runBench(o);                       // with error columns, so that they round-trip too
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

TEST(BenchRun, UnknownDeviceWritesNothing) {
  std::string dir = tempDir("nodevice");
  ts::BenchOptions o = tinyOptions(dir + "/out");
  o.sweep.set("device", {"cpu,no-such-device"});
  expectOneLineError([&] { ts::runBench(o); }, {"no-such-device"});
  EXPECT_FALSE(fs::exists(dir + "/out"));
  fs::remove_all(dir);
}

// A python3 with matplotlib ("" when there is none).
static std::string plotPython() {
  for (const char* candidate : {"python3", "/usr/bin/python3"}) {
    std::string probe = std::string(candidate) + " -c 'import matplotlib' >/dev/null 2>&1";
    if (std::system(probe.c_str()) == 0) return candidate;
  }
  return "";
}

// Runs `script` (bench/plot.py) on DIR/bench.csv into DIR/plots, with `options`; `log` gets its
// output.
static int runPlot(const std::string& python, const std::string& script, const std::string& dir,
                   std::string& log, const std::string& options = "") {
  std::string cmd = python + " '" + script + "' '" + dir + "/bench.csv' --out '" + dir +
                    "/plots' " + options + " >'" + dir + "/log.txt' 2>&1";
  int rc = std::system(cmd.c_str());
  std::ifstream logIn(dir + "/log.txt");
  log.assign((std::istreambuf_iterator<char>(logIn)), std::istreambuf_iterator<char>());
  return rc;
}

// bench/plot.py on a small generated CSV, when a python3 with matplotlib is available.
TEST(BenchPlot, PlotScriptRunsOnASmallCsv) {
  std::string python = plotPython();
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
            {"config_id", std::string(technique) + tile},
            {"device", "cpu"},
            {"scene", "builtin:street"},
            {"light_set", "many"},
            {"light_count", "-1"},
            {"light_range", "0"},
            {"light_threshold", "0"},
            {"seed", "1"},
            {"resolution", "64x36"},
            {"gbuffer", "fp32"},
            {"technique", technique},
            {"tile", tile},
            {"culling", "rect"},
            {"math", "precise"},
            {"slices", "16"},
            {"device_name", "Test / cpu"},
            {"frame", std::to_string(frame)},
            {"lights", "924"},
            {"total_ms", std::to_string(1.0 + frame * 0.1 + (technique[0] == 'd' ? 2 : 0))},
            {"kernels", "bin=0.5;shade=" + std::to_string(0.5 + frame * 0.1)},
            {"wall_ms", "3"},
            {"compile_ms", "100"},
            {"raster_ms", "2"},
            {"lighting_computations", std::to_string(1000 + frame)},
            {"evaluations", "900"},
            {"limit_ms", "0.1"},
            {"limit_pct", "10"},
            {"flops_basis", "evaluations"}};
        std::vector<std::string> fields;
        for (const auto& c : cols) fields.push_back(v.count(c) ? v[c] : "");
        csv << ts::csvLine(fields) << "\n";
      }
  csv.close();
  std::string log;
  int rc = runPlot(python, script, dir, log);
  ASSERT_EQ(rc, 0) << log;
  EXPECT_TRUE(fs::exists(dir + "/plots/report.md")) << log;
  size_t png = 0;
  for (const auto& e : fs::directory_iterator(dir + "/plots"))
    png += e.path().extension() == ".png";
  EXPECT_GE(png, 2u) << log;
  fs::remove_all(dir);
}

// A light-count sweep gets the log-log scaling figure (frame and binning time against lights):
// one per panel, a binning line only for the technique with binning kernels.
TEST(BenchPlot, LightCountSweepGetsTheScalingFigure) {
  std::string python = plotPython();
  if (python.empty()) GTEST_SKIP() << "no python3 with matplotlib";
  std::string script = ts::test::sourceDir() + "/bench/plot.py";
  std::string dir = tempDir("plot-scaling");
  std::ofstream csv(dir + "/bench.csv");
  auto cols = ts::benchCsvColumns();
  csv << ts::csvLine(cols) << "\n";
  for (const char* technique : {"tiled", "brute"})
    for (int lights : {1000, 4000, 16000}) {
      const double bin = 0.001 * lights, shade = 0.002 * lights;
      std::map<std::string, std::string> v = {
          {"config_id", technique + std::to_string(lights)},
          {"device", "cpu"},
          {"scene", "builtin:street"},
          {"light_set", "many"},
          {"light_count", std::to_string(lights)},
          {"light_range", "3"},
          {"resolution", "64x36"},
          {"technique", technique},
          {"tile", "16x16"},
          {"device_name", "Test / cpu"},
          {"frame", "0"},
          {"lights", std::to_string(lights)},
          {"total_ms", std::to_string(technique[0] == 't' ? bin + shade : 2 * shade)},
          {"kernels", technique[0] == 't'
                          ? "bin_count=" + std::to_string(bin) + ";shade=" + std::to_string(shade)
                          : "shade=" + std::to_string(2 * shade)}};
      std::vector<std::string> fields;
      for (const auto& c : cols) fields.push_back(v.count(c) ? v[c] : "");
      csv << ts::csvLine(fields) << "\n";
    }
  csv.close();
  std::string log;
  int rc = runPlot(python, script, dir, log);
  ASSERT_EQ(rc, 0) << log;
  size_t scaling = 0;
  for (const auto& e : fs::directory_iterator(dir + "/plots"))
    scaling +=
        e.path().extension() == ".png" && e.path().filename().string().rfind("scaling_", 0) == 0;
  EXPECT_EQ(scaling, 1u) << log;
  std::ifstream reportIn(dir + "/plots/report.md");
  std::string report((std::istreambuf_iterator<char>(reportIn)), std::istreambuf_iterator<char>());
  EXPECT_NE(report.find("Scaling with the number of lights"), std::string::npos) << report;
  fs::remove_all(dir);
}

// --time-with-geometry: the whole frame, so that forward and deferred compare: total_ms +
// shadow_ms for every technique, + raster_ms (the G-buffer pass) for a G-buffer technique only
// (a forward technique's geometry passes are inside its total_ms).
TEST(BenchPlot, TimeWithGeometryAddsTheGBufferPassToTheGBufferTechniquesOnly) {
  std::string python = plotPython();
  if (python.empty()) GTEST_SKIP() << "no python3 with matplotlib";
  std::string script = ts::test::sourceDir() + "/bench/plot.py";
  std::string dir = tempDir("plot-geometry");
  std::ofstream csv(dir + "/bench.csv");
  auto cols = ts::benchCsvColumns();
  csv << ts::csvLine(cols) << "\n";
  for (const char* technique : {"tiled", "tiled-forward"}) {
    std::map<std::string, std::string> v = {
        {"config_id", technique}, {"device", "cpu"},       {"scene", "builtin:street"},
        {"raster", "gl"},         {"resolution", "64x36"}, {"technique", technique},
        {"tile", "16x16"},        {"device_name", "Test"}, {"frame", "0"},
        {"total_ms", "10.5"},     {"raster_ms", "40.25"},  {"shadow_ms", "2"},
        {"kernels", "shade=10.5"}};
    std::vector<std::string> fields;
    for (const auto& c : cols) fields.push_back(v.count(c) ? v[c] : "");
    csv << ts::csvLine(fields) << "\n";
  }
  csv.close();
  std::string log;
  ASSERT_EQ(runPlot(python, script, dir, log, "--time-with-geometry"), 0) << log;
  std::ifstream reportIn(dir + "/plots/report.md");
  std::string report((std::istreambuf_iterator<char>(reportIn)), std::istreambuf_iterator<char>());
  EXPECT_NE(report.find("| tiled | 16x16 |  | 1 | 52.750 |"), std::string::npos) << report;
  EXPECT_NE(report.find("| tiled-forward | 16x16 |  | 1 | 12.500 |"), std::string::npos) << report;
  fs::remove_all(dir);
}

// plot.py's DRAWS_SCENE is the registry's drawsScene set (what --time-with-geometry adds
// raster_ms to depends on it).
TEST(BenchPlot, DrawsSceneListIsTheRegistrys) {
  std::ifstream in(ts::test::sourceDir() + "/bench/plot.py");
  std::string line, listed;
  while (std::getline(in, line))
    if (line.rfind("DRAWS_SCENE = {", 0) == 0) listed = line;
  ASSERT_FALSE(listed.empty()) << "no DRAWS_SCENE line in bench/plot.py";
  std::set<std::string> fromPlot, fromRegistry;
  for (size_t q = listed.find('"'); q != std::string::npos; q = listed.find('"', q + 1)) {
    size_t end = listed.find('"', q + 1);
    fromPlot.insert(listed.substr(q + 1, end - q - 1));
    q = end;
  }
  for (const ts::TechniqueInfo& t : ts::techniqueRegistry())
    if (t.drawsScene) fromRegistry.insert(t.name);
  EXPECT_EQ(fromPlot, fromRegistry);
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
      {"text.csv", header + "\n" + set(good, "total_ms", "fast") + "\n",
       "total_ms is not a number: 'fast'"},
      {"kernels.csv", header + "\n" + set(good, "kernels", "shade=x") + "\n",
       "kernel time is not a number"},
      {"truncated.csv", header + "\n1,2,3\n", "line 2: 3 field(s)"},
      {"noid.csv", header + "\n" + set(good, "config_id", "") + "\n", "no config_id"},
      {"junk.csv", header + "\n" + std::string(1 << 20, 'x') + "\n", "junk.csv"},
      {"bad.json", "{\"rows\": [", "not JSON"},
      {"rows.json", "{\"rows\": 5}", "no \"rows\" list"},
      {"row.json",
       "{\"rows\": [{\"config\": {\"technique\": \"tiled\", \"tile\": \"16x16\"}, \"config_id\": "
       "\"a\", \"frame\": 0, \"total_ms\": \"x\"}]}",
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
