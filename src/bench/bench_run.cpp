#include "bench/bench_run.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <sstream>

#include "bench/bench_frames.h"
#include "bench/bench_resume.h"
#include "bench/bench_stats.h"
#include "cl/cl_context.h"
#include "reference/error_metrics.h"
#include "reference/reference.h"
#include "render/frame_setup.h"
#include "render/stats.h"
#include "scene/light_range.h"
#include "scene/scene_loader.h"
#include "shading/shading_cpu.h"  // TS_SHADE_FLOPS_* (kernels/shading.h)
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

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// Relative tolerance (of the reference peak) for "pixels above tolerance", as in `render`.
constexpr double kTolerance = 1e-4;
// Floating-point operations of one contributing light evaluation (kernels/shading.h).
double shadeFlops(ShadingModel model) {
  return model == ShadingModel::MetallicRoughness ? TS_SHADE_FLOPS_METALLIC_ROUGHNESS
                                                  : TS_SHADE_FLOPS_BLINN_PHONG;
}
// Counters read back from bench.csv on --resume (18 digits, the most parseInteger reads).
constexpr long long kMaxCsvInteger = 999999999999999999LL;

std::string nowUtc() {
  std::time_t t = std::time(nullptr);
  std::tm g{};
  gmtime_r(&t, &g);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &g);
  return buf;
}

// The scene-defining part of a configuration (frameKey() without the resolution and the
// rasterizer: one BenchScene serves both rasterizers).
std::string sceneKey(const BenchConfig& c) {
  std::string k;
  for (const auto& d : benchDimensions())
    if (d.affectsFrame && d.name != "resolution" && d.name != "raster")
      k += d.name + "=" + d.get(c) + ";";
  return k;
}

json configJson(const BenchConfig& c) {
  json j = json::object();
  for (const auto& d : benchDimensions()) j[d.name] = d.get(c);
  return j;
}

// A JSON number, "inf" strings (PSNR of an exact image) as infinity, anything else NaN.
double num(const json& j, const char* key) {
  auto it = j.find(key);
  if (it == j.end() || it->is_null()) return std::nan("");
  if (it->is_number()) return it->get<double>();
  if (it->is_string()) {
    std::string s = it->get<std::string>();
    if (s == "inf") return INFINITY;
    if (s == "-inf") return -INFINITY;
    try {
      return std::stod(s);
    } catch (const std::exception&) {
    }
  }
  return std::nan("");
}

std::string str(const json& j, const char* key) {
  auto it = j.find(key);
  if (it == j.end() || it->is_null()) return "";
  return it->is_string() ? it->get<std::string>() : it->dump();
}

std::string intText(const json& j, const char* key) {
  auto it = j.find(key);
  if (it == j.end() || !it->is_number()) return "";
  return it->is_number_float() ? numberText(it->get<double>()) : it->dump();
}

json summaryJson(const Summary& s) {
  return {{"n", s.n}, {"median", s.median}, {"min", s.min}, {"max", s.max}, {"mean", s.mean}};
}

std::string packKernels(const json& kernels) {
  std::string s;
  for (const auto& k : kernels)
    s += (s.empty() ? "" : ";") + k.at("name").get<std::string>() + "=" + numberText(num(k, "ms"));
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

const char* const kErrorFields[] = {"max_abs", "rmse", "psnr_db", "max_rel_peak", "p50", "p99", "p999"};

// bench.csv columns after the dimensions.
const std::vector<std::string>& rowColumns() {
  static const std::vector<std::string> cols = {
      "device_name", "lanes_used", "features_used", "gbuffer_bytes_per_pixel", "kernel_options", "frame",
      "lights", "geometry_pixels", "total_ms", "kernels", "wall_ms",
      "upload_ms", "compile_ms", "raster_ms", "warmup", "repeat", "lighting_computations",
      "evaluations", "gbuffer_bytes_read", "nonfinite_pixels", "list_min", "list_mean", "list_max", "min_bytes",
      "min_flops", "flops_basis", "bandwidth_gbs", "peak_gflops", "limit_ms", "limit_pct",
      "reference_contributing", "err_max_abs", "err_rmse", "err_psnr_db", "err_max_rel_peak",
      "err_p50", "err_p99", "err_p999", "err_shading_max_rel_peak", "notes"};
  return cols;
}

std::vector<std::string> csvFieldsOf(const json& row) {
  std::vector<std::string> f;
  f.push_back(str(row, "config_id"));
  const json& config = row.at("config");
  for (const auto& d : benchDimensions()) f.push_back(config.contains(d.name) ? str(config, d.name.c_str()) : "");
  const json& limit = row.contains("limit") ? row["limit"] : json::object();
  const json& bins = row.contains("lights_per_bin") ? row["lights_per_bin"] : json::object();
  const json& error = row.contains("error") ? row["error"] : json::object();
  std::string notes;
  if (row.contains("notes"))
    for (const auto& n : row["notes"]) notes += (notes.empty() ? "" : " | ") + n.get<std::string>();
  f.push_back(str(row, "device_name"));
  f.push_back(intText(row, "lanes_used"));
  f.push_back(str(row, "features_used"));
  f.push_back(intText(row, "gbuffer_bytes_per_pixel"));
  f.push_back(str(row, "kernel_options"));
  f.push_back(intText(row, "frame"));
  f.push_back(intText(row, "lights"));
  f.push_back(intText(row, "geometry_pixels"));
  f.push_back(numberText(num(row, "total_ms")));
  f.push_back(packKernels(row.value("kernels", json::array())));
  f.push_back(numberText(num(row, "wall_ms")));
  f.push_back(numberText(num(row, "upload_ms")));
  f.push_back(numberText(num(row, "compile_ms")));
  f.push_back(numberText(num(row, "raster_ms")));
  f.push_back(intText(row, "warmup"));
  f.push_back(intText(row, "repeat"));
  f.push_back(intText(row, "lighting_computations"));
  f.push_back(intText(row, "evaluations"));
  f.push_back(intText(row, "gbuffer_bytes_read"));
  f.push_back(intText(row, "nonfinite_pixels"));
  f.push_back(intText(bins, "min"));
  f.push_back(numberText(num(bins, "mean")));
  f.push_back(intText(bins, "max"));
  f.push_back(intText(limit, "min_bytes"));
  f.push_back(numberText(num(limit, "min_flops")));
  f.push_back(str(limit, "flops_basis"));
  f.push_back(numberText(num(limit, "bandwidth_gbs")));
  f.push_back(numberText(num(limit, "peak_gflops")));
  f.push_back(numberText(num(limit, "limit_ms")));
  f.push_back(numberText(num(limit, "limit_pct")));
  f.push_back(intText(row, "reference_contributing"));
  for (const char* e : kErrorFields) f.push_back(error.empty() ? "" : numberText(num(error, e)));
  f.push_back(row.contains("error_shading") ? numberText(num(row["error_shading"], "max_rel_peak"))
                                            : "");
  f.push_back(notes);
  return f;
}

// The inverse of csvFieldsOf for rows that bench.json lost (kernel launch counts are not in the
// CSV and come back as absent).
json rowFromCsv(const std::map<std::string, std::string>& r, const std::string& csvName) {
  auto get = [&](const std::string& k) {
    auto it = r.find(k);
    return it == r.end() ? std::string() : it->second;
  };
  auto number = [&](const std::string& k) -> json {
    std::string v = get(k);
    if (v.empty()) return nullptr;
    return jsonNumber(std::strtod(v.c_str(), nullptr));  // "inf", "-inf" stay strings
  };
  auto integer = [&](const std::string& k) -> json {
    std::string v = get(k);
    if (v.empty()) return nullptr;
    return (unsigned long long)parseInteger(csvName + " column " + k, v, 0, kMaxCsvInteger);
  };
  json config = json::object();
  for (const auto& d : benchDimensions()) config[d.name] = get(d.name);
  json row = {{"technique", get("technique")},
              {"kernels", unpackKernels(get("kernels"))},
              {"total_ms", number("total_ms")},
              {"lighting_computations", integer("lighting_computations")},
              {"evaluations", integer("evaluations")},
              {"gbuffer_bytes_read", integer("gbuffer_bytes_read")},
              {"nonfinite_pixels", integer("nonfinite_pixels")},
              {"lights_per_bin", {{"min", integer("list_min")}, {"mean", number("list_mean")}, {"max", integer("list_max")}}},
              {"notes", json::array()},
              {"config_id", get("config_id")},
              {"config", config},
              {"device_name", get("device_name")},
              {"lanes_used", integer("lanes_used")},
              {"features_used", get("features_used")},
              {"gbuffer_bytes_per_pixel", integer("gbuffer_bytes_per_pixel")},
              {"kernel_options", get("kernel_options")},
              {"frame", int(parseInteger(csvName + " column frame", get("frame"), 0, INT32_MAX))},
              {"lights", integer("lights")},
              {"geometry_pixels", integer("geometry_pixels")},
              {"wall_ms", number("wall_ms")},
              {"upload_ms", number("upload_ms")},
              {"compile_ms", number("compile_ms")},
              {"raster_ms", number("raster_ms")},
              {"warmup", integer("warmup")},
              {"repeat", integer("repeat")},
              {"limit", {{"min_bytes", integer("min_bytes")}, {"min_flops", number("min_flops")},
                         {"flops_basis", get("flops_basis")}, {"bandwidth_gbs", number("bandwidth_gbs")},
                         {"peak_gflops", number("peak_gflops")}, {"limit_ms", number("limit_ms")},
                         {"limit_pct", number("limit_pct")}}}};
  for (const auto& n : splitList(get("notes"), '|')) row["notes"].push_back(n);
  if (!get("reference_contributing").empty()) row["reference_contributing"] = integer("reference_contributing");
  if (!get("err_max_abs").empty()) {
    json e = json::object();
    for (const char* k : kErrorFields) e[k] = number(std::string("err_") + k);
    row["error"] = e;
  }
  if (!get("err_shading_max_rel_peak").empty())
    row["error_shading"] = {{"max_rel_peak", number("err_shading_max_rel_peak")}};
  return row;
}

std::string fixed(double v, int digits) {
  if (!std::isfinite(v)) return "-";
  std::ostringstream s;
  s << std::fixed << std::setprecision(digits) << v;
  return s.str();
}

void printTable(const json& summaries, std::ostream& out) {
  if (summaries.empty()) return;
  // Dimensions that differ between configurations get a column; technique, tile and G-buffer
  // always do.
  std::vector<std::string> shown = {"technique", "tile", "gbuffer"};
  for (const auto& d : benchDimensions()) {
    if (std::find(shown.begin(), shown.end(), d.name) != shown.end()) continue;
    std::set<std::string> values;
    for (const auto& s : summaries) values.insert(str(s.at("config"), d.name.c_str()));
    if (values.size() > 1) shown.push_back(d.name);
  }
  std::vector<std::vector<std::string>> table;
  std::vector<std::string> head = shown;
  for (const char* h :
       {"median ms", "(min-max)", "wall ms", "raster ms", "% limit", "per-kernel median ms"})
    head.push_back(h);
  table.push_back(head);
  for (const auto& s : summaries) {
    std::vector<std::string> row;
    for (const auto& d : shown) row.push_back(str(s.at("config"), d.c_str()));
    const json& t = s.at("total_ms");
    row.push_back(fixed(num(t, "median"), 3));
    row.push_back("(" + fixed(num(t, "min"), 3) + "-" + fixed(num(t, "max"), 3) + ")");
    row.push_back(fixed(num(s.at("wall_ms"), "median"), 2));
    row.push_back(fixed(num(s.at("raster_ms"), "median"), 2));
    std::string pct = fixed(num(s.at("limit_pct"), "median"), 1);
    std::string basis = str(s, "flops_basis");
    row.push_back(pct == "-" ? pct : pct + (basis == "reference" ? "" : basis == "evaluations" ? "*" : "~"));
    std::string kernels;
    for (const auto& k : s.at("kernels"))
      kernels += (kernels.empty() ? "" : " ") + k.at("name").get<std::string>() + "=" + fixed(num(k, "median"), 3);
    row.push_back(kernels);
    table.push_back(row);
  }
  std::vector<size_t> width(head.size(), 0);
  for (const auto& r : table)
    for (size_t i = 0; i < r.size(); ++i) width[i] = std::max(width[i], r[i].size());
  for (const auto& r : table) {
    std::string line;
    for (size_t i = 0; i < r.size(); ++i) {
      bool last = i + 1 == r.size();
      bool numeric = i >= shown.size() && !last;
      std::string cell = r[i];
      std::string pad(width[i] - cell.size(), ' ');
      line += numeric ? pad + cell : cell + (last ? "" : pad);
      if (!last) line += "  ";
    }
    out << line << "\n";
  }
  out << "% limit: device limit time / measured kernel time (median over frames); limit = max(bytes "
         "/ copy bandwidth, contributing evaluations x "
      << TS_SHADE_FLOPS_BLINN_PHONG << " (Blinn-Phong) or " << TS_SHADE_FLOPS_METALLIC_ROUGHNESS
      << " (metallic-roughness) FLOP / peak). Evaluations counted by the reference, or * by the "
         "technique itself (~ mixed).\n";
}

struct Entry {
  size_t index = 0;  // in the expanded sweep
  BenchConfig config;
  std::vector<int> frames;          // timed frames
  std::set<int> pending;            // not in the output yet
  std::set<int> errorFrames;
  std::unique_ptr<Technique> technique;
  ClContext* cl = nullptr;
  const Calibration* calibration = nullptr;
  std::string deviceName;
  double compileMs = 0.0;
  SceneFeatures features;      // what its kernels and layout model (BenchScene::features)
  std::string kernelOptions;   // its kernels' build options
  bool warmed = false, failed = false;
};

}  // namespace

std::vector<std::string> benchCsvColumns() {
  std::vector<std::string> c = {"config_id"};
  for (const auto& d : benchDimensions()) c.push_back(d.name);
  for (const auto& r : rowColumns()) c.push_back(r);
  return c;
}

std::vector<std::string> summaryCsvColumns() {
  std::vector<std::string> c = {"config_id"};
  for (const auto& d : benchDimensions()) c.push_back(d.name);
  for (const char* k :
       {"device_name", "lanes_used", "features_used", "gbuffer_bytes_per_pixel", "frames", "total_ms_median", "total_ms_min", "total_ms_max", "total_ms_mean",
        "wall_ms_median", "wall_ms_min", "wall_ms_max", "upload_ms_median", "compile_ms",
        "raster_ms_median", "kernels_median", "lighting_computations_median", "evaluations_median",
        "limit_ms_median", "limit_pct_median", "flops_basis", "nonfinite_pixels_max", "error_frames", "err_max_abs_max",
        "err_rmse_max", "err_psnr_db_min", "err_max_rel_peak_max"})
    c.push_back(k);
  return c;
}

json summarizeRows(const json& rows) {
  std::vector<std::string> order;
  std::map<std::string, std::map<int, const json*>> byConfig;  // last row of a frame wins
  for (const auto& r : rows) {
    std::string id = str(r, "config_id");
    if (!byConfig.count(id)) order.push_back(id);
    byConfig[id][r.value("frame", 0)] = &r;
  }
  json out = json::array();
  for (const auto& id : order) {
    const auto& frames = byConfig[id];
    const json& first = *frames.begin()->second;
    std::vector<double> total, wall, upload, raster, lc, ev, limitMs, limitPct, compile;
    std::vector<std::pair<std::string, std::vector<double>>> kernels;
    std::set<std::string> bases;
    std::vector<double> errMax, errRmse, errPsnr, errRel;
    double nonfinite = 0.0;
    json frameList = json::array();
    for (const auto& [frame, rp] : frames) {
      const json& r = *rp;
      frameList.push_back(frame);
      total.push_back(num(r, "total_ms"));
      wall.push_back(num(r, "wall_ms"));
      upload.push_back(num(r, "upload_ms"));
      raster.push_back(num(r, "raster_ms"));
      compile.push_back(num(r, "compile_ms"));
      lc.push_back(num(r, "lighting_computations"));
      ev.push_back(num(r, "evaluations"));
      if (double n = num(r, "nonfinite_pixels"); n > nonfinite) nonfinite = n;
      if (r.contains("limit")) {
        limitMs.push_back(num(r["limit"], "limit_ms"));
        limitPct.push_back(num(r["limit"], "limit_pct"));
        std::string b = str(r["limit"], "flops_basis");
        if (!b.empty()) bases.insert(b);
      }
      for (const auto& k : r.value("kernels", json::array())) {
        std::string name = k.at("name").get<std::string>();
        auto it = std::find_if(kernels.begin(), kernels.end(), [&](const auto& p) { return p.first == name; });
        if (it == kernels.end()) {
          kernels.push_back({name, {}});
          it = kernels.end() - 1;
        }
        it->second.push_back(num(k, "ms"));
      }
      if (r.contains("error")) {
        errMax.push_back(num(r["error"], "max_abs"));
        errRmse.push_back(num(r["error"], "rmse"));
        errPsnr.push_back(num(r["error"], "psnr_db"));
        errRel.push_back(num(r["error"], "max_rel_peak"));
      }
    }
    json k = json::array();
    for (const auto& [name, v] : kernels) {
      Summary s = summarize(v);
      k.push_back({{"name", name}, {"median", s.median}, {"min", s.min}, {"max", s.max}});
    }
    json s = {{"config_id", id},
              {"config", first.at("config")},
              {"technique", str(first, "technique")},
              {"device_name", str(first, "device_name")},
              {"lanes_used", first.value("lanes_used", json())},
              {"features_used", first.value("features_used", json())},
              {"gbuffer_bytes_per_pixel", first.value("gbuffer_bytes_per_pixel", json())},
              {"frames", frames.size()},
              {"frame_list", frameList},
              {"compile_ms", summarize(compile).max},
              {"total_ms", summaryJson(summarize(total))},
              {"wall_ms", summaryJson(summarize(wall))},
              {"upload_ms", summaryJson(summarize(upload))},
              {"raster_ms", summaryJson(summarize(raster))},
              {"kernels", k},
              {"lighting_computations", summaryJson(summarize(lc))},
              {"evaluations", summaryJson(summarize(ev))},
              {"limit_ms", summaryJson(summarize(limitMs))},
              {"limit_pct", summaryJson(summarize(limitPct))},
              {"nonfinite_pixels_max", uint64_t(nonfinite)},
              {"flops_basis", bases.empty() ? "" : bases.size() == 1 ? *bases.begin() : "mixed"}};
    if (!errMax.empty()) {
      // The worst frame, infinities kept: summarize() skips them, but a frame with NaN/inf pixels
      // has an infinite error (and PSNR -inf), and PSNR +inf (exact) only if every frame is.
      auto worst = [](const std::vector<double>& v, double sign) {
        double w = -sign * INFINITY;
        for (double x : v)
          if (!std::isnan(x)) w = sign > 0 ? std::max(w, x) : std::min(w, x);
        return jsonNumber(w);
      };
      s["error"] = {{"frames", errMax.size()},
                    {"max_abs", worst(errMax, 1)},
                    {"rmse", worst(errRmse, 1)},
                    {"psnr_db", worst(errPsnr, -1)},
                    {"max_rel_peak", worst(errRel, 1)}};
    }
    out.push_back(s);
  }
  return out;
}

std::vector<int> selectErrorFrames(const std::string& spec, const std::vector<int>& timed) {
  std::string s = spec;
  s.erase(std::remove_if(s.begin(), s.end(), [](unsigned char c) { return std::isspace(c); }), s.end());
  if (s.empty() || s == "all") return timed;
  if (std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isdigit(c); }) && s.size() < 7) {
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
    throw Error("--error-frames: expected all, N (that many of the timed frames), A:B[:S] or "
                "a;b;c, got '" + shortText(spec) + "'");
  }
  std::vector<int> out;
  for (int t : timed)
    if (std::binary_search(listed.begin(), listed.end(), t)) out.push_back(t);
  return out;
}

BenchRunResult runBench(const BenchOptions& o) {
  checkInteger("--warmup", o.warmup, 0, kMaxWarmup);
  checkInteger("--repeat", o.repeat, 1, kMaxRepeat);
  o.frames.validate();
  selectErrorFrames(o.errorFrames, {0, 1, 2});
  if (o.resume && o.overwrite) throw Error("--resume and --overwrite exclude each other");

  BenchRunResult result;
  std::vector<BenchConfig> configs = expandSweep(o.sweep);
  result.configurations = configs.size();
  std::vector<Entry> entries;
  for (size_t i = 0; i < configs.size(); ++i)
    if (o.shard.selects(i)) {
      Entry e;
      e.index = i;
      e.config = configs[i];
      entries.push_back(std::move(e));
    }
  result.selected = entries.size();

  const std::string csvPath = o.outDir + "/bench.csv", jsonPath = o.outDir + "/bench.json",
                    summaryPath = o.outDir + "/summary.csv";
  std::error_code ec;
  bool csvExists = fs::exists(csvPath, ec);
  if (csvExists && !o.resume && !o.overwrite)
    throw Error(csvPath + " exists: pass --resume to continue that run or --overwrite to start over");
  for (const auto& p : {csvPath, jsonPath, summaryPath})
    if (fs::exists(p, ec) && !fs::is_regular_file(p, ec))
      throw Error(p + (fs::is_directory(p, ec) ? ": it is a directory" : " exists and is not a file"));

  // Everything that can be refused is refused before any file is written: the devices (one
  // context each, calibrated later, once, before anything is timed on it), the scenes, the frames.
  std::map<std::string, std::unique_ptr<ClContext>> contexts;
  for (const auto& e : entries)
    if (!contexts.count(e.config.device))
      contexts.emplace(e.config.device, std::make_unique<ClContext>(e.config.device));

  // Scenes (one per distinct scene definition) and the frames each configuration times.
  // Per scene definition: the scene (or imported G-buffer), its rasterizers, and its lights with
  // the scene's own ranges (before --light-threshold) for the error reference that every
  // configuration of the scene is measured against (src/bench/bench_frames.h).
  std::map<std::string, BenchScene> scenes;
  for (auto& e : entries) {
    std::string key = sceneKey(e.config);
    auto it = scenes.find(key);
    if (it == scenes.end())
      it = outOfMemoryAs("loading scene " + e.config.scene,
                         [&] { return scenes.try_emplace(key, e.config).first; });
    else
      it->second.check(e.config);
    e.frames = o.frames.resolve(it->second.pathLength());
    if (o.error) {
      auto ef = selectErrorFrames(o.errorFrames, e.frames);
      e.errorFrames.insert(ef.begin(), ef.end());
    }
  }

  // What is already there (resume): bench.csv is the record of completed rows, of which only
  // those this run would have written itself are kept (bench_resume.h); bench.json gives their
  // full JSON records (a row whose record disagrees was edited and is dropped; one without a
  // record, lost when a run was killed between the two writes, is rebuilt from the CSV).
  std::set<std::pair<std::string, int>> done;
  json rows = json::array(), runs = json::array();
  std::vector<std::string> keptLines;
  if (csvExists && o.resume) {
    std::map<std::string, ResumeExpectation> expected;
    for (const auto& e : entries)
      expected[e.config.id()] = {e.config, contexts.at(e.config.device)->deviceName(),
                                 {e.frames.begin(), e.frames.end()}, e.errorFrames};
    ResumeScan scan = scanBenchCsv(csvPath, expected, o.warmup, o.repeat);
    std::map<std::pair<std::string, int>, json> recorded;
    if (fs::exists(jsonPath, ec)) {
      // Cut short (a run killed while writing it) is said and survived; valid JSON that breaks
      // the strict rules (a key twice, deep nesting) was made by hand and is an error.
      const std::string text = readTextFile(jsonPath, "bench results");
      const json old = json::accept(text) ? parseStrictJson(text, jsonPath) : json();
      if (!old.is_object()) {
        std::cerr << "tileshade: warning: bench --resume: " << jsonPath
                  << " is not a bench.json; its rows come back from bench.csv, its earlier runs "
                     "are lost\n";
      } else {
        if (old.contains("rows") && old["rows"].is_array())
          for (const auto& r : old["rows"]) {
            if (!r.is_object() || !r.contains("frame") || !r["frame"].is_number_integer()) continue;
            recorded[{str(r, "config_id"), r["frame"].get<int>()}] = r;
          }
        if (old.contains("runs") && old["runs"].is_array()) runs = old["runs"];
      }
    }
    const std::vector<std::string> columns = benchCsvColumns();
    for (const auto& k : scan.kept) {
      std::vector<std::string> fields;
      for (const auto& c : columns) fields.push_back(k.fields.at(c));
      json row = rowFromCsv(k.fields, csvPath);
      auto rec = recorded.find({k.configId, k.frame});
      if (rec != recorded.end()) {
        std::vector<std::string> fromJson;
        try {
          fromJson = csvFieldsOf(rec->second);
        } catch (const std::exception&) {
        }
        if (fromJson != fields) {
          scan.drop("values that differ from its record in bench.json (edited?)", k.lineNumber);
          continue;
        }
        row = rec->second;
      }
      done.insert({k.configId, k.frame});
      rows.push_back(std::move(row));
      keptLines.push_back(k.line);
    }
    for (const auto& line : scan.describeDrops(csvPath))
      std::cerr << "tileshade: warning: bench --resume: " << line << "\n";
  }

  size_t pendingTotal = 0;
  for (auto& e : entries) {
    std::string id = e.config.id();
    for (int f : e.frames) {
      if (done.count({id, f})) ++result.skippedRows;
      else e.pending.insert(f);
    }
    pendingTotal += e.pending.size();
  }

  // Now the files: bench.csv starts again from its header and the kept rows (never appended
  // after rows that were dropped), then grows a row per measurement.
  fs::create_directories(o.outDir, ec);
  if (ec) throw Error("cannot create output folder " + o.outDir + ": " + ec.message());
  if (o.overwrite)
    for (const auto& p : {csvPath, jsonPath, summaryPath}) fs::remove(p, ec);
  {
    std::string text = csvLine(benchCsvColumns()) + "\n";
    for (const auto& line : keptLines) text += line + "\n";
    writeFileAtomically(csvPath, text);
  }
  std::ofstream csv(csvPath, std::ios::app);
  if (!csv) throw Error("cannot write " + csvPath);

  std::ostream& log = std::cout;
  if (o.printTable) {
    log << "bench: " << result.configurations << " configuration(s)";
    if (o.shard.count > 1)
      log << ", " << result.selected << " in shard " << o.shard.index << "/" << o.shard.count;
    log << "; " << pendingTotal << " measurement(s) to run";
    if (result.skippedRows) log << ", " << result.skippedRows << " already in " << csvPath;
    log << "\n";
  }

  json run = {{"started", nowUtc()},
              {"command", o.command},
              {"description", o.description},
              {"frames", o.frames.text},
              {"warmup", o.warmup},
              {"repeat", o.repeat},
              {"error", o.error},
              {"error_frames", o.errorFrames},
              {"shard", std::to_string(o.shard.index) + "/" + std::to_string(o.shard.count)},
              {"shade_flops", {{"blinn-phong", TS_SHADE_FLOPS_BLINN_PHONG},
                               {"metallic-roughness", TS_SHADE_FLOPS_METALLIC_ROUGHNESS}}},
              {"devices", json::array()}};
  auto writeJson = [&](bool finished) {
    json r = run;
    if (finished) r["finished"] = nowUtc();
    json all = runs;
    all.push_back(r);
    json doc = {{"tool", "tileshade bench"},
                {"format_version", 1},
                {"runs", all},
                {"summaries", summarizeRows(rows)},
                {"rows", rows}};
    writeFileAtomically(jsonPath, doc.dump(1) + "\n");
  };

  // Each device is calibrated once per run, when it is first used (before anything is timed).
  std::map<std::string, Calibration> calibrations;
  std::set<std::string> announced;
  auto context = [&](const std::string& spec) -> ClContext& {
    ClContext& cl = *contexts.at(spec);
    if (!announced.insert(spec).second) return cl;
    json device = {{"spec", spec.empty() ? "default" : spec},
                   {"name", cl.deviceName()},
                   {"type", cl.info().type},
                   {"compute_units", cl.info().computeUnits}};
    if (o.calibrate) {
      Calibration c = calibrate(cl, o.calibration);
      calibrations[spec] = c;
      device["calibration"] = c.toJson();
      if (o.printTable)
        log << "device: " << cl.deviceName() << "\n"
            << "calibration: copy bandwidth " << fixed(c.bandwidthGBs, 1) << " GB/s (median of "
            << c.copyMs.size() << ", " << (c.copyBytes >> 20) << " MiB read + written), peak "
            << fixed(c.peakGflops, 1) << " GFLOP/s (float" << (c.vectorWidth > 1 ? std::to_string(c.vectorWidth) : "")
            << " multiply-add chains, median of " << c.fmaMs.size() << ")\n";
    } else if (o.printTable) {
      log << "device: " << cl.deviceName() << " (not calibrated: no limit columns)\n";
    }
    run["devices"].push_back(device);
    return cl;
  };

  Progress progress(pendingTotal, o.progress);
  auto fail = [&](Entry& e, const std::string& what) {
    e.failed = true;
    e.technique.reset();
    std::string msg = e.config.key() + ": " + what;
    result.failures.push_back(msg);
    progress.note("bench: configuration failed: " + msg);
  };

  // Groups of configurations sharing the host-side frame (scene, lights, resolution): each frame
  // is rasterized once for the group, encoded once per precision, referenced once per precision.
  std::vector<std::string> groupOrder;
  std::map<std::string, std::vector<Entry*>> groups;
  for (auto& e : entries) {
    if (e.pending.empty()) continue;
    std::string k = e.config.frameKey();
    if (!groups.count(k)) groupOrder.push_back(k);
    groups[k].push_back(&e);
  }

  for (const auto& gk : groupOrder) {
    auto& group = groups[gk];
    const BenchConfig& g = group.front()->config;
    BenchScene& scene = scenes.at(sceneKey(g));
    for (Entry* e : group) {
      try {
        ClContext& cl = context(e->config.device);
        e->cl = &cl;
        e->deviceName = cl.deviceName();
        auto cal = calibrations.find(e->config.device);
        e->calibration = cal == calibrations.end() ? nullptr : &cal->second;
        double before = cl.compileMs();
        TechniqueConfig tc = e->config.techniqueConfig();
        tc.features = scene.features(e->config);
        e->features = tc.features;
        e->technique = createTechnique(e->config.technique, cl, tc);
        e->kernelOptions = tc.kernelOptions();
        e->compileMs = cl.compileMs() - before;
      } catch (const Error& x) {
        fail(*e, x.what());
      } catch (const cl::Error& x) {
        fail(*e, std::string("OpenCL error ") + x.what() + " (" + std::to_string(x.err()) + ")");
      }
    }
    std::set<int> frames;
    for (Entry* e : group) frames.insert(e->pending.begin(), e->pending.end());

    for (int f : frames) {
      PreparedFrame prepared = outOfMemoryAs(
          "preparing a " + std::to_string(g.width) + "x" + std::to_string(g.height) + " frame of " +
              g.scene,
          [&] { return scene.prepare(g, f); });
      // Each configuration's layout (precision x features), encoded once each, when needed.
      std::map<std::pair<GBufferFormat, std::string>, EncodedGBuffer> layouts;
      auto encoded = [&](GBufferFormat format, const SceneFeatures& features) -> const EncodedGBuffer& {
        auto key = std::make_pair(format, features.describe());
        auto it = layouts.find(key);
        if (it == layouts.end())
          it = layouts.emplace(key, encode(prepared.gbuffer, format, features)).first;
        return it->second;
      };
      std::map<std::pair<int, int>, ReferenceImage> references, shadingReferences;
      // The error reference of every configuration of this frame: the windowed model in double
      // from the fp32 G-buffer and the scene's own light ranges, so storage precision, light
      // ranges, arithmetic and culling all show in err_* (error_vs_stored isolates the last two).
      std::optional<ReferenceImage> sceneReference;
      auto sceneRef = [&]() -> const ReferenceImage& {
        if (!sceneReference)
          sceneReference = shadeReference(
              prepared.encoded, prepared.intrinsics,
              scene.ownRangeLights(prepared),
              prepared.ambient, TS_MODEL_WINDOWED);
        return *sceneReference;
      };
      const size_t pixels = size_t(g.width) * g.height;
      const uint64_t geometry = prepared.gbuffer.geometryPixels();

      for (Entry* e : group) {
        if (!e->pending.count(f)) continue;
        std::string label = e->config.technique + " " + std::to_string(e->config.tileWidth) + "x" +
                            std::to_string(e->config.tileHeight) + " " + toString(e->config.format) +
                            " frame " + std::to_string(f);
        if (e->failed) {
          progress.step(label + " (failed)");
          continue;
        }
        try {
          ClContext& cl = *e->cl;
          const EncodedGBuffer& enc = encoded(e->config.format, e->features);
          TechniqueConfig tc = e->config.techniqueConfig();
          tc.features = e->features;
          auto upload = [&] {
            return DeviceFrame::upload(cl, enc, prepared.intrinsics, prepared.lights, prepared.ambient);
          };
          if (!e->warmed) {
            for (int w = 0; w < o.warmup; ++w) {
              DeviceFrame df = upload();
              e->technique->render(df, FrameRequest{});
            }
            e->warmed = true;
          }
          struct Timed {
            FrameResult r;
            double wallMs, uploadMs;
          };
          std::vector<Timed> reps;
          for (int k = 0; k < o.repeat; ++k) {
            auto t0 = Clock::now();
            DeviceFrame df = upload();
            cl.queue().finish();
            double up = msSince(t0);
            FrameResult r = e->technique->render(df, FrameRequest{});
            double wall = msSince(t0);
            reps.push_back({std::move(r), wall, up});
          }
          std::vector<size_t> idx(reps.size());
          for (size_t i = 0; i < idx.size(); ++i) idx[i] = i;
          std::sort(idx.begin(), idx.end(), [&](size_t a, size_t b) { return reps[a].r.totalMs < reps[b].r.totalMs; });
          Timed& m = reps[idx[(idx.size() - 1) / 2]];

          std::optional<ErrorStats> error, errorStored, errorShading;
          const ReferenceImage* reference = nullptr;
          if (e->errorFrames.count(f)) {
            // The stored values decide the reference; the features' planes do not change them.
            std::pair<int, int> key{int(e->config.format), tc.shadingModel};
            auto it = references.find(key);
            if (it == references.end())
              it = references.emplace(key, shadeReference(enc, prepared.intrinsics, prepared.lights,
                                                          prepared.ambient, tc.shadingModel)).first;
            reference = &it->second;
            errorStored = compareToReference(m.r.image, *reference, kTolerance * reference->peak);
            // The same values with the kernels' float positions: the shading arithmetic alone.
            auto shading = shadingReferences.find(key);
            if (shading == shadingReferences.end())
              shading = shadingReferences.emplace(key, shadeReference(enc, prepared.intrinsics,
                                                      prepared.lights, prepared.ambient,
                                                      tc.shadingModel, 0, {},
                                                      ReferencePositions::KernelFloat)).first;
            errorShading = compareToReference(m.r.image, shading->second,
                                              kTolerance * shading->second.peak);
            // fp32 with the scene's own ranges is the scene reference itself: not shaded twice.
            bool same = e->config.format == GBufferFormat::FP32 &&
                        e->config.lightThreshold <= 0.0f && tc.shadingModel == TS_MODEL_WINDOWED;
            const ReferenceImage& truth = same ? *reference : sceneRef();
            error = compareToReference(m.r.image, truth, kTolerance * truth.peak);
          }

          // The limit: G-buffer read once + float4 image written once; contributing evaluations
          // (the reference's ideal count when computed, else the technique's own) x the model's
          // flops per evaluation (shadeFlops).
          double minBytes = double(pixels) * double(enc.bytesPerPixel()) + double(pixels) * 16.0;
          double contributing = reference ? double(reference->contributing) : double(m.r.counters.evaluations);
          double minFlops = contributing * shadeFlops(e->features.model);

          json row = techniqueJson(e->config.technique, m.r, error, std::nullopt);
          row["config_id"] = e->config.id();
          row["config"] = configJson(e->config);
          row["device_name"] = e->deviceName;
          row["lanes_used"] = e->technique->lanes();
          row["frame"] = f;
          row["lights"] = prepared.lights.size();
          row["geometry_pixels"] = geometry;
          row["wall_ms"] = m.wallMs;
          row["upload_ms"] = m.uploadMs;
          row["compile_ms"] = e->compileMs;
          row["raster_ms"] = prepared.rasterMs;
          row["features_used"] = e->features.describe();
          row["gbuffer_bytes_per_pixel"] = enc.bytesPerPixel();
          row["kernel_options"] = e->kernelOptions;
          row["warmup"] = o.warmup;
          row["repeat"] = o.repeat;
          json limit = {{"min_bytes", uint64_t(minBytes)},
                        {"min_flops", minFlops},
                        {"flops_basis", reference ? "reference" : "evaluations"}};
          if (e->calibration) {
            double lim = limitMs(*e->calibration, minBytes, minFlops);
            limit["bandwidth_gbs"] = e->calibration->bandwidthGBs;
            limit["peak_gflops"] = e->calibration->peakGflops;
            limit["limit_ms"] = lim;
            limit["limit_pct"] = m.r.totalMs > 0 ? 100.0 * lim / m.r.totalMs : 0.0;
          }
          row["limit"] = limit;
          if (reference) row["reference_contributing"] = reference->contributing;
          if (errorStored) row["error_vs_stored"] = errorJson(*errorStored);
          if (errorShading) row["error_shading"] = errorJson(*errorShading);

          csv << csvLine(csvFieldsOf(row)) << "\n";
          flushChecked(csv, csvPath);
          rows.push_back(std::move(row));
          ++result.measuredRows;
          e->pending.erase(f);
        } catch (const Error& x) {
          fail(*e, x.what());
        } catch (const cl::Error& x) {
          fail(*e, std::string("OpenCL error ") + x.what() + " (" + std::to_string(x.err()) + ")");
        }
        progress.step(label);
      }
      writeJson(false);
    }
    for (Entry* e : group) e->technique.reset();  // free the group's device buffers
  }
  progress.finish();

  result.summaries = summarizeRows(rows);
  writeJson(true);
  {
    std::ostringstream s;
    s << csvLine(summaryCsvColumns()) << "\n";
    for (const auto& sm : result.summaries) {
      std::vector<std::string> f = {str(sm, "config_id")};
      for (const auto& d : benchDimensions()) f.push_back(str(sm.at("config"), d.name.c_str()));
      auto med = [&](const char* k) { return numberText(num(sm.at(k), "median")); };
      std::string kernels;
      for (const auto& k : sm.at("kernels"))
        kernels += (kernels.empty() ? "" : ";") + k.at("name").get<std::string>() + "=" + numberText(num(k, "median"));
      const json err = sm.contains("error") ? sm["error"] : json::object();
      auto e = [&](const char* k) { return err.empty() ? std::string() : numberText(num(err, k)); };
      for (const auto& v :
           {str(sm, "device_name"), intText(sm, "lanes_used"), str(sm, "features_used"),
            intText(sm, "gbuffer_bytes_per_pixel"), intText(sm, "frames"), med("total_ms"),
            numberText(num(sm.at("total_ms"), "min")), numberText(num(sm.at("total_ms"), "max")),
            numberText(num(sm.at("total_ms"), "mean")), med("wall_ms"),
            numberText(num(sm.at("wall_ms"), "min")), numberText(num(sm.at("wall_ms"), "max")),
            med("upload_ms"), numberText(num(sm, "compile_ms")), med("raster_ms"), kernels,
            med("lighting_computations"), med("evaluations"), med("limit_ms"), med("limit_pct"),
            str(sm, "flops_basis"), intText(sm, "nonfinite_pixels_max"),
            err.empty() ? std::string() : intText(err, "frames"),
            e("max_abs"), e("rmse"), e("psnr_db"), e("max_rel_peak")})
        f.push_back(v);
      s << csvLine(f) << "\n";
    }
    writeFileAtomically(summaryPath, s.str());
  }

  if (o.printTable) {
    printTable(result.summaries, log);
    log << "wrote " << csvPath << ", " << jsonPath << ", " << summaryPath << "\n";
  }
  return result;
}

}  // namespace ts
