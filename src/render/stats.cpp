#include "render/stats.h"

#include <cmath>

namespace ts {

nlohmann::json jsonNumber(double v) {
  if (std::isfinite(v)) return v;
  if (std::isnan(v)) return "nan";
  return v > 0 ? "inf" : "-inf";
}

nlohmann::json errorJson(const ErrorStats& e) {
  nlohmann::json j = {{"max_abs", jsonNumber(e.maxAbs)},
                      {"rmse", jsonNumber(e.rmse)},
                      {"psnr_db", jsonNumber(e.psnr)},
                      {"max_rel_peak", jsonNumber(e.maxRelPeak)},
                      {"p50", jsonNumber(e.p50)},
                      {"p99", jsonNumber(e.p99)},
                      {"p999", jsonNumber(e.p999)},
                      {"tolerance", jsonNumber(e.tolerance)},
                      {"pixels_above_tolerance", e.pixelsAboveTolerance},
                      {"nonfinite_pixels", e.nonfinitePixels},
                      {"reference_peak", jsonNumber(e.peak)}};
  // Only where the comparison allowed the receivers' slack (a forward technique's image).
  if (e.receiverSlack)
    j["receiver_slack"] = {{"pixels", e.slackPixels},
                           {"ambiguous_shadow_pairs", e.ambiguousShadowPairs}};
  return j;
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
      {"nonfinite_pixels", countNonFinitePixels(r.image)},
      {"lights_per_bin", {{"min", c.listMin}, {"mean", c.listMean}, {"max", c.listMax}}},
      {"notes", c.notes},
  };
  if (error) j["error"] = errorJson(*error);
  if (missed) j["missed_contributions"] = *missed;
  // --msaa in tiled: what its multisampled G-buffer held and where it shaded per sample.
  if (c.sampleShading)
    j["msaa_gbuffer"] = {{"samples", c.sampleShading->samples},
                         {"pixels_shaded_per_sample", c.sampleShading->pixelsShadedPerSample},
                         {"gbuffer_bytes", c.sampleShading->gbufferBytes}};
  return j;
}

}  // namespace ts
