// `tileshade bench`: the options (one per sweep dimension, from benchDimensions(), plus the run
// options), an optional JSON config holding the same fields, then runBench().
#include "bench/bench_cli.h"

#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>

#include <nlohmann/json.hpp>

#include "bench/bench_config.h"
#include "bench/bench_merge.h"
#include "bench/bench_run.h"
#include "util/error.h"
#include "util/file_read.h"
#include "util/short_text.h"
#include "util/strict_json.h"
#include "util/option_values.h"

namespace ts {
namespace {

struct BenchCliState {
  std::map<std::string, std::vector<std::string>> dims;
  std::map<std::string, CLI::Option*> dimOptions;
  std::string config, frames = "8", errorFrames = "all", out = "bench-out", shard = "0/1";
  int warmup = 1, repeat = 1, calibMiB = 256;
  bool error = false, shadowError = false, resume = false, overwrite = false, noCalibrate = false,
       quiet = false, list = false;
  CLI::Option* shadowErrorOpt = nullptr;
  CLI::Option *framesOpt = nullptr, *warmupOpt = nullptr, *repeatOpt = nullptr, *errorOpt = nullptr,
              *errorFramesOpt = nullptr, *calibOpt = nullptr;
};

std::string commandLine() {
  std::ifstream in("/proc/self/cmdline", std::ios::binary);
  std::string all((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>()), s;
  std::string arg;
  for (char c : all) {
    if (c) {
      arg += c;
      continue;
    }
    bool quote = arg.empty() || arg.find_first_of(" \t\"'$") != std::string::npos;
    s += (s.empty() ? "" : " ") + (quote ? "'" + arg + "'" : arg);
    arg.clear();
  }
  return s;
}

std::vector<std::string> jsonValues(const std::string& key, const nlohmann::json& v) {
  std::vector<std::string> out;
  auto one = [&](const nlohmann::json& x) {
    if (x.is_string()) out.push_back(x.get<std::string>());
    else if (x.is_boolean()) out.push_back(switchNames().name(x.get<bool>()));  // depth_split
    else if (x.is_number_integer()) out.push_back(std::to_string(x.get<long long>()));
    else if (x.is_number()) {
      std::ostringstream s;
      s << x.get<double>();
      out.push_back(s.str());
    } else {
      throw Error("bench config: '" + shortText(key) +
                  "' expects strings, numbers or booleans, got " + shortText(x.dump()));
    }
  };
  if (v.is_array()) {
    for (const auto& x : v) one(x);
  } else {
    one(v);
  }
  return out;
}

// Applies the --config file; command-line options that were given win.
void applyConfigFile(BenchCliState& s, BenchOptions& o) {
  const std::string text = readTextFile(s.config, "bench config");
  std::map<std::string, const CLI::Option*> runOptions = {{"frames", s.framesOpt},
                                                          {"warmup", s.warmupOpt},
                                                          {"repeat", s.repeatOpt},
                                                          {"error", s.errorOpt},
                                                          {"error_frames", s.errorFramesOpt},
                                                          {"shadow_error", s.shadowErrorOpt},
                                                          {"calib_mib", s.calibOpt}};
  applyBenchConfig(text, s.config, o, [&](const std::string& field) {
    auto run = runOptions.find(field);
    if (run != runOptions.end()) return run->second->count() > 0;
    return s.dimOptions.at(field)->count() > 0;
  });
}

void runCommand(BenchCliState& s) {
  BenchOptions o;
  o.frames.text = s.frames;
  o.warmup = s.warmup;
  o.repeat = s.repeat;
  o.error = s.error;
  o.errorFrames = s.errorFrames;
  o.shadowError = s.shadowError;
  o.outDir = s.out;
  o.shard = Shard::parse(s.shard);
  o.resume = s.resume;
  o.overwrite = s.overwrite;
  o.calibrate = !s.noCalibrate;
  checkInteger("--calib-mib", s.calibMiB, 1, kMaxCalibMiB);
  o.calibration.copyBytes = size_t(s.calibMiB) << 20;
  o.progress = !s.quiet;
  o.command = commandLine();
  for (const auto& [name, values] : s.dims)
    if (s.dimOptions.at(name)->count()) o.sweep.set(name, values);
  if (!s.config.empty()) applyConfigFile(s, o);

  if (s.list) {
    auto configs = expandSweep(o.sweep);
    o.frames.validate();
    std::cout << configs.size() << " configuration(s); frames '" << o.frames.text << "'\n";
    for (size_t i = 0; i < configs.size(); ++i)
      std::cout << i << (o.shard.selects(i) ? " * " : "   ") << configs[i].id() << "  "
                << configs[i].key() << "\n";
    if (o.shard.count > 1)
      std::cout << "* = in shard " << o.shard.index << "/" << o.shard.count << "\n";
    return;
  }
  BenchRunResult r = runBench(o);
  if (!r.failures.empty())
    throw Error(std::to_string(r.failures.size()) +
                " configuration(s) failed (listed above); the "
                "others were written");
}

// `bench merge OUT SHARD_DIR…` (bench_merge.h); bench's own options do not apply to it.
CLI::App* addMergeCommand(CLI::App& bench, BenchMergeOptions& m) {
  CLI::App* merge = bench.add_subcommand(
      "merge",
      "join the output folders of the shards of one sweep (bench --shard k/n) into OUT as one "
      "unsharded run writes it, after checking that they are every shard of the same sweep, each "
      "once (see bench/README.md)");
  merge->add_option("OUT", m.outDir, "output folder: bench.csv, bench.json, summary.csv")
      ->required();
  merge->add_option("SHARD_DIR", m.shardDirs, "the shards' --out folders, in any order")
      ->required();
  merge->add_flag("--overwrite", m.overwrite, "replace OUT's results if it has some");
  return merge;
}

void runMerge(CLI::App& bench, BenchMergeOptions& m) {
  for (const CLI::Option* opt : bench.get_options())
    if (opt->count() && opt->get_name() != "--help")
      throw Error("bench merge: " + opt->get_name() +
                  " is an option of a sweep; give it to the shards' bench runs, not to merge");
  m.command = commandLine();
  mergeBenchShards(m);
}

}  // namespace

void applyBenchConfig(const std::string& text, const std::string& source, BenchOptions& o,
                      const std::function<bool(const std::string&)>& givenOnCommandLine) {
  nlohmann::json j =
      parseStrictJson(text, "bench config " + shortText(source, 200), JsonComments::Allowed);
  if (!j.is_object()) throw Error("bench config " + source + " is not a JSON object");
  for (auto it = j.begin(); it != j.end(); ++it) {
    const std::string& key = it.key();
    const auto& v = it.value();
    auto want = [&](bool ok, const char* what) {
      if (!ok) throw Error("bench config " + source + ": '" + shortText(key) + "' expects " + what);
    };
    // An integer field within lo..hi (a JSON integer, not truncated to int).
    auto integer = [&](long long lo, long long hi) {
      want(v.is_number_integer(), "an integer");
      bool inRange = v.is_number_unsigned()
                         ? v.get<unsigned long long>() <= (unsigned long long)hi &&
                               (lo <= 0 || v.get<unsigned long long>() >= (unsigned long long)lo)
                         : v.get<long long>() >= lo && v.get<long long>() <= hi;
      if (!inRange)
        throw Error("bench config " + source + ": '" + shortText(key) + "' expects an integer in " +
                    std::to_string(lo) + ".." + std::to_string(hi) + ", got " +
                    shortText(v.dump()));
      return v.is_number_unsigned() ? (long long)v.get<unsigned long long>() : v.get<long long>();
    };
    auto frameSpec = [&]() {
      want(v.is_string() || v.is_number_integer(), "a frame spec string");
      return v.is_string() ? v.get<std::string>() : std::to_string(integer(0, 10000000));
    };
    if (key == "description") {
      want(v.is_string(), "a string");
      o.description = v.get<std::string>();
    } else if (key == "comment" || key == "notes") {
      // free text
    } else if (key == "frames") {
      std::string f = frameSpec();
      if (!givenOnCommandLine(key)) o.frames.text = f;
    } else if (key == "warmup") {
      int n = int(integer(0, kMaxWarmup));
      if (!givenOnCommandLine(key)) o.warmup = n;
    } else if (key == "repeat") {
      int n = int(integer(1, kMaxRepeat));
      if (!givenOnCommandLine(key)) o.repeat = n;
    } else if (key == "error") {
      want(v.is_boolean(), "true or false");
      if (!givenOnCommandLine(key)) o.error = v.get<bool>();
    } else if (key == "error_frames") {
      std::string f = frameSpec();
      if (!givenOnCommandLine(key)) o.errorFrames = f;
    } else if (key == "shadow_error") {
      want(v.is_boolean(), "true or false");
      if (!givenOnCommandLine(key)) o.shadowError = v.get<bool>();
    } else if (key == "calib_mib") {
      size_t mib = size_t(integer(1, kMaxCalibMiB));
      if (!givenOnCommandLine(key)) o.calibration.copyBytes = mib << 20;
    } else {
      std::string known;
      const BenchDimension* dim = nullptr;
      for (const auto& d : benchDimensions()) {
        known += d.name + ", ";
        if (d.matchesKey(key)) dim = &d;
      }
      if (!dim)
        throw Error("bench config " + source + ": unknown field '" + shortText(key) +
                    "' (known: " + known +
                    "frames, warmup, repeat, error, error_frames, shadow_error, calib_mib, "
                    "description)");
      if (!givenOnCommandLine(dim->name)) o.sweep.set(dim->name, jsonValues(key, v));
    }
  }
}

CliCommand addBenchCommand(CLI::App& app) {
  auto state = std::make_shared<BenchCliState>();
  BenchCliState& s = *state;
  CLI::App* cmd = app.add_subcommand(
      "bench",
      "sweep techniques x tile sizes x light sets x precisions x resolutions x devices over a "
      "scene's camera path; per-kernel times, counters, error and % of the device limit to "
      "CSV/JSON (see bench/README.md)");
  for (const auto& d : benchDimensions()) {
    auto* opt = cmd->add_option(d.optionName(), s.dims[d.name],
                                d.help + " [default: " + d.defaultValue + "]")
                    ->delimiter(',')
                    ->group("Sweep (comma lists; the cartesian product is run)");
    s.dimOptions[d.name] = opt;
  }
  const char* run = "Run";
  cmd->add_option("--config", s.config,
                  "JSON file with the same fields (dimension names as keys, "
                  "lists or single values; frames, warmup, repeat, error, "
                  "error_frames, shadow_error); command-line options win")
      ->group(run);
  s.framesOpt = cmd->add_option("--frames", s.frames,
                                "timed frames of the camera path: A:B[:S] (half-open range), N "
                                "(N frames spread over the path), all, or a;b;c")
                    ->capture_default_str()
                    ->group(run);
  s.warmupOpt = cmd->add_option("--warmup", s.warmup,
                                "untimed renders of each configuration before its first timed "
                                "frame")
                    ->capture_default_str()
                    ->group(run);
  s.repeatOpt = cmd->add_option("--repeat", s.repeat,
                                "timed renders per frame; the row keeps the one with the median "
                                "kernel total")
                    ->capture_default_str()
                    ->group(run);
  s.errorOpt = cmd->add_flag("--error", s.error,
                             "error against the double reference (max abs, RMSE, PSNR, max rel "
                             "peak, quantiles); expensive on a CPU")
                   ->group(run);
  s.errorFramesOpt = cmd->add_option("--error-frames", s.errorFrames,
                                     "with --error or --shadow-error: all, N (N of the timed "
                                     "frames) or a frame range/list")
                         ->capture_default_str()
                         ->group(run);
  s.shadowErrorOpt =
      cmd->add_flag("--shadow-error", s.shadowError,
                    "the shadow maps against exact visibility (Embree ray queries) on the error "
                    "frames: shadow_wrong_pct (the (pixel, light) pairs the maps get wrong), "
                    "shadow_err_max_rel_peak/rmse/p99 (the image against the one shaded with "
                    "exact visibility, of its peak), shadow_err_psnr_db; expensive "
                    "(docs/shadows.md)")
          ->group(run);
  cmd->add_option("--out", s.out, "output folder: bench.csv, bench.json, summary.csv")
      ->capture_default_str()
      ->group(run);
  cmd->add_option("--shard", s.shard,
                  "k/n (n <= 1000000): run configuration i only when i mod n == k")
      ->capture_default_str()
      ->group(run);
  cmd->add_flag(
         "--resume", s.resume,
         "skip (configuration, frame) rows already in OUT/bench.csv; rows this run would not "
         "write (truncated, edited, another sweep's) are dropped and counted on stderr")
      ->group(run);
  cmd->add_flag("--overwrite", s.overwrite, "start over even if OUT/bench.csv exists")->group(run);
  cmd->add_flag("--no-calibrate", s.noCalibrate,
                "skip the bandwidth/peak calibration (no limit columns)")
      ->group(run);
  s.calibOpt =
      cmd->add_option("--calib-mib", s.calibMiB, "size of each buffer of the copy calibration")
          ->capture_default_str()
          ->group(run);
  cmd->add_flag("--quiet", s.quiet, "no progress on stderr (failures are still reported)")
      ->group(run);
  cmd->add_flag("--list", s.list, "print the expanded configurations (and the shard's) and exit")
      ->group(run);
  auto mergeOptions = std::make_shared<BenchMergeOptions>();
  CLI::App* merge = addMergeCommand(*cmd, *mergeOptions);
  return {cmd, [state, cmd, merge, mergeOptions] {
            if (*merge) runMerge(*cmd, *mergeOptions);
            else runCommand(*state);
          }};
}

}  // namespace ts
