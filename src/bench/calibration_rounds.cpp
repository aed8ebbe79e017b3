#include "bench/calibration_rounds.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "bench/bench_stats.h"

namespace ts {
namespace {

std::vector<double> validRounds(const std::vector<double>& rounds) {
  std::vector<double> v;
  for (double r : rounds)
    if (std::isfinite(r) && r > 0.0) v.push_back(r);
  return v;
}

}  // namespace

RoundSpread spreadOf(const std::vector<double>& rounds) {
  RoundSpread s;
  s.rounds = rounds;
  Summary m = summarize(validRounds(rounds));
  if (m.n == 0) return s;
  s.best = s.max = m.max;
  s.min = m.min;
  s.median = m.median;
  return s;
}

bool bestTwoAgree(const std::vector<double>& rounds, double agreement) {
  std::vector<double> v = validRounds(rounds);
  if (v.size() < 2) return false;
  std::partial_sort(v.begin(), v.begin() + 2, v.end(), std::greater<double>());
  return v[0] - v[1] <= agreement * v[0];
}

bool roundsSettled(const std::vector<std::vector<double>>& rates,
                   const CalibrationRoundsOptions& o) {
  size_t n = rates.empty() ? 0 : rates.front().size();
  if (n >= size_t(std::max(o.maxRounds, 1))) return true;
  if (n < size_t(std::max(o.minRounds, 1))) return false;
  return std::all_of(rates.begin(), rates.end(),
                     [&](const std::vector<double>& r) { return bestTwoAgree(r, o.agreement); });
}

nlohmann::json spreadJson(const RoundSpread& s) {
  return {
      {"best", s.best}, {"min", s.min}, {"median", s.median}, {"max", s.max}, {"rounds", s.rounds}};
}

std::string spreadText(const nlohmann::json& calibration, const std::string& key,
                       const std::string& unit) {
  auto number = [](const nlohmann::json& j, const char* k) {
    return j.is_object() && j.contains(k) && j[k].is_number() ? j[k].get<double>() : NAN;
  };
  std::string text = fixedText(number(calibration, key.c_str()), 1) + " " + unit;
  const std::string spreadKey = key + "_spread";
  if (!calibration.is_object() || !calibration.contains(spreadKey)) return text;
  const nlohmann::json& s = calibration[spreadKey];
  size_t rounds =
      s.is_object() && s.contains("rounds") && s["rounds"].is_array() ? s["rounds"].size() : 0;
  return text + " (best of " + std::to_string(rounds) + (rounds == 1 ? " round: " : " rounds: ") +
         fixedText(number(s, "min"), 1) + "-" + fixedText(number(s, "max"), 1) + ", median " +
         fixedText(number(s, "median"), 1) + ")";
}

std::string calibrationText(const nlohmann::json& c) {
  auto integer = [&](const char* k) {
    return c.is_object() && c.contains(k) && c[k].is_number_integer() ? c[k].get<long long>() : 0;
  };
  long long width = integer("fma_vector_width");
  std::string text = "copy bandwidth " + spreadText(c, "copy_bandwidth_gbs", "GB/s") + ", " +
                     std::to_string(integer("copy_bytes_per_buffer") >> 20) +
                     " MiB read + written; peak " + spreadText(c, "peak_gflops", "GFLOP/s") +
                     ", float" + (width > 1 ? std::to_string(width) : "") + " multiply-add chains";
  if (c.is_object() && c.contains("settled") && c["settled"].is_boolean() &&
      !c["settled"].get<bool>()) {
    double agreement =
        c.contains("agreement") && c["agreement"].is_number() ? c["agreement"].get<double>() : NAN;
    text += "; the best two rounds did not agree within " + fixedText(agreement * 100.0, 0) +
            "% (a loaded machine: the limit is less certain)";
  }
  return text;
}

void printCalibrations(const nlohmann::json& runs, std::ostream& out) {
  std::set<std::string> printed;
  if (!runs.is_array()) return;
  for (const auto& run : runs) {
    if (!run.is_object() || !run.contains("devices") || !run["devices"].is_array()) continue;
    for (const auto& d : run["devices"]) {
      if (!d.is_object() || !d.contains("calibration")) continue;
      std::string name =
          d.contains("name") && d["name"].is_string() ? d["name"].get<std::string>() : "device";
      std::string line = "% limit on " + name + ": " + calibrationText(d["calibration"]);
      if (printed.insert(line).second) out << line << "\n";
    }
  }
}

}  // namespace ts
