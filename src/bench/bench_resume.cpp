#include "bench/bench_resume.h"

#include <algorithm>
#include <cstdlib>
#include <sstream>

#include "bench/bench_columns.h"
#include "bench/bench_stats.h"
#include "util/error.h"
#include "util/file_read.h"
#include "util/option_values.h"

namespace ts {
namespace {

// Why a parsed row cannot be resumed, or "" when it can.
std::string unusable(const std::map<std::string, std::string>& r,
                     const std::map<std::string, ResumeExpectation>& expected, int warmup,
                     int repeat) {
  for (const auto& column : benchColumns())
    if (!wellTyped(column, r.at(column.name)))
      return "a value that is missing or not of its column's type";
  auto it = expected.find(r.at("config_id"));
  if (it == expected.end()) return "a configuration this sweep (or shard) does not run";
  const ResumeExpectation& e = it->second;
  for (const auto& d : benchDimensions())
    if (r.at(d.name) != d.get(e.config))
      return "dimension values that do not match the row's config_id";
  if (r.at("device_name") != e.deviceName)
    return "measured on another device than --device names now";
  int frame = int(std::strtol(r.at("frame").c_str(), nullptr, 10));
  if (r.at("frame").size() > 9 || !e.frames.count(frame))
    return "a frame that --frames does not time";
  if (r.at("warmup") != std::to_string(warmup) || r.at("repeat") != std::to_string(repeat))
    return "measured with another --warmup or --repeat";
  if (e.errorFrames.count(frame) && r.at("err_max_abs").empty())
    return "no error columns where --error wants them";
  // A frame without shadow-casting lights gets the note instead of the columns (bench_measure).
  if (e.shadowErrorFrames.count(frame) && r.at("shadow_wrong_pct").empty() &&
      r.at("notes").find(kNoShadowErrorNote) == std::string::npos)
    return "no shadow-error columns where --shadow-error wants them";
  return "";
}

}  // namespace

void ResumeScan::drop(const std::string& reason, size_t lineNumber) {
  for (auto& d : drops)
    if (d.reason == reason) {
      ++d.rows;
      return;
    }
  drops.push_back({reason, 1, lineNumber});
}

size_t ResumeScan::droppedRows() const {
  size_t n = 0;
  for (const auto& d : drops) n += d.rows;
  return n;
}

std::vector<std::string> ResumeScan::describeDrops(const std::string& path) const {
  std::vector<std::string> out;
  for (const auto& d : drops)
    out.push_back("dropped " + std::to_string(d.rows) + " row(s) of " + path + ": " + d.reason +
                  " (first at line " + std::to_string(d.firstLine) + ")");
  return out;
}

std::vector<BenchCsvRecord> readBenchCsv(const std::string& path,
                                         const std::string& otherHeaderAdvice) {
  std::istringstream in(readTextFile(path, "bench results"));
  const std::vector<std::string> columns = benchCsvColumns();
  const std::string headerLine = csvLine(columns);
  std::vector<BenchCsvRecord> records;
  std::string line;
  bool sawHeader = false;
  for (size_t number = 1; std::getline(in, line); ++number) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    if (!sawHeader) {
      if (line != headerLine)
        throw Error(path + " has other columns than this version writes; " + otherHeaderAdvice);
      sawHeader = true;
      continue;
    }
    if (line == headerLine) continue;  // `cat` of two files
    BenchCsvRecord record;
    record.lineNumber = number;
    record.line = line;
    std::vector<std::string> fields;
    if (!parseCsvRecord(line, fields)) {
      record.malformed = "a quote that is not closed or is out of place";
    } else if (fields.size() != columns.size()) {
      record.malformed = fields.size() < columns.size()
                             ? "fewer fields than the header (a truncated row)"
                             : "more fields than the header";
    } else {
      for (size_t i = 0; i < columns.size(); ++i) record.fields[columns[i]] = fields[i];
    }
    records.push_back(std::move(record));
  }
  if (in.bad()) throw Error("cannot read " + path);
  return records;
}

ResumeScan scanBenchCsv(const std::string& path,
                        const std::map<std::string, ResumeExpectation>& expected, int warmup,
                        int repeat) {
  ResumeScan scan;
  std::map<std::pair<std::string, int>, size_t> keptAt;  // index into scan.kept
  std::vector<bool> superseded;
  for (BenchCsvRecord& record : readBenchCsv(path, "resume into a new --out")) {
    const size_t number = record.lineNumber;
    if (!record.malformed.empty()) {
      scan.drop(record.malformed, number);
      continue;
    }
    ResumeScan::Row row;
    row.fields = std::move(record.fields);
    std::string why = unusable(row.fields, expected, warmup, repeat);
    if (!why.empty()) {
      scan.drop(why, number);
      continue;
    }
    row.configId = row.fields.at("config_id");
    row.frame = int(std::strtol(row.fields.at("frame").c_str(), nullptr, 10));
    row.line = std::move(record.line);
    row.lineNumber = number;
    auto key = std::make_pair(row.configId, row.frame);
    auto old = keptAt.find(key);
    if (old != keptAt.end()) {
      scan.drop("a (configuration, frame) measured again later; the last row is kept",
                scan.kept[old->second].lineNumber);
      superseded[old->second] = true;
    }
    keptAt[key] = scan.kept.size();
    scan.kept.push_back(std::move(row));
    superseded.push_back(false);
  }
  std::vector<ResumeScan::Row> kept;
  for (size_t i = 0; i < scan.kept.size(); ++i)
    if (!superseded[i]) kept.push_back(std::move(scan.kept[i]));
  scan.kept = std::move(kept);
  return scan;
}

}  // namespace ts
