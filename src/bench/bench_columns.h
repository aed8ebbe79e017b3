#pragma once
// The schema of bench.csv and summary.csv (bench/README.md) as tables of columns, as
// benchDimensions() is for the sweep: each column names its value in a bench.json row (or
// summary) by a JSON path and gives its type, and writing a row, reading it back for --resume
// (rowFromCsv) and checking a resumed value's type all follow the table. A new measurement column
// is one entry in bench_columns.cpp; the dimension columns come from benchDimensions() and need
// no edit here.
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace ts {

// The note a --shadow-error row carries instead of the shadow_* columns when no light of its
// frame casts a shadow (bench_measure.cpp); --resume keeps such a row (bench_resume.cpp).
inline constexpr const char* kNoShadowErrorNote =
    "--shadow-error: no light casts a shadow in this frame";

// How a column's JSON value becomes CSV text, comes back, and is checked on --resume.
enum class BenchColumnType {
  Text,           // a string as it is (other JSON as its dump); read back as a string
  Integer,        // digits (a non-integer number as numberText); 1 to 18 digits read back
  Time,           // milliseconds as numberText; read back: a finite number >= 0
  Number,         // numberText ("inf"/"-inf" for infinities, "" for NaN); any number read back
  Kernels,        // the kernels array as "name=ms;name=ms" (times finite, >= 0)
  KernelMedians,  // summary.csv: the kernels' medians as "name=median;…" (never read back)
  Notes,          // the notes array joined with " | "; read back split at '|'
};

struct BenchColumn {
  std::string name;  // CSV header
  std::string path;  // JSON pointer into the record, e.g. "/limit/min_bytes"
  BenchColumnType type;
  bool required = false;  // every row the runner writes has a value (--resume drops one without)
  // Read back, the record has this column's JSON value only when column `presentIf` has a value
  // (the column itself for an optional value, the group's first column for a group such as
  // err_*); "" = always there, null when the field is empty.
  std::string presentIf;
};

// bench.csv in file order: config_id, the dimensions (benchDimensions(), path /config/NAME),
// then the measurements.
const std::vector<BenchColumn>& benchColumns();
// summary.csv in file order (records of summarizeRows).
const std::vector<BenchColumn>& summaryColumns();
// Their names: the files' headers.
std::vector<std::string> benchCsvColumns();
std::vector<std::string> summaryCsvColumns();

// The CSV fields of `record` (a bench.json row or summary) under `columns`; an absent value (or
// null, or of another JSON type than the column's) is an empty field.
std::vector<std::string> csvFields(const std::vector<BenchColumn>& columns,
                                   const nlohmann::json& record);

// A bench.csv row (column -> value) back as its bench.json row, for rows that bench.json lost
// (kernel launch counts are not in the CSV and stay absent). An integer beyond 18 digits is a
// ts::Error naming `csvName` and the column.
nlohmann::json rowFromCsv(const std::map<std::string, std::string>& fields,
                          const std::string& csvName);

// Whether `value` is of the column's type (empty: whether the column may be empty).
bool wellTyped(const BenchColumn& column, const std::string& value);

// A JSON value as the tables read it: numbers, "inf"/"-inf" strings as infinities, anything else
// (absent included) NaN; text: strings as they are, other JSON as its dump, absent or null "";
// integer text: numbers only (a float as numberText), else "".
double jsonDoubleOf(const nlohmann::json* value);
std::string jsonTextOf(const nlohmann::json* value);
std::string jsonIntegerTextOf(const nlohmann::json* value);
// The value at `key` of an object (nullptr when absent or `j` is not an object).
const nlohmann::json* findKey(const nlohmann::json& j, const std::string& key);

}  // namespace ts
