#pragma once
// The benchmark runner behind `tileshade bench` (options in bench_cli.cpp, file formats in
// bench/README.md): expands the sweep, calibrates each device, times every configuration over
// the frames of its scene's camera path and writes DIR/bench.csv, DIR/bench.json, DIR/summary.csv.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/bench_columns.h"  // the files' columns (benchCsvColumns, rowFromCsv)
#include "bench/bench_config.h"
#include "bench/bench_summary.h"  // summarizeRows
#include "bench/calibrate.h"

namespace ts {

// Limits of the run options (command line and --config alike).
constexpr int kMaxWarmup = 1000, kMaxRepeat = 1000, kMaxCalibMiB = 65536;

struct BenchOptions {
  BenchSweep sweep;
  FrameSpec frames;                 // which frames of the camera path are timed
  int warmup = 1;                   // untimed renders per configuration before its first frame
  int repeat = 1;                   // timed renders per frame; the row keeps the median one
  bool error = false;               // error against the double reference
  std::string errorFrames = "all";  // "all", "N" (N of the timed frames), or a frame list/range
  // The shadow maps against exact visibility (Embree) on the error frames (error_frames), with
  // or without --error: the shadow_* error columns (docs/shadows.md).
  bool shadowError = false;
  std::string outDir = "bench-out";
  Shard shard;
  bool resume = false;     // skip (configuration, frame) rows already in DIR/bench.csv
  bool overwrite = false;  // start over even if DIR/bench.csv exists
  bool calibrate = true;   // measure bandwidth/peak (off: no limit columns)
  CalibrationOptions calibration;
  bool progress = true;     // stderr progress
  bool printTable = true;   // summary table on stdout
  std::string command;      // recorded in bench.json
  std::string description;  // recorded in bench.json (from a --config file)
};

struct BenchRunResult {
  size_t configurations = 0;          // after expansion
  size_t selected = 0;                // in this shard
  size_t skippedRows = 0;             // already present (resume)
  size_t measuredRows = 0;            // written by this run
  std::vector<std::string> failures;  // "config: message" of configurations that failed
  nlohmann::json summaries;           // as in bench.json "summaries"
};

BenchRunResult runBench(const BenchOptions& options);

// The time/frame subset with error: "all", "N" (N of `timed` spread evenly), or a FrameSpec
// range/list intersected with `timed`. Throws ts::Error on a bad spec.
std::vector<int> selectErrorFrames(const std::string& spec, const std::vector<int>& timed);

}  // namespace ts
