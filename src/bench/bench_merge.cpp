#include "bench/bench_merge.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <map>
#include <tuple>

#include "bench/bench_columns.h"
#include "bench/bench_config.h"
#include "bench/bench_resume.h"
#include "bench/bench_stats.h"
#include "bench/bench_summary.h"
#include "bench/bench_sweep_record.h"
#include "bench/calibration_rounds.h"
#include "util/error.h"
#include "util/file_read.h"
#include "util/file_write.h"
#include "util/short_text.h"
#include "util/strict_json.h"

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace ts {
namespace {

const char* const kWhat = "bench merge: ";

[[noreturn]] void refuse(const std::string& why) { throw Error(kWhat + why); }

std::string shardText(const Shard& s) {
  return std::to_string(s.index) + "/" + std::to_string(s.count);
}

// One shard's output folder as its last run (the one that finished it) recorded it.
struct ShardFolder {
  std::string dir;  // as given, without trailing slashes
  json doc;         // its bench.json
  json lastRun;     // doc["runs"]'s last record
  Shard shard;
  SweepRunOptions runOptions;
  std::string hash;  // of its sweep record
};

std::string withoutTrailingSlashes(std::string dir) {
  while (dir.size() > 1 && dir.back() == '/') dir.pop_back();
  return dir;
}

// A bench --out folder with a finished run that records its sweep; refused otherwise.
ShardFolder readShardFolder(const std::string& given) {
  ShardFolder f;
  f.dir = withoutTrailingSlashes(given);
  std::error_code ec;
  if (!fs::exists(f.dir, ec)) refuse(f.dir + ": no such folder");
  if (!fs::is_directory(f.dir, ec)) refuse(f.dir + " is a file, not a bench --out folder");
  const std::string csv = f.dir + "/bench.csv", jsonPath = f.dir + "/bench.json";
  if (!fs::exists(csv, ec)) refuse(f.dir + " has no bench.csv (not a bench --out folder)");
  if (!fs::exists(jsonPath, ec))
    refuse(f.dir + " has bench.csv but no bench.json, which records its sweep");
  f.doc = readJsonFile(jsonPath, "bench results");
  const json* runs = findKey(f.doc, "runs");
  if (!runs || !runs->is_array() || runs->empty() || !findKey(f.doc, "rows") ||
      !f.doc["rows"].is_array())
    refuse(jsonPath + " is not a bench.json (no runs or rows)");
  f.lastRun = runs->back();
  if (!findKey(f.lastRun, "finished"))
    refuse(f.dir + ": its run did not finish (bench --resume with its options and --out " + f.dir +
           " completes it)");
  const json* sweep = findKey(f.lastRun, "sweep");
  if (!sweep)
    refuse(jsonPath +
           " records no sweep (written by a tileshade before bench merge): run the "
           "shard again, or concatenate the bench.csv files for plot.py");
  const json* hash = findKey(*sweep, "hash");
  if (!hash || !hash->is_string()) refuse(jsonPath + ": its sweep record has no hash");
  f.hash = hash->get<std::string>();
  f.runOptions = SweepRunOptions::fromRun(f.lastRun, kWhat + jsonPath);
  const json* shard = findKey(f.lastRun, "shard");
  if (!shard || !shard->is_string()) refuse(jsonPath + ": its run record has no shard");
  try {
    f.shard = Shard::parse(shard->get<std::string>());
  } catch (const Error&) {
    refuse(jsonPath + ": its run record's shard '" + shortText(shard->dump()) + "' is not k/n");
  }
  return f;
}

// Why shard folder `b` is not of `a`'s sweep, in a few words ("" when both record one sweep).
std::string sweepDifference(const ShardFolder& a, const ShardFolder& b) {
  if (a.hash == b.hash) return "";
  auto fa = a.runOptions.fields(), fb = b.runOptions.fields();
  for (const auto& field : fa) {
    // A named reference, not a structured binding: C++17 lambdas cannot capture those (clang).
    const std::string &name = field.first, &value = field.second;
    auto other = std::find_if(fb.begin(), fb.end(), [&](const auto& p) { return p.first == name; });
    std::string theirs = other == fb.end() ? "(none)" : other->second;
    if (theirs != value)
      return name + " '" + shortText(theirs) + "' where " + a.dir + " has '" + shortText(value) +
             "'";
  }
  const json &da = a.lastRun["sweep"], &db = b.lastRun["sweep"];
  if (da.value("configurations", json()) != db.value("configurations", json()))
    return shortText(db.value("configurations", json()).dump()) + " configuration(s) where " +
           a.dir + " has " + shortText(da.value("configurations", json()).dump());
  const json dimsA = da.value("dimensions", json::object()),
             dimsB = db.value("dimensions", json::object());
  for (const auto& dim : benchDimensions()) {
    json va = dimsA.value(dim.name, json()), vb = dimsB.value(dim.name, json());
    if (va != vb)
      return dim.optionName() + " " + shortText(vb.is_null() ? "(default)" : vb.dump()) +
             " where " + a.dir + " has " + shortText(va.is_null() ? "(default)" : va.dump());
  }
  return "other configurations (sweep hash " + b.hash + " where " + a.dir + " has " + a.hash + ")";
}

// The folders sorted by shard index, after checking that they are every shard of one split of
// one sweep, each once.
std::vector<ShardFolder> checkShardSet(std::vector<ShardFolder> folders) {
  const ShardFolder& first = folders.front();
  const int count = first.shard.count;
  for (const auto& f : folders) {
    std::string why = sweepDifference(first, f);
    if (!why.empty()) refuse(f.dir + " is a shard of another sweep than " + first.dir + ": " + why);
    if (f.shard.count != first.shard.count)
      refuse(f.dir + " is shard " + shardText(f.shard) + ", another split of the sweep than " +
             first.dir + "'s " + shardText(first.shard));
  }
  std::sort(folders.begin(), folders.end(), [](const ShardFolder& a, const ShardFolder& b) {
    return a.shard.index < b.shard.index;
  });
  for (size_t i = 1; i < folders.size(); ++i)
    if (folders[i].shard.index == folders[i - 1].shard.index) {
      std::error_code ec;
      if (fs::equivalent(folders[i].dir, folders[i - 1].dir, ec))
        refuse(folders[i].dir + " is given twice (shard " + shardText(folders[i].shard) + ")");
      refuse(folders[i - 1].dir + " and " + folders[i].dir + " are both shard " +
             shardText(folders[i].shard));
    }
  for (int k = 0, at = 0; k < count; ++k) {
    if (at < int(folders.size()) && folders[at].shard.index == k) {
      ++at;
      continue;
    }
    refuse("shard " + std::to_string(k) + "/" + std::to_string(count) + " is missing (" +
           std::to_string(folders.size()) + " of " + std::to_string(count) +
           " shard folders given)");
  }
  return folders;
}

// The sweep's configurations, expanded again from the recorded dimensions; the hash says they
// are the ones the shards ran (another tileshade version may expand them otherwise).
std::vector<BenchConfig> sweepConfigurations(const ShardFolder& f) {
  const std::string source = kWhat + f.dir + "/bench.json";
  std::vector<BenchConfig> configs;
  try {
    configs = expandSweep(sweepFromRecord(f.lastRun["sweep"].value("dimensions", json()), source));
  } catch (const Error& e) {
    refuse(f.dir + "/bench.json: its sweep does not expand here (" + e.what() + ")");
  }
  if (sweepHash(configs, f.runOptions) != f.hash)
    refuse(f.dir +
           "/bench.json: its sweep expands to other configurations here than it ran "
           "(written by another tileshade version?)");
  return configs;
}

// A merged row with where it came from and where one unsharded run writes it.
struct MergedRow {
  std::tuple<size_t, int, size_t> order;  // (frame group, frame, configuration index)
  json record;
  std::string line;  // "DIR/bench.csv line N", for refusals
};

class Merger {
 public:
  explicit Merger(const std::vector<BenchConfig>& configs) : configs_(configs) {
    // An unsharded run measures frame groups (BenchConfig::frameKey) in the order of their first
    // configuration, each frame of a group in turn, the group's configurations in sweep order.
    std::map<std::string, size_t> groupOf;
    for (size_t i = 0; i < configs.size(); ++i) {
      auto g = groupOf.emplace(configs[i].frameKey(), groupOf.size()).first->second;
      index_[configs[i].id()] = {i, g};
    }
  }

  void addShard(const ShardFolder& f);
  json rowsInRunOrder();

 private:
  const std::vector<BenchConfig>& configs_;
  std::map<std::string, std::pair<size_t, size_t>> index_;   // config_id -> (index, frame group)
  std::map<std::pair<std::string, int>, std::string> seen_;  // (config_id, frame) -> its line
  std::vector<MergedRow> rows_;
};

void Merger::addShard(const ShardFolder& f) {
  const std::string csv = f.dir + "/bench.csv";
  std::map<std::pair<std::string, int>, const json*> recorded;  // bench.json's rows
  for (const auto& r : f.doc["rows"])
    if (r.is_object() && r.contains("frame") && r["frame"].is_number_integer())
      recorded[{jsonTextOf(findKey(r, "config_id")), r["frame"].get<int>()}] = &r;
  const std::vector<std::string> columns = benchCsvColumns();
  for (BenchCsvRecord& record :
       readBenchCsv(csv, "merge the shards with the tileshade that ran them")) {
    const std::string where = csv + " line " + std::to_string(record.lineNumber);
    if (!record.malformed.empty()) refuse(where + ": " + record.malformed);
    for (const auto& column : benchColumns())
      if (!wellTyped(column, record.fields.at(column.name)))
        refuse(where + ": " + column.name + " is missing or not of its type");
    const std::string id = record.fields.at("config_id");
    auto it = index_.find(id);
    if (it == index_.end())
      refuse(where + ": configuration " + shortText(id) + " is not in the sweep");
    const auto [index, group] = it->second;
    if (!f.shard.selects(index))
      refuse(where + ": configuration " + id + " is not one of shard " + shardText(f.shard) + "'s");
    for (const auto& d : benchDimensions())
      if (record.fields.at(d.name) != d.get(configs_[index]))
        refuse(where + ": " + d.name + " '" + shortText(record.fields.at(d.name)) +
               "' is not configuration " + id + "'s (edited?)");
    if (record.fields.at("warmup") != std::to_string(f.runOptions.warmup) ||
        record.fields.at("repeat") != std::to_string(f.runOptions.repeat))
      refuse(where + ": measured with another --warmup or --repeat than the sweep's");
    const int frame = int(std::strtol(record.fields.at("frame").c_str(), nullptr, 10));
    auto twice = seen_.emplace(std::make_pair(id, frame), where);
    if (!twice.second)
      refuse("configuration " + id + " frame " + std::to_string(frame) +
             " is there twice: " + twice.first->second + " and " + where);
    // Its full record from bench.json (kernel launch counts are not in the CSV), when the two
    // agree; rebuilt from the CSV when a killed run lost it.
    json row;
    auto rec = recorded.find({id, frame});
    if (rec != recorded.end()) {
      std::vector<std::string> fields, fromJson;
      for (const auto& c : columns) fields.push_back(record.fields.at(c));
      try {
        fromJson = csvFields(benchColumns(), *rec->second);
      } catch (const std::exception&) {
      }
      if (fromJson != fields)
        refuse(where + ": values that differ from its record in " + f.dir +
               "/bench.json (edited?)");
      row = *rec->second;
    } else {
      row = rowFromCsv(record.fields, csv);
    }
    rows_.push_back({{group, frame, index}, std::move(row), where});
  }
}

json Merger::rowsInRunOrder() {
  std::stable_sort(rows_.begin(), rows_.end(),
                   [](const MergedRow& a, const MergedRow& b) { return a.order < b.order; });
  json rows = json::array();
  for (auto& r : rows_) rows.push_back(std::move(r.record));
  return rows;
}

// OUT must not be a shard folder, nor a file, nor hold results unless overwrite.
void checkOutFolder(const BenchMergeOptions& o, const std::vector<ShardFolder>& shards) {
  std::error_code ec;
  if (fs::exists(o.outDir, ec) && !fs::is_directory(o.outDir, ec))
    refuse("OUT " + o.outDir + " is a file, not a folder");
  for (const auto& s : shards)
    if (fs::exists(o.outDir, ec) && fs::equivalent(o.outDir, s.dir, ec))
      refuse("OUT " + o.outDir + " is the shard folder " + s.dir + "; merge into another folder");
  for (const char* name : {"bench.csv", "bench.json", "summary.csv"}) {
    const std::string p = o.outDir + "/" + name;
    if (!fs::exists(p, ec)) continue;
    if (!fs::is_regular_file(p, ec)) refuse(p + " exists and is not a file");
    if (!o.overwrite) refuse(p + " exists: pass --overwrite to replace it");
  }
}

}  // namespace

BenchMergeResult mergeBenchShards(const BenchMergeOptions& o) {
  if (o.shardDirs.empty()) refuse("no shard folders given");
  std::vector<ShardFolder> folders;
  for (const auto& dir : o.shardDirs) folders.push_back(readShardFolder(dir));
  folders = checkShardSet(std::move(folders));
  checkOutFolder(o, folders);
  const std::vector<BenchConfig> configs = sweepConfigurations(folders.front());
  Merger merger(configs);
  json runs = json::array(), shardList = json::array();
  for (const auto& f : folders) {
    merger.addShard(f);
    for (const auto& run : f.doc["runs"]) runs.push_back(run);
    shardList.push_back(f.dir);
  }
  BenchMergeResult result;
  result.shards = folders.size();
  result.configurations = configs.size();
  const json rows = merger.rowsInRunOrder();
  result.rows = rows.size();
  result.summaries = summarizeRows(rows);

  const std::string csvPath = o.outDir + "/bench.csv", jsonPath = o.outDir + "/bench.json",
                    summaryPath = o.outDir + "/summary.csv";
  std::error_code ec;
  fs::create_directories(o.outDir, ec);
  if (ec) refuse("cannot create output folder " + o.outDir + ": " + ec.message());
  std::string csv = csvLine(benchCsvColumns()) + "\n";
  for (const auto& r : rows) csv += csvLine(csvFields(benchColumns(), r)) + "\n";
  writeFileAtomically(csvPath, csv);
  json doc = {{"tool", "tileshade bench"},
              {"format_version", 1},
              {"runs", runs},
              {"merge", {{"finished", nowUtc()}, {"command", o.command}, {"shards", shardList}}},
              {"summaries", result.summaries},
              {"rows", rows}};
  writeFileAtomically(jsonPath, doc.dump(1) + "\n");
  writeFileAtomically(summaryPath, summaryCsvText(result.summaries));
  if (o.printTable) {
    std::cout << "bench merge: " << result.shards << " shard(s) of a sweep of "
              << result.configurations << " configuration(s); " << result.rows << " row(s)\n";
    printSummaryTable(result.summaries, std::cout);
    printCalibrations(runs, std::cout);
    std::cout << "wrote " << csvPath << ", " << jsonPath << ", " << summaryPath << "\n";
  }
  return result;
}

}  // namespace ts
