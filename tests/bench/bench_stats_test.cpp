// `tileshade bench`'s statistics and CSV (src/bench/bench_stats.h): medians over frames, the CSV
// quoting and its strict records.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/bench_run.h"
#include "bench/bench_stats.h"
#include "bench_test_support.h"

namespace fs = std::filesystem;

namespace {

using ts::test::tempDir;

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
    return nlohmann::json{{"config_id", id},   {"config", {{"technique", "t"}}},
                          {"frame", frame},    {"total_ms", ms},
                          {"wall_ms", ms + 1}, {"kernels", {{{"name", "k"}, {"ms", ms}}}}};
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

TEST(BenchCsv, StrictRecordsRefuseStrayQuotes) {
  std::vector<std::string> f;
  EXPECT_TRUE(ts::parseCsvRecord("a,\"b,\"\"c\"\"\",", f));
  EXPECT_EQ(f, (std::vector<std::string>{"a", "b,\"c\"", ""}));
  for (const char* bad : {"\"a", "a\"b\",c", "\"a\"b,c", "a,\"b"})
    EXPECT_FALSE(ts::parseCsvRecord(bad, f)) << bad;
}

}  // namespace
