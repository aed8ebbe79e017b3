#pragma once
// What makes runs parts of one sweep (the shards of `bench --shard`, and `bench merge` joining
// them): the expanded configurations in sweep order and the run options that decide which rows
// a run writes. Every run records it in bench.json as its "sweep" (bench/README.md):
//   {"hash": 16 hex digits, "configurations": N, "dimensions": {name: [values as given]},
//    "calibrate": true|false}
// beside the run's own "frames", "warmup", "repeat", "error" and "error_frames". The dimensions
// expand (expandSweep) to the configurations again, so that a merge can put rows back in the order
// of one unsharded run; the hash says whether two runs are of the same sweep.
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/bench_config.h"

namespace ts {

// The run options that decide what a sweep's rows are, beside its configurations.
struct SweepRunOptions {
  std::string frames;  // --frames as given
  int warmup = 1, repeat = 1;
  bool error = false;
  std::string errorFrames;  // only counts with error
  bool calibrate = true;    // off: no limit columns

  // From a bench.json run record ("frames", …, "sweep"/"calibrate"); ts::Error naming `source`
  // and the field when one is missing or of another type.
  static SweepRunOptions fromRun(const nlohmann::json& run, const std::string& source);
  // (name, value) of each option, in a fixed order: what the hash covers, and what a refusal
  // names when two runs differ.
  std::vector<std::pair<std::string, std::string>> fields() const;
};

// Hex of a 64-bit FNV-1a hash over every configuration's key() (in order) and the run options.
std::string sweepHash(const std::vector<BenchConfig>& configs, const SweepRunOptions& run);

// The "sweep" record of a run (see above).
nlohmann::json sweepRecord(const BenchSweep& sweep, const std::vector<BenchConfig>& configs,
                           const SweepRunOptions& run);

// A recorded "dimensions" object back as a sweep; ts::Error naming `source` when it is not one.
BenchSweep sweepFromRecord(const nlohmann::json& dimensions, const std::string& source);

}  // namespace ts
