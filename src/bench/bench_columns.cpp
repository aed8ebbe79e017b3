#include "bench/bench_columns.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>

#include "bench/bench_config.h"
#include "bench/bench_stats.h"
#include "render/stats.h"
#include "util/option_values.h"

namespace ts {
namespace {

using json = nlohmann::json;
using Type = BenchColumnType;

// Counters read back from bench.csv (18 digits, the most parseInteger reads).
constexpr long long kMaxCsvInteger = 999999999999999999LL;

// Columns after the dimensions, in file order.
const std::vector<BenchColumn>& measurementColumns() {
  static const std::vector<BenchColumn> columns = {
      {"device_name", "/device_name", Type::Text, true, ""},
      {"lanes_used", "/lanes_used", Type::Integer, true, ""},
      {"features_used", "/features_used", Type::Text, false, ""},
      {"gbuffer_bytes_per_pixel", "/gbuffer_bytes_per_pixel", Type::Integer, true, ""},
      {"kernel_options", "/kernel_options", Type::Text, false, ""},
      {"frame", "/frame", Type::Integer, true, ""},
      {"lights", "/lights", Type::Integer, true, ""},
      {"geometry_pixels", "/geometry_pixels", Type::Integer, true, ""},
      {"total_ms", "/total_ms", Type::Time, true, ""},
      {"kernels", "/kernels", Type::Kernels, true, ""},
      {"wall_ms", "/wall_ms", Type::Time, true, ""},
      {"upload_ms", "/upload_ms", Type::Time, true, ""},
      {"compile_ms", "/compile_ms", Type::Time, true, ""},
      {"raster_ms", "/raster_ms", Type::Time, true, ""},
      {"shadow_ms", "/shadow_ms", Type::Time, false, ""},
      {"shadow_bytes", "/shadow_bytes", Type::Integer, false, ""},
      {"shadow_bytes_written", "/shadow_bytes_written", Type::Integer, false, ""},
      {"warmup", "/warmup", Type::Integer, true, ""},
      {"repeat", "/repeat", Type::Integer, true, ""},
      {"lighting_computations", "/lighting_computations", Type::Integer, true, ""},
      {"evaluations", "/evaluations", Type::Integer, true, ""},
      {"gbuffer_bytes_read", "/gbuffer_bytes_read", Type::Integer, true, ""},
      {"nonfinite_pixels", "/nonfinite_pixels", Type::Integer, true, ""},
      {"list_min", "/lights_per_bin/min", Type::Integer, false, ""},
      {"list_mean", "/lights_per_bin/mean", Type::Number, false, ""},
      {"list_max", "/lights_per_bin/max", Type::Integer, false, ""},
      {"min_bytes", "/limit/min_bytes", Type::Integer, true, ""},
      {"min_flops", "/limit/min_flops", Type::Number, true, ""},
      {"flops_basis", "/limit/flops_basis", Type::Text, true, ""},
      {"bandwidth_gbs", "/limit/bandwidth_gbs", Type::Number, false, ""},  // when calibrated
      {"peak_gflops", "/limit/peak_gflops", Type::Number, false, ""},
      {"limit_ms", "/limit/limit_ms", Type::Number, false, ""},
      {"limit_pct", "/limit/limit_pct", Type::Number, false, ""},
      {"limit_pct_slowest_round", "/limit/limit_pct_slowest_round", Type::Number, false, ""},
      // With --error, on the frames that get it (--error-frames).
      {"reference_contributing", "/reference_contributing", Type::Integer, false,
       "reference_contributing"},
      {"err_max_abs", "/error/max_abs", Type::Number, false, "err_max_abs"},
      {"err_rmse", "/error/rmse", Type::Number, false, "err_max_abs"},
      {"err_psnr_db", "/error/psnr_db", Type::Number, false, "err_max_abs"},
      {"err_max_rel_peak", "/error/max_rel_peak", Type::Number, false, "err_max_abs"},
      {"err_p50", "/error/p50", Type::Number, false, "err_max_abs"},
      {"err_p99", "/error/p99", Type::Number, false, "err_max_abs"},
      {"err_p999", "/error/p999", Type::Number, false, "err_max_abs"},
      {"err_shading_max_rel_peak", "/error_shading/max_rel_peak", Type::Number, false,
       "err_shading_max_rel_peak"},
      // With --shadow-error, on the frames that get it (--error-frames).
      {"shadow_wrong_pct", "/shadow_error/wrong_pct", Type::Number, false, ""},
      {"shadow_err_max_rel_peak", "/shadow_error/err_max_rel_peak", Type::Number, false, ""},
      {"shadow_err_rmse", "/shadow_error/err_rmse", Type::Number, false, ""},
      {"shadow_err_p99", "/shadow_error/err_p99", Type::Number, false, ""},
      {"shadow_err_psnr_db", "/shadow_error/err_psnr_db", Type::Number, false, ""},
      {"shadow_exact_ms", "/shadow_error/exact_ms", Type::Time, false, ""},
      {"notes", "/notes", Type::Notes, false, ""},
  };
  return columns;
}

// A summary.csv column (summary.csv is never read back: no resume rules).
BenchColumn summaryColumn(const char* name, const char* path, Type type) {
  return {name, path, type, false, ""};
}

// summary.csv columns after the dimensions (summarizeRows' records), in file order.
const std::vector<BenchColumn>& summaryMeasurementColumns() {
  static const std::vector<BenchColumn> columns = {
      summaryColumn("device_name", "/device_name", Type::Text),
      summaryColumn("lanes_used", "/lanes_used", Type::Integer),
      summaryColumn("features_used", "/features_used", Type::Text),
      summaryColumn("gbuffer_bytes_per_pixel", "/gbuffer_bytes_per_pixel", Type::Integer),
      summaryColumn("frames", "/frames", Type::Integer),
      summaryColumn("total_ms_median", "/total_ms/median", Type::Number),
      summaryColumn("total_ms_min", "/total_ms/min", Type::Number),
      summaryColumn("total_ms_max", "/total_ms/max", Type::Number),
      summaryColumn("total_ms_mean", "/total_ms/mean", Type::Number),
      summaryColumn("wall_ms_median", "/wall_ms/median", Type::Number),
      summaryColumn("wall_ms_min", "/wall_ms/min", Type::Number),
      summaryColumn("wall_ms_max", "/wall_ms/max", Type::Number),
      summaryColumn("upload_ms_median", "/upload_ms/median", Type::Number),
      summaryColumn("compile_ms", "/compile_ms", Type::Number),
      summaryColumn("raster_ms_median", "/raster_ms/median", Type::Number),
      summaryColumn("shadow_ms_median", "/shadow_ms/median", Type::Number),
      summaryColumn("shadow_bytes_max", "/shadow_bytes_max", Type::Integer),
      summaryColumn("kernels_median", "/kernels", Type::KernelMedians),
      summaryColumn("lighting_computations_median", "/lighting_computations/median", Type::Number),
      summaryColumn("evaluations_median", "/evaluations/median", Type::Number),
      summaryColumn("limit_ms_median", "/limit_ms/median", Type::Number),
      summaryColumn("limit_pct_median", "/limit_pct/median", Type::Number),
      summaryColumn("flops_basis", "/flops_basis", Type::Text),
      summaryColumn("nonfinite_pixels_max", "/nonfinite_pixels_max", Type::Integer),
      summaryColumn("error_frames", "/error/frames", Type::Integer),
      summaryColumn("err_max_abs_max", "/error/max_abs", Type::Number),
      summaryColumn("err_rmse_max", "/error/rmse", Type::Number),
      summaryColumn("err_psnr_db_min", "/error/psnr_db", Type::Number),
      summaryColumn("err_max_rel_peak_max", "/error/max_rel_peak", Type::Number),
  };
  return columns;
}

// config_id, the dimensions, then `tail`.
std::vector<BenchColumn> withDimensions(const std::vector<BenchColumn>& tail) {
  std::vector<BenchColumn> columns = {{"config_id", "/config_id", Type::Text, true, ""}};
  for (const auto& d : benchDimensions())
    columns.push_back({d.name, "/config/" + d.name, Type::Text, false, ""});
  columns.insert(columns.end(), tail.begin(), tail.end());
  return columns;
}

// The value at a JSON pointer, stepping only through objects; nullptr when absent.
const json* findPath(const json& record, const std::string& path) {
  const json* at = &record;
  size_t start = 1;
  while (at && start <= path.size()) {
    size_t end = std::min(path.find('/', start), path.size());
    at = findKey(*at, path.substr(start, end - start));
    start = end + 1;
  }
  return at;
}

// "name=T;name=T" of a kernels array, T each kernel's `timeKey`.
std::string packKernels(const json* kernels, const char* timeKey) {
  std::string s;
  if (!kernels) return s;
  for (const auto& k : *kernels)
    s += (s.empty() ? "" : ";") + k.at("name").get<std::string>() + "=" +
         numberText(jsonDoubleOf(findKey(k, timeKey)));
  return s;
}

json unpackKernels(const std::string& packed) {
  json out = json::array();
  for (const auto& item : splitList(packed, ';')) {
    size_t eq = item.find('=');
    if (eq == std::string::npos) continue;
    double ms = std::strtod(item.c_str() + eq + 1, nullptr);
    out.push_back({{"name", item.substr(0, eq)}, {"ms", ms}});
  }
  return out;
}

std::string fieldOf(const BenchColumn& column, const json& record) {
  const json* value = findPath(record, column.path);
  switch (column.type) {
    case Type::Text: return jsonTextOf(value);
    case Type::Integer: return jsonIntegerTextOf(value);
    case Type::Time:
    case Type::Number: return numberText(jsonDoubleOf(value));
    case Type::Kernels: return packKernels(value, "ms");
    case Type::KernelMedians: return packKernels(value, "median");
    case Type::Notes: {
      std::string notes;
      if (value)
        for (const auto& n : *value) notes += (notes.empty() ? "" : " | ") + n.get<std::string>();
      return notes;
    }
  }
  return "";
}

json valueOf(const BenchColumn& column, const std::string& field, const std::string& csvName) {
  switch (column.type) {
    case Type::Text: return field;
    case Type::Integer:
      if (field.empty()) return nullptr;
      return (unsigned long long)parseInteger(csvName + " column " + column.name, field, 0,
                                              kMaxCsvInteger);
    case Type::Time:
    case Type::Number:
      if (field.empty()) return nullptr;
      return jsonNumber(std::strtod(field.c_str(), nullptr));  // "inf", "-inf" stay strings
    case Type::Kernels:
    case Type::KernelMedians: return unpackKernels(field);
    case Type::Notes: {
      json notes = json::array();
      for (const auto& n : splitList(field, '|')) notes.push_back(n);
      return notes;
    }
  }
  return nullptr;
}

// A number as numberText writes it: the whole text, "inf"/"-inf" for infinities.
bool isNumber(const std::string& s, bool finiteNonNegative) {
  if (s.empty() || std::isspace((unsigned char)s[0])) return false;
  char* end = nullptr;
  double v = std::strtod(s.c_str(), &end);
  if (end != s.c_str() + s.size() || std::isnan(v)) return false;
  return !finiteNonNegative || (std::isfinite(v) && v >= 0.0);
}

// 1 to 18 digits: what rowFromCsv reads back.
bool isInteger(const std::string& s) {
  return !s.empty() && s.size() <= 18 &&
         std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isdigit(c); });
}

// "name=ms;name=ms", every time a finite number >= 0.
bool isKernelList(const std::string& s) {
  if (s.empty()) return false;
  for (const auto& item : splitList(s, ';')) {
    size_t eq = item.find('=');
    if (eq == 0 || eq == std::string::npos || !isNumber(item.substr(eq + 1), true)) return false;
  }
  return true;
}

std::vector<std::string> namesOf(const std::vector<BenchColumn>& columns) {
  std::vector<std::string> names;
  for (const auto& c : columns) names.push_back(c.name);
  return names;
}

}  // namespace

const std::vector<BenchColumn>& benchColumns() {
  static const std::vector<BenchColumn> columns = withDimensions(measurementColumns());
  return columns;
}

const std::vector<BenchColumn>& summaryColumns() {
  static const std::vector<BenchColumn> columns = withDimensions(summaryMeasurementColumns());
  return columns;
}

std::vector<std::string> benchCsvColumns() { return namesOf(benchColumns()); }
std::vector<std::string> summaryCsvColumns() { return namesOf(summaryColumns()); }

std::vector<std::string> csvFields(const std::vector<BenchColumn>& columns, const json& record) {
  std::vector<std::string> fields;
  for (const auto& c : columns) fields.push_back(fieldOf(c, record));
  return fields;
}

json rowFromCsv(const std::map<std::string, std::string>& fields, const std::string& csvName) {
  auto get = [&](const std::string& name) {
    auto it = fields.find(name);
    return it == fields.end() ? std::string() : it->second;
  };
  json row = json::object();
  for (const auto& c : benchColumns())
    if (c.presentIf.empty() || !get(c.presentIf).empty())
      row[json::json_pointer(c.path)] = valueOf(c, get(c.name), csvName);
  // techniqueJson's own "technique" key, which the CSV holds once, as the dimension.
  row["technique"] = get("technique");
  return row;
}

bool wellTyped(const BenchColumn& column, const std::string& value) {
  if (value.empty()) return !column.required;
  switch (column.type) {
    case Type::Text:
    case Type::Notes: return true;
    case Type::Integer: return isInteger(value);
    case Type::Time: return isNumber(value, true);
    case Type::Number: return isNumber(value, false);
    case Type::Kernels:
    case Type::KernelMedians: return isKernelList(value);
  }
  return false;
}

const json* findKey(const json& j, const std::string& key) {
  if (!j.is_object()) return nullptr;
  auto it = j.find(key);
  return it == j.end() ? nullptr : &*it;
}

double jsonDoubleOf(const json* value) {
  if (!value || value->is_null()) return std::nan("");
  if (value->is_number()) return value->get<double>();
  if (value->is_string()) {
    const std::string& s = value->get_ref<const std::string&>();
    if (s == "inf") return INFINITY;
    if (s == "-inf") return -INFINITY;
    try {
      return std::stod(s);
    } catch (const std::exception&) {
    }
  }
  return std::nan("");
}

std::string jsonTextOf(const json* value) {
  if (!value || value->is_null()) return "";
  return value->is_string() ? value->get<std::string>() : value->dump();
}

std::string jsonIntegerTextOf(const json* value) {
  if (!value || !value->is_number()) return "";
  return value->is_number_float() ? numberText(value->get<double>()) : value->dump();
}

}  // namespace ts
