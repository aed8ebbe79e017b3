// The repeated calibration's bookkeeping on synthetic rates (src/bench/calibration_rounds.h): the
// best round, the spread, when the rounds may stop, and how bench prints them. Host only.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/calibration_rounds.h"

namespace {

TEST(BenchCalibrationRounds, BestIsTheLargestRoundAndTheSpreadIsKept) {
  // A loaded machine: the rate swings 185..293 between rounds (issue #19's figures).
  ts::RoundSpread s = ts::spreadOf({185.0, 293.0, 240.0, 287.0, 201.0});
  EXPECT_DOUBLE_EQ(s.best, 293.0);
  EXPECT_DOUBLE_EQ(s.max, 293.0);
  EXPECT_DOUBLE_EQ(s.min, 185.0);
  EXPECT_DOUBLE_EQ(s.median, 240.0);
  EXPECT_EQ(s.rounds.size(), 5u);
}

TEST(BenchCalibrationRounds, FailedRoundsAreNotTheBest) {
  ts::RoundSpread s = ts::spreadOf({0.0, NAN, 120.0, INFINITY, 100.0});
  EXPECT_DOUBLE_EQ(s.best, 120.0);
  EXPECT_DOUBLE_EQ(s.min, 100.0);
  EXPECT_DOUBLE_EQ(s.median, 110.0);
  EXPECT_EQ(s.rounds.size(), 5u);  // every round is recorded as measured
  ts::RoundSpread none = ts::spreadOf({0.0, NAN});
  EXPECT_EQ(none.best, 0.0);  // so limitMs gives no limit rather than a wrong one
}

TEST(BenchCalibrationRounds, BestTwoAgreeWithinTheTolerance) {
  EXPECT_TRUE(ts::bestTwoAgree({200.0, 290.0, 285.0}, 0.03));   // 1.7% apart
  EXPECT_FALSE(ts::bestTwoAgree({200.0, 290.0, 270.0}, 0.03));  // 6.9% apart
  EXPECT_TRUE(ts::bestTwoAgree({290.0, 282.0}, 0.03));          // 2.76%
  EXPECT_FALSE(ts::bestTwoAgree({290.0, 281.0}, 0.03));         // 3.1%
  EXPECT_FALSE(ts::bestTwoAgree({290.0}, 0.03));                // one round proves nothing
  EXPECT_FALSE(ts::bestTwoAgree({290.0, NAN}, 0.03));
}

TEST(BenchCalibrationRounds, StopAtAgreementOrAtTheBound) {
  ts::CalibrationRoundsOptions o;  // 2..5 rounds, 3%
  EXPECT_FALSE(ts::roundsSettled({{}, {}}, o));
  EXPECT_FALSE(ts::roundsSettled({{60.0}, {290.0}}, o));
  EXPECT_TRUE(ts::roundsSettled({{60.0, 61.0}, {290.0, 288.0}}, o));
  // Every rate must agree: the bandwidth agrees, the peak does not.
  EXPECT_FALSE(ts::roundsSettled({{60.0, 61.0}, {290.0, 200.0}}, o));
  EXPECT_FALSE(ts::roundsSettled({{60, 61, 60, 61}, {290, 200, 185, 250}}, o));
  EXPECT_TRUE(ts::roundsSettled({{60, 61, 60, 61, 60}, {290, 200, 185, 250, 240}}, o));
  o.minRounds = 3;
  EXPECT_FALSE(ts::roundsSettled({{60.0, 61.0}, {290.0, 288.0}}, o));
  o.maxRounds = 1;  // a single round: stop after it whatever it says
  EXPECT_TRUE(ts::roundsSettled({{60.0}, {290.0}}, o));
}

TEST(BenchCalibrationRounds, RecordAndTextShowTheSpread) {
  ts::RoundSpread s = ts::spreadOf({185.0, 293.0, 240.0});
  nlohmann::json record = {{"peak_gflops", s.best},      {"peak_gflops_spread", ts::spreadJson(s)},
                           {"copy_bandwidth_gbs", 62.9}, {"copy_bytes_per_buffer", 256 << 20},
                           {"fma_vector_width", 16},     {"settled", false},
                           {"agreement", 0.03}};
  EXPECT_EQ(record["peak_gflops_spread"]["median"].get<double>(), 240.0);
  EXPECT_EQ(record["peak_gflops_spread"]["rounds"].size(), 3u);
  EXPECT_EQ(ts::spreadText(record, "peak_gflops", "GFLOP/s"),
            "293.0 GFLOP/s (best of 3 rounds: 185.0-293.0, median 240.0)");
  // A record written before the rounds: the value alone.
  EXPECT_EQ(ts::spreadText(record, "copy_bandwidth_gbs", "GB/s"), "62.9 GB/s");
  std::string line = ts::calibrationText(record);
  EXPECT_NE(line.find("256 MiB"), std::string::npos) << line;
  EXPECT_NE(line.find("float16"), std::string::npos) << line;
  EXPECT_NE(line.find("did not agree within 3%"), std::string::npos) << line;

  nlohmann::json runs = {
      {{"devices", {{{"name", "cpu-x"}, {"calibration", record}}, {{"name", "uncalibrated"}}}}}};
  std::ostringstream out;
  ts::printCalibrations(runs, out);
  EXPECT_EQ(out.str().rfind("% limit on cpu-x: copy bandwidth 62.9 GB/s", 0), 0u) << out.str();
  EXPECT_EQ(out.str().find("uncalibrated"), std::string::npos);
}

}  // namespace
