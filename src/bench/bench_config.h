#pragma once
// The benchmark's configuration space. A sweep gives a list of values per dimension; its cartesian
// product is the list of configurations (one BenchConfig each). Adding a dimension = one field in
// BenchConfig + one entry in benchDimensions() (bench_config.cpp): the command-line option, the
// JSON config key, the CSV column and the configuration key all come from that entry.
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "gbuffer/gbuffer_layout.h"
#include "scene/scene_loader.h"
#include "techniques/technique.h"
#include "util/option_values.h"

namespace ts {

// One point of the sweep.
struct BenchConfig {
  std::string device;               // "" = default (see ClContext)
  std::string scene = "builtin:street";
  std::string lightSet;             // "" = the scene's default set
  int lightCount = -1;              // -1 = the set's own count
  float lightRange = 0.0f;          // > 0 overrides every light's range
  float lightThreshold = 0.0f;      // > 0: ranges from the attenuation threshold
  uint32_t seed = 1;
  std::string technique = "tiled";
  int tileWidth = 16, tileHeight = 16;
  GBufferFormat format = GBufferFormat::FP32;
  int width = 1280, height = 720;
  std::string culling = "rect";
  std::string math = "precise";
  int clusterSlices = 16;
  int lanes = 0;                    // TechniqueConfig::lanes; 0 = auto
  std::string raster = "software";  // rasterizer of the G-buffer: software or gl
  std::string variant;              // built-in scene variants (scene_loader.h), "" = none
  std::string shadingModel = "auto";  // auto, blinn-phong, metallic-roughness
  std::string features = "auto";   // auto, general, or a list (chooseFeatures)
  std::string spotCulling = "cone"; // cone, bound-sphere, range-sphere

  // Everything but the features, which depend on the scene (BenchScene::features).
  TechniqueConfig techniqueConfig() const;
  SceneOptions sceneOptions() const;
  // "device=…;scene=…;…" over every dimension, canonical values: equal keys = same configuration.
  std::string key() const;
  // The part of key() that decides the host-side frame (scene, lights, resolution): the G-buffer
  // is rasterized once per frame for all configurations sharing it (precision is encoded after).
  std::string frameKey() const;
  // Short stable id (hex of a 64-bit FNV-1a hash of key()).
  std::string id() const;
};

struct BenchDimension {
  std::string name;          // JSON key and CSV column (snake_case); option --name with '-'
  std::string option;        // the option when it differs from --name (e.g. --lights)
  std::string help;
  std::string defaultValue;  // canonical string of BenchConfig's default
  bool affectsFrame = false; // part of frameKey()
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
std::vector<BenchConfig> expandSweep(const BenchSweep& sweep);

// parseTileSize, parseResolution and splitList, shared with `render`, are in util/option_values.h.

// Which frames of the camera path are timed:
//   "A:B" or "A:B:S"   frames A, A+S, … below B (half-open, like Python's range)
//   "N"                N frames spread evenly over the scene's camera path (0..N-1 if it is
//                      shorter than N: frame k uses camera k mod path length)
//   "all"              every frame of the path
//   "a;b;c"            exactly these frames
struct FrameSpec {
  std::string text = "8";
  void validate() const;                            // throws ts::Error
  std::vector<int> resolve(int pathLength) const;   // sorted, unique
};

// --shard k/n: configuration i runs in shard k when i mod n == k (0 <= k < n).
struct Shard {
  int index = 0, count = 1;
  static Shard parse(const std::string& s);  // "k/n"; throws ts::Error
  bool selects(size_t configIndex) const { return int(configIndex % size_t(count)) == index; }
};

}  // namespace ts
