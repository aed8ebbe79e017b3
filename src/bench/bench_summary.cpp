#include "bench/bench_summary.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <vector>

#include "bench/bench_columns.h"
#include "bench/bench_config.h"
#include "bench/bench_stats.h"
#include "shading/shading_cpu.h"  // TS_SHADE_FLOPS_* (kernels/shading.h)
#include "render/stats.h"

namespace ts {
namespace {

using json = nlohmann::json;

double num(const json& j, const char* key) { return jsonDoubleOf(findKey(j, key)); }
std::string str(const json& j, const char* key) { return jsonTextOf(findKey(j, key)); }

json summaryJson(const Summary& s) {
  // No values (an uncalibrated bench's limit_pct): no statistics, not a median of 0.
  if (s.n == 0)
    return {{"n", 0}, {"median", nullptr}, {"min", nullptr}, {"max", nullptr}, {"mean", nullptr}};
  return {{"n", s.n}, {"median", s.median}, {"min", s.min}, {"max", s.max}, {"mean", s.mean}};
}

}  // namespace

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
    std::vector<double> total, wall, upload, raster, shadow, lc, ev, limitMs, limitPct, compile;
    std::vector<std::pair<std::string, std::vector<double>>> kernels;
    std::set<std::string> bases;
    std::vector<double> errMax, errRmse, errPsnr, errRel;
    double nonfinite = 0.0, shadowBytes = 0.0;
    json frameList = json::array();
    for (const auto& [frame, rp] : frames) {
      const json& r = *rp;
      frameList.push_back(frame);
      total.push_back(num(r, "total_ms"));
      wall.push_back(num(r, "wall_ms"));
      upload.push_back(num(r, "upload_ms"));
      raster.push_back(num(r, "raster_ms"));
      // Rows written before bench drew shadow maps have none: they drew none.
      shadow.push_back(r.contains("shadow_ms") ? num(r, "shadow_ms") : 0.0);
      if (r.contains("shadow_bytes")) shadowBytes = std::max(shadowBytes, num(r, "shadow_bytes"));
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
        auto it = std::find_if(kernels.begin(), kernels.end(),
                               [&](const auto& p) { return p.first == name; });
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
              {"shadow_ms", summaryJson(summarize(shadow))},
              {"shadow_bytes_max", uint64_t(shadowBytes)},
              {"kernels", k},
              {"lighting_computations", summaryJson(summarize(lc))},
              {"evaluations", summaryJson(summarize(ev))},
              {"limit_ms", summaryJson(summarize(limitMs))},
              {"limit_pct", summaryJson(summarize(limitPct))},
              {"nonfinite_pixels_max", uint64_t(nonfinite)},
              {"flops_basis", bases.empty()       ? ""
                              : bases.size() == 1 ? *bases.begin()
                                                  : "mixed"}};
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

std::string summaryCsvText(const json& summaries) {
  std::string text = csvLine(summaryCsvColumns()) + "\n";
  for (const auto& s : summaries) text += csvLine(csvFields(summaryColumns(), s)) + "\n";
  return text;
}

void printSummaryTable(const json& summaries, std::ostream& out) {
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
  for (const char* h : {"median ms", "(min-max)", "wall ms", "raster ms", "shadow ms", "% limit",
                        "per-kernel median ms"})
    head.push_back(h);
  table.push_back(head);
  for (const auto& s : summaries) {
    std::vector<std::string> row;
    for (const auto& d : shown) row.push_back(str(s.at("config"), d.c_str()));
    const json& t = s.at("total_ms");
    row.push_back(fixedText(num(t, "median"), 3));
    row.push_back("(" + fixedText(num(t, "min"), 3) + "-" + fixedText(num(t, "max"), 3) + ")");
    row.push_back(fixedText(num(s.at("wall_ms"), "median"), 2));
    row.push_back(fixedText(num(s.at("raster_ms"), "median"), 2));
    row.push_back(fixedText(num(s.at("shadow_ms"), "median"), 2));
    std::string pct = fixedText(num(s.at("limit_pct"), "median"), 1);
    std::string basis = str(s, "flops_basis");
    row.push_back(pct == "-" ? pct
                             : pct + (basis == "reference"     ? ""
                                      : basis == "evaluations" ? "*"
                                                               : "~"));
    std::string kernels;
    for (const auto& k : s.at("kernels"))
      kernels += (kernels.empty() ? "" : " ") + k.at("name").get<std::string>() + "=" +
                 fixedText(num(k, "median"), 3);
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
  out << "% limit: device limit time / measured kernel time (median over frames); limit = "
         "max(bytes / copy bandwidth, contributing evaluations x "
      << TS_SHADE_FLOPS_BLINN_PHONG << " (Blinn-Phong) or " << TS_SHADE_FLOPS_METALLIC_ROUGHNESS
      << " (metallic-roughness) FLOP / peak). Evaluations counted by the reference, or * by the "
         "technique itself (~ mixed).\n";
}

}  // namespace ts
