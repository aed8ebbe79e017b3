#pragma once
// The benchmark's configuration space. A sweep gives a list of values per dimension; its cartesian
// product is the list of configurations (one BenchConfig each). Adding a dimension = one field in
// PipelineOptions (render/pipeline_options.h) + one entry in benchDimensions() (bench_config.cpp):
// the command-line option, the JSON config key, the CSV column and the configuration key all come
// from that entry, and a knob's values from its name table (util/enum_names.h).
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "render/pipeline_options.h"
#include "util/option_values.h"

namespace ts {

// One point of the sweep: a pipeline (PipelineOptions: techniqueConfig(), sceneOptions()) and
// the technique that runs it.
struct BenchConfig : PipelineOptions {
  std::string technique = "tiled";

  // "device=…;scene=…;…" over every dimension, canonical values: equal keys = same configuration.
  std::string key() const;
  // The part of key() that decides the host-side frame (scene, lights, resolution): the G-buffer
  // is rasterized once per frame for all configurations sharing it (precision is encoded after).
  std::string frameKey() const;
  // Short stable id (hex of a 64-bit FNV-1a hash of key()).
  std::string id() const;
};

struct BenchDimension {
  std::string name;    // JSON key and CSV column (snake_case); option --name with '-'
  std::string option;  // the option when it differs from --name (e.g. --lights)
  std::string help;
  std::string defaultValue;   // canonical string of BenchConfig's default
  bool affectsFrame = false;  // part of frameKey()
  // A dimension added after bench.csv files were written: in key() (so in id()) only at a value
  // other than its default, so that the configurations of earlier sweeps keep their ids.
  bool keyedOffDefault = false;
  // Parses and validates a value into the config; throws ts::Error with one clear line.
  std::function<void(BenchConfig&, const std::string&)> set;
  // Canonical string of the config's value (what set() accepts).
  std::function<std::string(const BenchConfig&)> get;

  std::string optionName() const;  // "--light-count"
  // Whether a JSON config key names this dimension: the name or the option without dashes.
  bool matchesKey(const std::string& key) const;
};

const std::vector<BenchDimension>& benchDimensions();
// By name, or by option stem ("lights", "light-count"); throws ts::Error listing the names.
const BenchDimension& findDimension(const std::string& name);

// Values per dimension by name; a dimension left out keeps BenchConfig's default.
struct BenchSweep {
  std::map<std::string, std::vector<std::string>> values;
  void set(const std::string& dimension, std::vector<std::string> list);  // validates the name
};

// The cartesian product, in a fixed order (the first dimension varies slowest), duplicates (same
// key()) removed. "all" as a technique expands to every registered technique. Every value is
// validated before anything runs: ts::Error naming the option and the bad value.
// At most kMaxBenchConfigurations configurations (ts::Error beyond: a config file of long lists
// would otherwise exhaust memory before anything runs).
constexpr size_t kMaxBenchConfigurations = 100000;
// `notes`, when given, receives a line per technique whose per-light shadow-storage
// configurations were left out (only deferred and deferred-stencil reuse one map per light; a
// sweep with nothing else left is refused).
std::vector<BenchConfig> expandSweep(const BenchSweep& sweep,
                                     std::vector<std::string>* notes = nullptr);

// parseTileSize, parseResolution and splitList, shared with `render`, are in util/option_values.h.

// Which frames of the camera path are timed:
//   "A:B" or "A:B:S"   frames A, A+S, … below B (half-open, like Python's range)
//   "N"                N frames spread evenly over the scene's camera path (0..N-1 if it is
//                      shorter than N: frame k uses camera k mod path length)
//   "all"              every frame of the path
//   "a;b;c"            exactly these frames
struct FrameSpec {
  std::string text = "8";
  void validate() const;                           // throws ts::Error
  std::vector<int> resolve(int pathLength) const;  // sorted, unique
};

// --shard k/n: configuration i runs in shard k when i mod n == k (0 <= k < n).
struct Shard {
  int index = 0, count = 1;
  static Shard parse(const std::string& s);  // "k/n"; throws ts::Error
  bool selects(size_t configIndex) const { return int(configIndex % size_t(count)) == index; }
};

}  // namespace ts
