#pragma once
// `tileshade bench merge OUT SHARD_DIR…`: joins the output folders of the shards of one sweep
// (`bench --shard k/n`, run as separate processes or on separate machines) into OUT/bench.csv,
// OUT/bench.json and OUT/summary.csv as one unsharded run of the sweep writes them, rows in its
// order. Refused, in one line naming the folder and what is wrong, before anything is written:
// a folder that is missing, a file, or without bench.csv/bench.json; a shard whose run did not
// finish or that records no sweep (bench_sweep_record.h); shards of different sweeps or splits;
// a shard given twice or missing; a row that does not parse, is not its shard's, disagrees with
// its bench.json record, or whose (configuration, frame) is there twice; an OUT that already
// holds results (unless overwrite).
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace ts {

struct BenchMergeOptions {
  std::string outDir;
  std::vector<std::string> shardDirs;  // any order; every shard k/n of the sweep exactly once
  bool overwrite = false;              // replace OUT's bench.csv/bench.json/summary.csv
  bool printTable = true;              // the summary table on stdout, as `bench` prints it
  std::string command;                 // recorded in bench.json
};

struct BenchMergeResult {
  size_t shards = 0;
  size_t configurations = 0;  // of the sweep
  size_t rows = 0;
  nlohmann::json summaries;  // as in bench.json "summaries"
};

BenchMergeResult mergeBenchShards(const BenchMergeOptions& options);

}  // namespace ts
