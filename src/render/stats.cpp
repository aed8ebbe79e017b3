#include "render/stats.h"

#include <cmath>

namespace ts {

nlohmann::json errorJson(const ErrorStats& e) {
  auto finite = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json("inf"); };
  return {{"max_abs", e.maxAbs},       {"rmse", e.rmse},
          {"psnr_db", finite(e.psnr)}, {"max_rel_peak", e.maxRelPeak},
          {"p50", e.p50},              {"p99", e.p99},
          {"p999", e.p999},            {"tolerance", e.tolerance},
          {"pixels_above_tolerance", e.pixelsAboveTolerance},
          {"reference_peak", e.peak}};
}

nlohmann::json techniqueJson(const std::string& name, const FrameResult& r,
                             const std::optional<ErrorStats>& error,
                             const std::optional<uint64_t>& missed) {
  nlohmann::json kernels = nlohmann::json::array();
  for (const auto& k : r.kernels)
    kernels.push_back({{"name", k.name}, {"ms", k.ms}, {"launches", k.launches}});
  const WorkCounters& c = r.counters;
  nlohmann::json j = {
      {"technique", name},
      {"kernels", kernels},
      {"total_ms", r.totalMs},
      {"lighting_computations", c.lightingComputations},
      {"evaluations", c.evaluations},
      {"gbuffer_bytes_read", c.gbufferBytesRead},
      {"lights_per_bin", {{"min", c.listMin}, {"mean", c.listMean}, {"max", c.listMax}}},
      {"notes", c.notes},
  };
  if (error) j["error"] = errorJson(*error);
  if (missed) j["missed_contributions"] = *missed;
  return j;
}

}  // namespace ts
