#include "bench/bench_run.h"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <set>

#include "bench/bench_frames.h"
#include "bench/bench_measure.h"
#include "bench/bench_resume.h"
#include "bench/bench_stats.h"
#include "bench/bench_sweep_record.h"
#include "bench/calibration_rounds.h"
#include "cl/cl_context.h"
#include "shading/shading_cpu.h"  // TS_SHADE_FLOPS_* (kernels/shading.h)
#include "techniques/math_mode_note.h"
#include "techniques/technique.h"
#include "util/error.h"
#include "util/file_read.h"
#include "util/file_write.h"
#include "util/option_values.h"
#include "util/progress.h"
#include "util/short_text.h"
#include "util/strict_json.h"

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace ts {
namespace {

// The scene-defining part of a configuration (frameKey() without the resolution and the
// rasterizer: one BenchScene serves both rasterizers).
std::string sceneKey(const BenchConfig& c) {
  std::string k;
  for (const auto& d : benchDimensions())
    if (d.affectsFrame && d.name != "resolution" && d.name != "raster")
      k += d.name + "=" + d.get(c) + ";";
  return k;
}

// Refuses bad run options before anything else.
void checkOptions(const BenchOptions& o) {
  checkInteger("--warmup", o.warmup, 0, kMaxWarmup);
  checkInteger("--repeat", o.repeat, 1, kMaxRepeat);
  o.frames.validate();
  selectErrorFrames(o.errorFrames, {0, 1, 2});
  if (o.resume && o.overwrite) throw Error("--resume and --overwrite exclude each other");
}

// One `bench` run; runBench calls its stages in the order they are declared. Everything that
// can be refused (configurations, devices, scenes, the earlier run's files) is refused before
// startFiles() writes anything.
class BenchRunner {
 public:
  explicit BenchRunner(const BenchOptions& o)
      : o_(o),
        csvPath_(o.outDir + "/bench.csv"),
        jsonPath_(o.outDir + "/bench.json"),
        summaryPath_(o.outDir + "/summary.csv") {}

  void selectConfigurations();  // expands the sweep, keeps this shard's configurations
  void checkOutputFiles();      // refuses to replace a run without --resume or --overwrite
  void openDevices();           // one OpenCL context per device (calibrated on first use)
  void loadScenes();            // one BenchScene per scene definition; each entry's frames
  void loadResumeState();       // --resume: the earlier rows this run keeps
  void countPending();          // the (configuration, frame) measurements left to run
  void startFiles();            // bench.csv from its header and kept rows; the plan; the run record
  void measureAll();            // every pending measurement, group by group, frame by frame
  BenchRunResult finish();      // summaries, bench.json, summary.csv, the table

 private:
  ClContext& device(const std::string& spec);  // announced and calibrated on first use
  std::vector<std::vector<BenchEntry*>> frameGroups();
  void createTechniques(const std::vector<BenchEntry*>& group, BenchScene& scene);
  void measureFrame(const std::vector<BenchEntry*>& group, BenchScene& scene, int f);
  json measure(BenchEntry& e, GroupFrame& frame, int f);
  void appendRow(json row);
  void fail(BenchEntry& e, const std::string& what);
  void writeJson(bool finished);

  const BenchOptions& o_;
  const std::string csvPath_, jsonPath_, summaryPath_;
  BenchRunResult result_;
  json sweep_;  // what identifies the sweep (bench_sweep_record.h)
  std::vector<BenchEntry> entries_;
  bool csvExists_ = false;
  std::map<std::string, std::unique_ptr<ClContext>> contexts_;  // by device spec
  std::map<std::string, BenchScene> scenes_;                    // by sceneKey()
  std::set<std::pair<std::string, int>> done_;                  // (config_id, frame) kept
  json rows_ = json::array(), runs_ = json::array();            // bench.json's
  std::vector<std::string> keptLines_;                          // of the earlier bench.csv
  size_t pendingTotal_ = 0;
  std::ofstream csv_;
  json run_;                                         // this run's record
  std::map<std::string, Calibration> calibrations_;  // by device spec
  std::set<std::string> announced_;
  std::set<std::string> mathNotes_;  // printed once per run
  std::optional<Progress> progress_;
  std::ostream& log_ = std::cout;
};

void BenchRunner::selectConfigurations() {
  std::vector<std::string> notes;
  std::vector<BenchConfig> configs = expandSweep(o_.sweep, &notes);
  for (const std::string& note : notes) log_ << "bench: " << note << "\n";
  result_.configurations = configs.size();
  sweep_ =
      sweepRecord(o_.sweep, configs,
                  {o_.frames.text, o_.warmup, o_.repeat, o_.error, o_.errorFrames, o_.calibrate});
  for (size_t i = 0; i < configs.size(); ++i)
    if (o_.shard.selects(i)) {
      BenchEntry e;
      e.index = i;
      e.config = configs[i];
      entries_.push_back(std::move(e));
    }
  result_.selected = entries_.size();
}

void BenchRunner::checkOutputFiles() {
  std::error_code ec;
  csvExists_ = fs::exists(csvPath_, ec);
  if (csvExists_ && !o_.resume && !o_.overwrite)
    throw Error(csvPath_ +
                " exists: pass --resume to continue that run or --overwrite to start over");
  for (const auto& p : {csvPath_, jsonPath_, summaryPath_})
    if (fs::exists(p, ec) && !fs::is_regular_file(p, ec))
      throw Error(p +
                  (fs::is_directory(p, ec) ? ": it is a directory" : " exists and is not a file"));
}

void BenchRunner::openDevices() {
  for (const auto& e : entries_)
    if (!contexts_.count(e.config.device))
      contexts_.emplace(e.config.device, std::make_unique<ClContext>(e.config.device));
}

// Per scene definition: the scene (or imported G-buffer), its rasterizers, and its lights with
// the scene's own ranges (before --light-threshold) for the error reference that every
// configuration of the scene is measured against (src/bench/bench_frames.h).
void BenchRunner::loadScenes() {
  for (auto& e : entries_) {
    std::string key = sceneKey(e.config);
    auto it = scenes_.find(key);
    if (it == scenes_.end())
      it = outOfMemoryAs("loading scene " + e.config.scene,
                         [&] { return scenes_.try_emplace(key, e.config).first; });
    else it->second.check(e.config);
    e.frames = o_.frames.resolve(it->second.pathLength());
    if (o_.error || o_.shadowError) {
      auto ef = selectErrorFrames(o_.errorFrames, e.frames);
      if (o_.error) e.errorFrames.insert(ef.begin(), ef.end());
      if (o_.shadowError) e.shadowErrorFrames.insert(ef.begin(), ef.end());
    }
  }
}

// bench.csv is the record of completed rows, of which only those this run would have written
// itself are kept (bench_resume.h); bench.json gives their full JSON records (a row whose record
// disagrees was edited and is dropped; one without a record, lost when a run was killed between
// the two writes, is rebuilt from the CSV).
void BenchRunner::loadResumeState() {
  if (!csvExists_ || !o_.resume) return;
  std::error_code ec;
  std::map<std::string, ResumeExpectation> expected;
  for (const auto& e : entries_)
    expected[e.config.id()] = {e.config,
                               contexts_.at(e.config.device)->deviceName(),
                               {e.frames.begin(), e.frames.end()},
                               e.errorFrames,
                               e.shadowErrorFrames};
  ResumeScan scan = scanBenchCsv(csvPath_, expected, o_.warmup, o_.repeat);
  std::map<std::pair<std::string, int>, json> recorded;
  if (fs::exists(jsonPath_, ec)) {
    // Cut short (a run killed while writing it) is said and survived; valid JSON that breaks
    // the strict rules (a key twice, deep nesting) was made by hand and is an error.
    const std::string text = readTextFile(jsonPath_, "bench results");
    const json old = json::accept(text) ? parseStrictJson(text, jsonPath_) : json();
    if (!old.is_object()) {
      std::cerr << "tileshade: warning: bench --resume: " << jsonPath_
                << " is not a bench.json; its rows come back from bench.csv, its earlier runs "
                   "are lost\n";
    } else {
      if (old.contains("rows") && old["rows"].is_array())
        for (const auto& r : old["rows"]) {
          if (!r.is_object() || !r.contains("frame") || !r["frame"].is_number_integer()) continue;
          recorded[{jsonTextOf(findKey(r, "config_id")), r["frame"].get<int>()}] = r;
        }
      if (old.contains("runs") && old["runs"].is_array()) runs_ = old["runs"];
    }
  }
  const std::vector<std::string> columns = benchCsvColumns();
  for (const auto& k : scan.kept) {
    std::vector<std::string> fields;
    for (const auto& c : columns) fields.push_back(k.fields.at(c));
    json row = rowFromCsv(k.fields, csvPath_);
    auto rec = recorded.find({k.configId, k.frame});
    if (rec != recorded.end()) {
      std::vector<std::string> fromJson;
      try {
        fromJson = csvFields(benchColumns(), rec->second);
      } catch (const std::exception&) {
      }
      if (fromJson != fields) {
        scan.drop("values that differ from its record in bench.json (edited?)", k.lineNumber);
        continue;
      }
      row = rec->second;
    }
    done_.insert({k.configId, k.frame});
    rows_.push_back(std::move(row));
    keptLines_.push_back(k.line);
  }
  for (const auto& line : scan.describeDrops(csvPath_))
    std::cerr << "tileshade: warning: bench --resume: " << line << "\n";
}

void BenchRunner::countPending() {
  for (auto& e : entries_) {
    std::string id = e.config.id();
    for (int f : e.frames) {
      if (done_.count({id, f})) ++result_.skippedRows;
      else e.pending.insert(f);
    }
    pendingTotal_ += e.pending.size();
  }
}

// bench.csv starts again from its header and the kept rows (never appended after rows that were
// dropped), then grows a row per measurement.
void BenchRunner::startFiles() {
  std::error_code ec;
  fs::create_directories(o_.outDir, ec);
  if (ec) throw Error("cannot create output folder " + o_.outDir + ": " + ec.message());
  if (o_.overwrite)
    for (const auto& p : {csvPath_, jsonPath_, summaryPath_}) fs::remove(p, ec);
  {
    std::string text = csvLine(benchCsvColumns()) + "\n";
    for (const auto& line : keptLines_) text += line + "\n";
    writeFileAtomically(csvPath_, text);
  }
  csv_.open(csvPath_, std::ios::app);
  if (!csv_) throw Error("cannot write " + csvPath_);

  if (o_.printTable) {
    log_ << "bench: " << result_.configurations << " configuration(s)";
    if (o_.shard.count > 1)
      log_ << ", " << result_.selected << " in shard " << o_.shard.index << "/" << o_.shard.count;
    log_ << "; " << pendingTotal_ << " measurement(s) to run";
    if (result_.skippedRows) log_ << ", " << result_.skippedRows << " already in " << csvPath_;
    log_ << "\n";
  }

  run_ = {{"started", nowUtc()},
          {"command", o_.command},
          {"description", o_.description},
          {"frames", o_.frames.text},
          {"warmup", o_.warmup},
          {"repeat", o_.repeat},
          {"error", o_.error},
          {"error_frames", o_.errorFrames},
          {"shadow_error", o_.shadowError},
          {"shard", std::to_string(o_.shard.index) + "/" + std::to_string(o_.shard.count)},
          {"sweep", sweep_},
          {"shade_flops",
           {{"blinn-phong", TS_SHADE_FLOPS_BLINN_PHONG},
            {"metallic-roughness", TS_SHADE_FLOPS_METALLIC_ROUGHNESS}}},
          {"devices", json::array()}};
}

void BenchRunner::writeJson(bool finished) {
  json r = run_;
  if (finished) r["finished"] = nowUtc();
  json all = runs_;
  all.push_back(r);
  json doc = {{"tool", "tileshade bench"},
              {"format_version", 1},
              {"runs", all},
              {"summaries", summarizeRows(rows_)},
              {"rows", rows_}};
  writeFileAtomically(jsonPath_, doc.dump(1) + "\n");
}

// Each device is calibrated once per run, when it is first used (before anything is timed).
ClContext& BenchRunner::device(const std::string& spec) {
  ClContext& cl = *contexts_.at(spec);
  if (!announced_.insert(spec).second) return cl;
  json device = {{"spec", spec.empty() ? "default" : spec},
                 {"name", cl.deviceName()},
                 {"type", cl.info().type},
                 {"compute_units", cl.info().computeUnits}};
  if (o_.calibrate) {
    Calibration c = calibrate(cl, o_.calibration);
    calibrations_[spec] = c;
    device["calibration"] = c.toJson();
    if (o_.printTable)
      log_ << "device: " << cl.deviceName() << "\n"
           << "calibration: " << calibrationText(device["calibration"]) << "\n";
  } else if (o_.printTable) {
    log_ << "device: " << cl.deviceName() << " (not calibrated: no limit columns)\n";
  }
  run_["devices"].push_back(device);
  return cl;
}

void BenchRunner::fail(BenchEntry& e, const std::string& what) {
  e.failed = true;
  e.technique.reset();
  std::string msg = e.config.key() + ": " + what;
  result_.failures.push_back(msg);
  progress_->note("bench: configuration failed: " + msg);
}

// Groups of configurations sharing the host-side frame (scene, lights, resolution), in sweep
// order: each frame is rasterized once for the group, encoded once per layout, referenced once
// per precision.
std::vector<std::vector<BenchEntry*>> BenchRunner::frameGroups() {
  std::vector<std::string> order;
  std::map<std::string, std::vector<BenchEntry*>> groups;
  for (auto& e : entries_) {
    if (e.pending.empty()) continue;
    std::string k = e.config.frameKey();
    if (!groups.count(k)) order.push_back(k);
    groups[k].push_back(&e);
  }
  std::vector<std::vector<BenchEntry*>> out;
  for (const auto& k : order) out.push_back(std::move(groups[k]));
  return out;
}

// The group's techniques on their devices (a configuration that cannot be built fails alone).
void BenchRunner::createTechniques(const std::vector<BenchEntry*>& group, BenchScene& scene) {
  for (BenchEntry* e : group) {
    try {
      ClContext& cl = device(e->config.device);
      e->cl = &cl;
      e->deviceName = cl.deviceName();
      auto cal = calibrations_.find(e->config.device);
      e->calibration = cal == calibrations_.end() ? nullptr : &cal->second;
      double before = cl.compileMs();
      TechniqueConfig tc = e->config.techniqueConfig(scene.features(e->config));
      e->features = tc.features;
      e->technique = createTechnique(e->config.technique, cl, tc);
      e->kernelOptions = tc.kernelOptions();
      e->compileMs = cl.compileMs() - before;
      std::string note = mathModeNote(tc.math, cl.deviceName(), cl.info().type);
      if (!note.empty() && mathNotes_.insert(note).second) progress_->note("bench: note: " + note);
    } catch (const Error& x) {
      fail(*e, x.what());
    } catch (const cl::Error& x) {
      fail(*e, std::string("OpenCL error ") + x.what() + " (" + std::to_string(x.err()) + ")");
    }
  }
}

void BenchRunner::measureAll() {
  progress_.emplace(pendingTotal_, o_.progress);
  for (const auto& group : frameGroups()) {
    BenchScene& scene = scenes_.at(sceneKey(group.front()->config));
    createTechniques(group, scene);
    std::set<int> frames;
    for (BenchEntry* e : group) frames.insert(e->pending.begin(), e->pending.end());
    for (int f : frames) {
      measureFrame(group, scene, f);
      writeJson(false);
    }
    for (BenchEntry* e : group) e->technique.reset();  // free the group's device buffers
  }
  progress_->finish();
}

// Frame `f` for every configuration of the group that still needs it.
void BenchRunner::measureFrame(const std::vector<BenchEntry*>& group, BenchScene& scene, int f) {
  GroupFrame frame(scene, group.front()->config, f);
  for (BenchEntry* e : group) {
    if (!e->pending.count(f)) continue;
    std::string label = e->config.technique + " " + std::to_string(e->config.tileWidth) + "x" +
                        std::to_string(e->config.tileHeight) + " " + toString(e->config.format) +
                        " frame " + std::to_string(f);
    if (e->failed) {
      progress_->step(label + " (failed)");
      continue;
    }
    try {
      appendRow(measure(*e, frame, f));
      e->pending.erase(f);
    } catch (const Error& x) {
      fail(*e, x.what());
    } catch (const cl::Error& x) {
      fail(*e, std::string("OpenCL error ") + x.what() + " (" + std::to_string(x.err()) + ")");
    }
    progress_->step(label);
  }
}

// One configuration on one frame: timed, its error where wanted, as a bench.json row.
json BenchRunner::measure(BenchEntry& e, GroupFrame& frame, int f) {
  const EncodedGBuffer& enc = frame.encoded(e.config.format, e.features);
  TechniqueConfig tc = e.config.techniqueConfig(e.features);
  const PerLightShadowMaps* perLight =
      e.config.shadowStorage == ShadowStorage::PerLight ? frame.perLightShadows() : nullptr;
  TimedFrame m = timeFrame(e, enc, frame.prepared(), frame.forward(), frame.sampleGBuffers(),
                           perLight, o_.warmup, o_.repeat);
  FrameErrors errors;
  if (e.errorFrames.count(f)) errors = measureErrors(e, frame, enc, tc, m.r.image);
  if (e.shadowErrorFrames.count(f)) measureShadowError(frame, m.r.image, errors);
  return measurementRow(e, frame, f, enc, m, errors, o_.warmup, o_.repeat);
}

// The row to bench.csv (flushed: the record a killed run resumes from) and to bench.json's rows.
void BenchRunner::appendRow(json row) {
  csv_ << csvLine(csvFields(benchColumns(), row)) << "\n";
  flushChecked(csv_, csvPath_);
  rows_.push_back(std::move(row));
  ++result_.measuredRows;
}

BenchRunResult BenchRunner::finish() {
  result_.summaries = summarizeRows(rows_);
  writeJson(true);
  writeFileAtomically(summaryPath_, summaryCsvText(result_.summaries));
  if (o_.printTable) {
    printSummaryTable(result_.summaries, log_);
    json runs = runs_;
    runs.push_back(run_);
    printCalibrations(runs, log_);
    log_ << "wrote " << csvPath_ << ", " << jsonPath_ << ", " << summaryPath_ << "\n";
  }
  return result_;
}

}  // namespace

std::vector<int> selectErrorFrames(const std::string& spec, const std::vector<int>& timed) {
  std::string s = spec;
  s.erase(std::remove_if(s.begin(), s.end(), [](unsigned char c) { return std::isspace(c); }),
          s.end());
  if (s.empty() || s == "all") return timed;
  if (std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isdigit(c); }) &&
      s.size() < 7) {
    size_t n = std::stoul(s);
    if (n < 1) throw Error("--error-frames: expected at least 1, got '" + shortText(spec) + "'");
    if (n >= timed.size()) return timed;
    std::vector<int> out;
    for (size_t k = 0; k < n; ++k) out.push_back(timed[k * timed.size() / n]);
    return out;
  }
  FrameSpec f{spec};
  std::vector<int> listed;
  try {
    listed = f.resolve(1 << 20);
  } catch (const Error&) {
    throw Error(
        "--error-frames: expected all, N (that many of the timed frames), A:B[:S] or "
        "a;b;c, got '" +
        shortText(spec) + "'");
  }
  std::vector<int> out;
  for (int t : timed)
    if (std::binary_search(listed.begin(), listed.end(), t)) out.push_back(t);
  return out;
}

BenchRunResult runBench(const BenchOptions& o) {
  checkOptions(o);
  BenchRunner run(o);
  run.selectConfigurations();
  run.checkOutputFiles();
  run.openDevices();
  run.loadScenes();
  run.loadResumeState();
  run.countPending();
  run.startFiles();
  run.measureAll();
  return run.finish();
}

}  // namespace ts
