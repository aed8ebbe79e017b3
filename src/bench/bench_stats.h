#pragma once
// Small statistics and CSV helpers of the benchmark.
#include <cstddef>
#include <map>
#include <string>
#include <vector>

namespace ts {

struct Summary {
  size_t n = 0;
  double median = 0.0, min = 0.0, max = 0.0, mean = 0.0;
};

// Median (mean of the two middle values for an even count), min, max, mean; all 0 when empty.
// Non-finite values are ignored.
Summary summarize(std::vector<double> values);

// CSV (RFC 4180): fields holding a comma, quote or line break are quoted, quotes doubled.
std::string csvField(const std::string& s);
std::string csvLine(const std::vector<std::string>& fields);

// The time now as bench.json records it ("2026-12-01T23:50:39Z", UTC).
std::string nowUtc();
// One line read back: false for an unterminated quote or a quote inside an unquoted field (or
// text after a closing one).
bool parseCsvRecord(const std::string& line, std::vector<std::string>& fields);

// Rows of a CSV file as column -> value. The first line is the header; a later line equal to the
// header is skipped (so `cat a.csv b.csv` of files with the same columns reads back as one table).
// Returns false when the file does not exist; header receives the file's columns. A line that is
// not a CSV record is an error naming the file and the line.
bool readCsv(const std::string& path, std::vector<std::string>& header,
             std::vector<std::map<std::string, std::string>>& rows);

// A number as CSV text: 6 significant digits, "" for NaN, "inf" for infinities.
std::string numberText(double v);
// A number with `digits` decimals for a printed table; "-" when not finite.
std::string fixedText(double v, int digits);

}  // namespace ts
