// `tileshade bench merge`: the shards of a small sweep (two frame groups, 8 configurations, two
// frames, 64x36 and 48x32) merged equal the unsharded run's rows and summaries apart from times,
// row order included; and every refusal (bench_merge.h) is one line naming the folder.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/bench_columns.h"
#include "bench/bench_merge.h"
#include "bench/bench_run.h"
#include "bench/bench_stats.h"
#include "bench_test_support.h"
#include "test_support.h"
#include "util/error.h"

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

using ts::test::expectOneLineError;

std::string baseDir() {
  static const std::string dir = [] {
    fs::path p =
        fs::temp_directory_path() / ("tileshade_bench_merge_" + std::to_string(::getpid()));
    fs::remove_all(p);
    fs::create_directories(p);
    return p.string();
  }();
  return dir;
}

ts::BenchOptions sweepOptions(const std::string& out, const std::string& shard) {
  ts::BenchOptions o;
  o.sweep.set("device", {"cpu"});
  o.sweep.set("resolution", {"64x36,48x32"});  // two frame groups: shards interleave them
  o.sweep.set("gbuffer", {"fp32,fp16"});
  o.sweep.set("technique", {"tiled"});
  o.sweep.set("tile", {"16,32x16"});
  o.frames.text = "0:40:20";  // frames 0 and 20
  o.warmup = 0;
  o.calibrate = false;
  o.outDir = out;
  o.shard = ts::Shard::parse(shard);
  o.progress = false;
  o.printTable = false;
  return o;
}

// A column whose value is a time (or follows from one): differs between runs.
bool timeColumn(const ts::BenchColumn& c) {
  return c.type == ts::BenchColumnType::Time || c.type == ts::BenchColumnType::Kernels ||
         c.type == ts::BenchColumnType::KernelMedians ||
         std::regex_search(c.name, std::regex("_ms|limit|gbs|gflops"));
}

// Each record's CSV fields without the time columns, in order.
std::vector<std::vector<std::string>> untimed(const std::vector<ts::BenchColumn>& columns,
                                              const json& records) {
  std::vector<std::vector<std::string>> out;
  for (const auto& r : records) {
    std::vector<std::string> all = ts::csvFields(columns, r), kept;
    for (size_t i = 0; i < columns.size(); ++i)
      if (!timeColumn(columns[i])) kept.push_back(all[i]);
    out.push_back(kept);
  }
  return out;
}

// The same of bench.csv or summary.csv.
std::vector<std::vector<std::string>> untimedCsv(const std::string& path,
                                                 const std::vector<ts::BenchColumn>& columns) {
  std::vector<std::string> header;
  std::vector<std::map<std::string, std::string>> rows;
  EXPECT_TRUE(ts::readCsv(path, header, rows)) << path;
  std::vector<std::vector<std::string>> out;
  for (const auto& row : rows) {
    std::vector<std::string> kept;
    for (const auto& c : columns)
      if (!timeColumn(c)) kept.push_back(row.at(c.name));
    out.push_back(kept);
  }
  return out;
}

// The unsharded run and shards 0/3, 1/3, 2/3 of the same sweep, once for every test.
class BenchMerge : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    for (const auto& [dir, shard] : {std::pair<std::string, std::string>{"whole", "0/1"},
                                     {"s0", "0/3"},
                                     {"s1", "1/3"},
                                     {"s2", "2/3"}}) {
      ts::BenchRunResult r = ts::runBench(sweepOptions(baseDir() + "/" + dir, shard));
      ASSERT_TRUE(r.failures.empty());
    }
  }
  static void TearDownTestSuite() { fs::remove_all(baseDir()); }

  static std::string dir(const std::string& name) { return baseDir() + "/" + name; }
  // A copy of shard folder `from` as `name`, for a case to spoil.
  static std::string copyOf(const std::string& from, const std::string& name) {
    fs::remove_all(dir(name));
    fs::copy(dir(from), dir(name), fs::copy_options::recursive);
    return dir(name);
  }
  static ts::BenchMergeOptions mergeOptions(const std::string& out,
                                            std::vector<std::string> shards) {
    ts::BenchMergeOptions m;
    m.outDir = dir(out);
    for (auto& s : shards) m.shardDirs.push_back(s.find('/') == std::string::npos ? dir(s) : s);
    m.printTable = false;
    return m;
  }
};

TEST_F(BenchMerge, ShardsMergedEqualTheUnshardedRun) {
  ts::BenchMergeResult r = ts::mergeBenchShards(mergeOptions("merged", {"s2", "s0", "s1"}));
  EXPECT_EQ(r.shards, 3u);
  EXPECT_EQ(r.configurations, 8u);
  EXPECT_EQ(r.rows, 16u);

  const auto& bench = ts::benchColumns();
  const auto& summary = ts::summaryColumns();
  json whole = json::parse(std::ifstream(dir("whole") + "/bench.json"));
  json merged = json::parse(std::ifstream(dir("merged") + "/bench.json"));
  // Row order too: the shards' rows are put back in the order one run measures them.
  EXPECT_EQ(untimed(bench, merged["rows"]), untimed(bench, whole["rows"]));
  EXPECT_EQ(untimed(summary, merged["summaries"]), untimed(summary, whole["summaries"]));
  EXPECT_EQ(untimedCsv(dir("merged") + "/bench.csv", bench),
            untimedCsv(dir("whole") + "/bench.csv", bench));
  EXPECT_EQ(untimedCsv(dir("merged") + "/summary.csv", summary),
            untimedCsv(dir("whole") + "/summary.csv", summary));
  EXPECT_EQ(untimedCsv(dir("merged") + "/bench.csv", bench).size(), 16u);
  // The merged files hold what the shards measured, times included.
  std::set<std::string> shardTimes, mergedTimes;
  for (const char* s : {"s0", "s1", "s2"}) {
    json shard = json::parse(std::ifstream(dir(s) + "/bench.json"));
    for (const auto& row : shard["rows"])
      shardTimes.insert(row["config_id"].get<std::string>() + " " + row["total_ms"].dump());
  }
  for (const auto& row : merged["rows"])
    mergedTimes.insert(row["config_id"].get<std::string>() + " " + row["total_ms"].dump());
  EXPECT_EQ(mergedTimes, shardTimes);
  // Every shard's run is listed, each with the sweep's record.
  ASSERT_EQ(merged["runs"].size(), 3u);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(merged["runs"][k]["shard"], std::to_string(k) + "/3");
    EXPECT_EQ(merged["runs"][k]["sweep"]["hash"], whole["runs"][0]["sweep"]["hash"]);
  }
  EXPECT_EQ(merged["merge"]["shards"].size(), 3u);

  // A second merge into the same OUT needs --overwrite.
  expectOneLineError(
      [&] {
        ts::mergeBenchShards(mergeOptions("merged", {"s0", "s1", "s2"}));
      },
      {"merged/bench.csv exists", "--overwrite"});
  ts::BenchMergeOptions again = mergeOptions("merged", {"s0", "s1", "s2"});
  again.overwrite = true;
  EXPECT_EQ(ts::mergeBenchShards(again).rows, 16u);
  // One unsharded run is a sweep of one shard.
  EXPECT_EQ(ts::mergeBenchShards(mergeOptions("merged_whole", {"whole"})).rows, 16u);
}

TEST_F(BenchMerge, RefusesShardsOfAnotherSweepOrSplit) {
  ASSERT_TRUE(ts::runBench([] {
                auto o = sweepOptions(dir("frames1"), "1/3");
                o.frames.text = "0:1";
                return o;
              }())
                  .failures.empty());
  expectOneLineError(
      [&] {
        ts::mergeBenchShards(mergeOptions("out", {"s0", "frames1", "s2"}));
      },
      {"frames1 is a shard of another sweep", "frames '0:1'", "'0:40:20'"});
  ASSERT_TRUE(ts::runBench([] {
                auto o = sweepOptions(dir("tiles1"), "1/3");
                o.sweep.set("tile", {"16"});
                return o;
              }())
                  .failures.empty());
  expectOneLineError(
      [&] {
        ts::mergeBenchShards(mergeOptions("out", {"s0", "tiles1", "s2"}));
      },
      {"tiles1 is a shard of another sweep", "configuration(s)"});
  ASSERT_TRUE(ts::runBench(sweepOptions(dir("half1"), "1/2")).failures.empty());
  expectOneLineError(
      [&] {
        ts::mergeBenchShards(mergeOptions("out", {"s0", "half1", "s2"}));
      },
      {"half1 is shard 1/2", "another split"});
  EXPECT_FALSE(fs::exists(dir("out")));
}

TEST_F(BenchMerge, RefusesAShardTwiceOrMissing) {
  copyOf("s1", "s1_again");
  expectOneLineError(
      [&] {
        ts::mergeBenchShards(mergeOptions("out", {"s0", "s1", "s1_again", "s2"}));
      },
      {"s1", "s1_again", "both shard 1/3"});
  expectOneLineError(
      [&] {
        ts::mergeBenchShards(mergeOptions("out", {"s0", "s1", dir("s1") + "/", "s2"}));
      },
      {"s1 is given twice (shard 1/3)"});
  expectOneLineError(
      [&] {
        ts::mergeBenchShards(mergeOptions("out", {"s0", "s1"}));
      },
      {"shard 2/3 is missing", "2 of 3"});
  expectOneLineError(
      [&] {
        ts::mergeBenchShards(mergeOptions("out", {"s2", "s1"}));
      },
      {"shard 0/3 is missing"});
  EXPECT_FALSE(fs::exists(dir("out")));
}

TEST_F(BenchMerge, RefusesARowTwice) {
  std::string d = copyOf("s1", "s1_doubled");
  std::vector<std::string> lines;
  {
    std::ifstream in(d + "/bench.csv");
    for (std::string l; std::getline(in, l);) lines.push_back(l);
  }
  std::ofstream(d + "/bench.csv", std::ios::app) << lines.back() << "\n";
  expectOneLineError(
      [&] {
        ts::mergeBenchShards(mergeOptions("out", {"s0", "s1_doubled", "s2"}));
      },
      {"is there twice", "s1_doubled/bench.csv line " + std::to_string(lines.size()),
       "s1_doubled/bench.csv line " + std::to_string(lines.size() + 1)});
  // A row of another shard's configuration, e.g. shard 0's rows copied into shard 1's folder.
  std::string other = copyOf("s1", "s1_foreign");
  std::vector<std::string> s0;
  {
    std::ifstream in(dir("s0") + "/bench.csv");
    for (std::string l; std::getline(in, l);) s0.push_back(l);
  }
  std::ofstream(other + "/bench.csv", std::ios::app) << s0.back() << "\n";
  expectOneLineError(
      [&] {
        ts::mergeBenchShards(mergeOptions("out", {"s0", "s1_foreign", "s2"}));
      },
      {"s1_foreign/bench.csv line", "is not one of shard 1/3's"});
  EXPECT_FALSE(fs::exists(dir("out")));
}

TEST_F(BenchMerge, RefusesFoldersThatAreNotFinishedShards) {
  fs::create_directories(dir("empty"));
  expectOneLineError(
      [&] {
        ts::mergeBenchShards(mergeOptions("out", {"s0", "empty", "s2"}));
      },
      {"empty has no bench.csv"});
  std::ofstream(dir("plain_file")) << "not a folder\n";
  expectOneLineError(
      [&] {
        ts::mergeBenchShards(mergeOptions("out", {"s0", "plain_file", "s2"}));
      },
      {"plain_file is a file"});
  expectOneLineError(
      [&] {
        ts::mergeBenchShards(mergeOptions("out", {"s0", "absent", "s2"}));
      },
      {"absent: no such folder"});
  // bench.json written before runs recorded their sweep, and a run that did not finish.
  for (const char* name : {"s1_old", "s1_unfinished"}) {
    std::string d = copyOf("s1", name);
    json doc = json::parse(std::ifstream(d + "/bench.json"));
    if (std::string(name) == "s1_old") doc["runs"].back().erase("sweep");
    else doc["runs"].back().erase("finished");
    std::ofstream(d + "/bench.json") << doc.dump(1);
  }
  expectOneLineError(
      [&] {
        ts::mergeBenchShards(mergeOptions("out", {"s0", "s1_old", "s2"}));
      },
      {"s1_old/bench.json records no sweep"});
  expectOneLineError(
      [&] {
        ts::mergeBenchShards(mergeOptions("out", {"s0", "s1_unfinished", "s2"}));
      },
      {"s1_unfinished: its run did not finish", "--resume"});
  // A row edited after it was written no longer matches its bench.json record.
  std::string edited = copyOf("s1", "s1_edited");
  std::vector<std::string> lines;
  {
    std::ifstream in(edited + "/bench.csv");
    for (std::string l; std::getline(in, l);) lines.push_back(l);
  }
  lines[1] = std::regex_replace(lines[1], std::regex(",tiled,"), ",brute,");
  {
    std::ofstream out(edited + "/bench.csv");
    for (const auto& l : lines) out << l << "\n";
  }
  expectOneLineError(
      [&] {
        ts::mergeBenchShards(mergeOptions("out", {"s0", "s1_edited", "s2"}));
      },
      {"s1_edited/bench.csv line 2", "technique 'brute'"});
  EXPECT_FALSE(fs::exists(dir("out")));
}

// A shard killed after some rows (bench.json's last run not finished, its last row lost) is refused
// until --resume has finished it; then the merge equals the unsharded run again. A row of
// bench.csv that bench.json lacks (lost between the two writes) comes back from bench.csv.
TEST_F(BenchMerge, AShardFinishedByResumeMergesAsAnyOther) {
  std::string d = copyOf("s1", "s1_killed");
  std::vector<std::string> lines;
  {
    std::ifstream in(d + "/bench.csv");
    for (std::string l; std::getline(in, l);) lines.push_back(l);
  }
  lines.pop_back();
  {
    std::ofstream out(d + "/bench.csv");
    for (const auto& l : lines) out << l << "\n";
  }
  json doc = json::parse(std::ifstream(d + "/bench.json"));
  doc["runs"].back().erase("finished");
  doc["rows"].erase(doc["rows"].begin());  // the first row now only in bench.csv
  std::ofstream(d + "/bench.json") << doc.dump(1);
  expectOneLineError(
      [&] {
        ts::mergeBenchShards(mergeOptions("out", {"s0", "s1_killed", "s2"}));
      },
      {"s1_killed: its run did not finish"});
  ts::BenchOptions resume = sweepOptions(d, "1/3");
  resume.resume = true;
  ts::BenchRunResult r = ts::runBench(resume);
  EXPECT_EQ(r.measuredRows, 1u);
  ts::mergeBenchShards(mergeOptions("resumed", {"s0", "s1_killed", "s2"}));
  json whole = json::parse(std::ifstream(dir("whole") + "/bench.json"));
  json merged = json::parse(std::ifstream(dir("resumed") + "/bench.json"));
  EXPECT_EQ(untimed(ts::benchColumns(), merged["rows"]),
            untimed(ts::benchColumns(), whole["rows"]));
  EXPECT_EQ(merged["runs"].size(), 4u);  // shard 1 ran twice

  std::string lost = copyOf("s1", "s1_lost_record");
  doc = json::parse(std::ifstream(lost + "/bench.json"));
  doc["rows"].erase(doc["rows"].begin());
  std::ofstream(lost + "/bench.json") << doc.dump(1);
  ts::mergeBenchShards(mergeOptions("lost_record", {"s0", "s1_lost_record", "s2"}));
  merged = json::parse(std::ifstream(dir("lost_record") + "/bench.json"));
  EXPECT_EQ(untimed(ts::benchColumns(), merged["rows"]),
            untimed(ts::benchColumns(), whole["rows"]));
}

TEST_F(BenchMerge, RefusesAnOutThatIsAFileOrAShard) {
  std::ofstream(dir("out_file")) << "x\n";
  expectOneLineError(
      [&] {
        ts::mergeBenchShards(mergeOptions("out_file", {"s0", "s1", "s2"}));
      },
      {"out_file is a file"});
  ts::BenchMergeOptions intoShard = mergeOptions("s1", {"s0", "s1", "s2"});
  intoShard.overwrite = true;
  expectOneLineError([&] { ts::mergeBenchShards(intoShard); }, {"is the shard folder"});
}

TEST_F(BenchMerge, CommandLine) {
  ts::test::CliRun r = ts::test::runTileshade("bench merge " + dir("cli") + " " + dir("s0") + " " +
                                              dir("s1") + " " + dir("s2"));
  EXPECT_EQ(r.exitCode(), 0) << r.output;
  EXPECT_NE(r.output.find("3 shard(s) of a sweep of 8 configuration(s); 16 row(s)"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("wrote " + dir("cli") + "/bench.csv"), std::string::npos) << r.output;
  r = ts::test::runTileshade("bench merge " + dir("cli") + " " + dir("s0"));
  EXPECT_EQ(r.exitCode(), 1);
  EXPECT_EQ(r.output.rfind("tileshade: error: bench merge: ", 0), 0u) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  r = ts::test::runTileshade("bench --technique tiled merge " + dir("cli2") + " " + dir("s0"));
  EXPECT_EQ(r.exitCode(), 1);
  EXPECT_NE(r.output.find("--technique is an option of a sweep"), std::string::npos) << r.output;
}

}  // namespace
