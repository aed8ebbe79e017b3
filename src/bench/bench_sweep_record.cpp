#include "bench/bench_sweep_record.h"

#include <cstdint>
#include <cstdio>

#include "util/error.h"

namespace ts {
namespace {

using json = nlohmann::json;

// A field of a run record of the given JSON type, or a one-line error.
const json& field(const json& record, const std::string& name, json::value_t type,
                  const std::string& source) {
  auto it = record.is_object() ? record.find(name) : record.end();
  bool ok =
      it != record.end() &&
      (it->type() == type || (type == json::value_t::number_integer && it->is_number_integer()));
  if (!ok) throw Error(source + ": its run record has no " + name + " of the expected type");
  return *it;
}

}  // namespace

SweepRunOptions SweepRunOptions::fromRun(const json& run, const std::string& source) {
  SweepRunOptions o;
  o.frames = field(run, "frames", json::value_t::string, source).get<std::string>();
  o.warmup = field(run, "warmup", json::value_t::number_integer, source).get<int>();
  o.repeat = field(run, "repeat", json::value_t::number_integer, source).get<int>();
  o.error = field(run, "error", json::value_t::boolean, source).get<bool>();
  o.errorFrames = field(run, "error_frames", json::value_t::string, source).get<std::string>();
  const json& sweep = field(run, "sweep", json::value_t::object, source);
  o.calibrate = field(sweep, "calibrate", json::value_t::boolean, source).get<bool>();
  return o;
}

std::vector<std::pair<std::string, std::string>> SweepRunOptions::fields() const {
  std::vector<std::pair<std::string, std::string>> f = {{"frames", frames},
                                                        {"warmup", std::to_string(warmup)},
                                                        {"repeat", std::to_string(repeat)},
                                                        {"error", error ? "on" : "off"}};
  if (error) f.emplace_back("error_frames", errorFrames);
  f.emplace_back("calibrate", calibrate ? "on" : "off");
  return f;
}

std::string sweepHash(const std::vector<BenchConfig>& configs, const SweepRunOptions& run) {
  uint64_t h = 1469598103934665603ull;  // FNV-1a, as BenchConfig::id()
  auto add = [&](const std::string& s) {
    for (unsigned char c : s) {
      h ^= c;
      h *= 1099511628211ull;
    }
    h ^= '\n';
    h *= 1099511628211ull;
  };
  for (const auto& c : configs) add(c.key());
  for (const auto& [name, value] : run.fields()) add(name + "=" + value);
  char buf[20];
  std::snprintf(buf, sizeof buf, "%016llx", (unsigned long long)h);
  return buf;
}

json sweepRecord(const BenchSweep& sweep, const std::vector<BenchConfig>& configs,
                 const SweepRunOptions& run) {
  return {{"hash", sweepHash(configs, run)},
          {"configurations", configs.size()},
          {"dimensions", sweep.values},
          {"calibrate", run.calibrate}};
}

BenchSweep sweepFromRecord(const json& dimensions, const std::string& source) {
  if (!dimensions.is_object()) throw Error(source + ": its sweep record has no dimensions object");
  BenchSweep sweep;
  for (auto it = dimensions.begin(); it != dimensions.end(); ++it) {
    std::vector<std::string> values;
    bool ok = it->is_array();
    if (ok)
      for (const auto& v : *it) {
        ok = ok && v.is_string();
        if (ok) values.push_back(v.get<std::string>());
      }
    if (!ok)
      throw Error(source + ": its sweep record's dimension '" + it.key() +
                  "' is not a list of strings");
    sweep.set(it.key(), values);
  }
  return sweep;
}

}  // namespace ts
