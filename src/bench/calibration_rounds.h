#pragma once
// The repeated calibration's bookkeeping (host only): a rate measured once swings with what else
// runs on the machine (185 to 293 GFLOP/s between runs on a loaded 2-core host, issue #19), so
// calibrate() measures whole rounds until the best two agree, keeps the best round (the rate least
// disturbed) and records the spread of the rounds beside it.
#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace ts {

struct CalibrationRoundsOptions {
  int minRounds = 2;        // never stop before this many rounds
  int maxRounds = 5;        // and never measure more
  double agreement = 0.03;  // settled: the second best round within this fraction of the best
};

// One rate (GB/s or GFLOP/s) over the rounds: each round's value, its best (largest) and spread.
struct RoundSpread {
  std::vector<double> rounds;
  double best = 0.0, min = 0.0, median = 0.0, max = 0.0;
};

// best = max; median as summarize(). Non-finite or non-positive rounds (a failed timing) are left
// out of everything but `rounds`; all 0 when none is left.
RoundSpread spreadOf(const std::vector<double>& rounds);

// Whether the two largest valid rounds agree: (best - second) <= agreement * best. False with
// fewer than two.
bool bestTwoAgree(const std::vector<double>& rounds, double agreement);

// Whether calibrate() may stop after the rounds measured so far (the same count in each list):
// at maxRounds, or from minRounds on once every rate's best two agree.
bool roundsSettled(const std::vector<std::vector<double>>& rates,
                   const CalibrationRoundsOptions& options);

// {"best", "min", "median", "max", "rounds": [...]} of bench.json's calibration record.
nlohmann::json spreadJson(const RoundSpread& s);

// "265.3 GFLOP/s (best of 5 rounds: 185.0-265.3, median 240.1)" for a calibration record's rate
// `key` ("peak_gflops" with unit "GFLOP/s", "copy_bandwidth_gbs" with "GB/s"); a record written
// before the rounds (no "<key>_spread") gives the value alone.
std::string spreadText(const nlohmann::json& calibration, const std::string& key,
                       const std::string& unit);

// A calibration record (Calibration::toJson) in one line: both rates with their spreads, and a
// warning when the best two rounds did not agree.
std::string calibrationText(const nlohmann::json& calibration);

// After the summary table: each calibrated device of bench.json's `runs` with its calibration, so
// the % limit column is read with the spread of the rates behind it. Nothing when none was
// calibrated.
void printCalibrations(const nlohmann::json& runs, std::ostream& out);

}  // namespace ts
