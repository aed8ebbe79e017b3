#pragma once
// What `bench --resume` keeps of an earlier run's OUT/bench.csv: only rows that parse (every
// column present and of its type) and that the current run would have written itself (one of
// its configurations, on the device its --device resolves to, one of its frames, with its
// --warmup/--repeat, with error columns where --error wants them). The rest is dropped and
// counted by reason, so that nothing unusable reaches bench.json, summary.csv or plot.py, and
// bench.csv is rewritten without it (rows are never appended after junk).
#include <cstddef>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "bench/bench_config.h"

namespace ts {

// What the current run writes for one configuration (by config_id).
struct ResumeExpectation {
  BenchConfig config;
  std::string deviceName;           // what its device spec resolves to
  std::set<int> frames;             // its timed frames
  std::set<int> errorFrames;        // the frames that get error columns
  std::set<int> shadowErrorFrames;  // the frames that get shadow-error columns (--shadow-error)
};

struct ResumeScan {
  struct Row {
    std::string configId;
    int frame = 0;
    std::string line;                           // as it was in the file
    size_t lineNumber = 0;                      // 1-based
    std::map<std::string, std::string> fields;  // column -> value
  };
  struct Drop {
    std::string reason;
    size_t rows = 0;
    size_t firstLine = 0;
  };
  std::vector<Row> kept;    // file order; each (configuration, frame) once, its last usable row
  std::vector<Drop> drops;  // one per reason, in order of first appearance

  void drop(const std::string& reason, size_t lineNumber);
  size_t droppedRows() const;
  // One line per reason: "dropped N row(s) of PATH: REASON (first at line L)".
  std::vector<std::string> describeDrops(const std::string& path) const;
};

// One line of a bench.csv after its header, as a record of benchCsvColumns() or why it is not one
// (readBenchCsv): the reading that --resume and `bench merge` share.
struct BenchCsvRecord {
  size_t lineNumber = 0;                      // 1-based
  std::string line;                           // as it was in the file
  std::map<std::string, std::string> fields;  // column -> value; empty when malformed
  std::string malformed;                      // "" or why the line is not a record of the header
};

// Reads `path`, whose header must be benchCsvColumns() (else a ts::Error: another version's or
// another tool's file, ending with `otherHeaderAdvice`), and returns its other non-empty lines in
// file order (a repeated header, from `cat` of two files, is skipped).
std::vector<BenchCsvRecord> readBenchCsv(const std::string& path,
                                         const std::string& otherHeaderAdvice);

// Reads `path`, whose header must be benchCsvColumns() (else a ts::Error: another version's or
// another tool's file is not resumed at all). Rows whose config_id is not in `expected` belong
// to another sweep or shard.
ResumeScan scanBenchCsv(const std::string& path,
                        const std::map<std::string, ResumeExpectation>& expected, int warmup,
                        int repeat);

}  // namespace ts
