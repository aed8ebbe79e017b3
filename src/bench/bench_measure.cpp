#include "bench/bench_measure.h"

#include "reference/transparent_composite.h"
#include "render/receiver_rounding.h"

#include <algorithm>
#include <chrono>

#include "bench/bench_columns.h"
#include "shading/shading_cpu.h"  // TS_SHADE_FLOPS_* (kernels/shading.h)
#include "techniques/technique.h"
#include "render/stats.h"
#include "util/error.h"

namespace ts {
namespace {

using json = nlohmann::json;
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

json configJson(const BenchConfig& c) {
  json j = json::object();
  for (const auto& d : benchDimensions()) j[d.name] = d.get(c);
  return j;
}

// The limit: G-buffer read once + float4 image written once; contributing evaluations (the
// reference's ideal count when computed, else the technique's own) x the model's flops per
// evaluation (shadeFlops); as a time when the device was calibrated.
json limitJson(const BenchEntry& e, size_t pixels, const EncodedGBuffer& enc, const TimedFrame& m,
               const ReferenceImage* reference) {
  double minBytes = double(pixels) * double(enc.bytesPerPixel()) + double(pixels) * 16.0;
  double contributing =
      reference ? double(reference->contributing) : double(m.r.counters.evaluations);
  double minFlops = contributing * shadeFlops(e.features.model);
  json limit = {{"min_bytes", uint64_t(minBytes)},
                {"min_flops", minFlops},
                {"flops_basis", reference ? "reference" : "evaluations"}};
  if (e.calibration) {
    double lim = limitMs(*e.calibration, minBytes, minFlops);
    limit["bandwidth_gbs"] = e.calibration->bandwidthGBs;
    limit["peak_gflops"] = e.calibration->peakGflops;
    limit["limit_ms"] = lim;
    limit["limit_pct"] = m.r.totalMs > 0 ? 100.0 * lim / m.r.totalMs : 0.0;
    // The calibration's spread carried to the row: the same % from its slowest round's rates
    // (limit_pct uses the best round's; bench/README.md, "The device limit").
    Calibration slowest = *e.calibration;
    slowest.bandwidthGBs = slowest.bandwidth.min;
    slowest.peakGflops = slowest.peak.min;
    double slowLim = limitMs(slowest, minBytes, minFlops);
    limit["limit_pct_slowest_round"] = m.r.totalMs > 0 ? 100.0 * slowLim / m.r.totalMs : 0.0;
  }
  return limit;
}

}  // namespace

GroupFrame::GroupFrame(BenchScene& scene, const BenchConfig& group, int frame)
    : scene_(scene),
      prepared_(outOfMemoryAs("preparing a " + std::to_string(group.width) + "x" +
                                  std::to_string(group.height) + " frame of " + group.scene,
                              [&] { return scene.prepare(group, frame); })),
      shadows_(scene.drawShadows(group, prepared_)),
      forward_(scene.forwardScene(group, prepared_)),
      pixels_(size_t(group.width) * group.height),
      geometry_(prepared_.gbuffer.geometryPixels()) {}

const EncodedGBuffer& GroupFrame::encoded(GBufferFormat format, const SceneFeatures& features) {
  auto key = std::make_pair(format, features.describe());
  auto it = layouts_.find(key);
  if (it == layouts_.end())
    it = layouts_.emplace(key, encode(prepared_.gbuffer, format, features)).first;
  return it->second;
}

const ReferenceImage& GroupFrame::storedReference(const EncodedGBuffer& enc, GBufferFormat format,
                                                  int model, ReferencePositions positions) {
  auto& cache = positions == ReferencePositions::KernelFloat ? shadingReferences_ : references_;
  std::pair<int, int> key{int(format), model};
  auto it = cache.find(key);
  if (it == cache.end()) {
    ReferenceImage ref = shadeFrame(enc, prepared_.lights, model, positions);
    withTransparentSurfaces(ref, prepared_.lights, model);
    it = cache.emplace(key, std::move(ref)).first;
  }
  return it->second;
}

const ReferenceImage& GroupFrame::sceneReference() {
  if (!sceneReference_) {
    const ViewLights lights = scene_.ownRangeLights(prepared_);
    sceneReference_ =
        shadeFrame(prepared_.encoded, lights, TS_MODEL_WINDOWED, ReferencePositions::FromDepth);
    withTransparentSurfaces(*sceneReference_, lights, TS_MODEL_WINDOWED);
  }
  return *sceneReference_;
}

ReferenceImage GroupFrame::shadeFrame(const EncodedGBuffer& enc, const ViewLights& lights,
                                      int model, ReferencePositions positions) {
  const std::optional<ReceiverRounding> rounding = receiverRounding();
  const ReceiverRounding* slack = rounding ? &*rounding : nullptr;
  if (!forward_ || forward_->samples() <= 1)
    return shadeReference(enc, prepared_.intrinsics, lights, prepared_.ambient, model, 0, {},
                          positions, nullptr, slack);
  // The planes the configuration shades: tiled's, or (fp32) those the forward techniques'
  // fragments hold.
  return shadeSampleAverage(sampleGBuffers()->like(enc), prepared_.intrinsics, lights,
                            prepared_.ambient, model, positions, slack);
}

SampleGBuffers* GroupFrame::sampleGBuffers() {
  if (!forward_ || forward_->samples() <= 1) return nullptr;
  if (!samples_) samples_ = std::make_unique<SampleGBuffers>(*forward_, prepared_.features);
  return samples_.get();
}

const ExactVisibilityResult* GroupFrame::exactShadows() {
  if (!exactShadows_) {
    exactShadows_.emplace();
    if (prepared_.lights.hasShadows())
      *exactShadows_ = measureAgainstExactVisibility(scene_.scene(), prepared_, prepared_.encoded);
  }
  return *exactShadows_ ? &**exactShadows_ : nullptr;
}

void measureShadowError(GroupFrame& frame, const std::vector<glm::vec4>& image, FrameErrors& out) {
  out.shadowErrorWanted = true;
  out.exact = frame.exactShadows();
  if (out.exact)
    out.errorVsExact = compareToReference(image, out.exact->exactReference,
                                          kTolerance * out.exact->exactReference.peak);
}

std::optional<ReceiverRounding> GroupFrame::receiverRounding() const {
  return ts::receiverRounding(scene_.scene(), prepared_.camera.viewFromWorld);
}

const PerLightShadowMaps* GroupFrame::perLightShadows() {
  if (shadows_ && !perLightShadows_)
    perLightShadows_ = std::make_unique<PerLightShadowMaps>(scene_.scene(), shadows_->layout);
  return perLightShadows_.get();
}

void GroupFrame::withTransparentSurfaces(ReferenceImage& ref, const ViewLights& lights, int model) {
  // --blend blend: only the forward techniques render such a frame (the G-buffer ones refuse
  // it), and they blend its transparent surfaces over the opaque ones: so do the references.
  if (!forward_ || forward_->transparentDraws() == 0) return;
  if (!transparentFragments_)
    transparentFragments_ = forward_->captureTransparent(prepared_.features, kCaptureBound);
  compositeTransparent(ref, *transparentFragments_, lights, prepared_.ambient, model,
                       prepared_.encoded);
}

TimedFrame timeFrame(BenchEntry& e, const EncodedGBuffer& enc, const PreparedFrame& prepared,
                     ForwardScene* forward, SampleGBuffers* samples,
                     const PerLightShadowMaps* perLight, int warmup, int repeat) {
  ClContext& cl = *e.cl;
  auto upload = [&] {
    DeviceFrame df =
        DeviceFrame::upload(cl, enc, prepared.intrinsics, prepared.lights, prepared.ambient);
    df.forward = forward;
    df.samples = samples;
    df.perLightShadows = perLight;
    return df;
  };
  if (!e.warmed) {
    for (int w = 0; w < warmup; ++w) {
      DeviceFrame df = upload();
      e.technique->render(df, FrameRequest{});
    }
    e.warmed = true;
  }
  std::vector<TimedFrame> reps;
  for (int k = 0; k < repeat; ++k) {
    auto t0 = Clock::now();
    DeviceFrame df = upload();
    cl.queue().finish();
    double up = msSince(t0);
    FrameResult r = e.technique->render(df, FrameRequest{});
    double wall = msSince(t0);
    reps.push_back({std::move(r), wall, up});
  }
  std::vector<size_t> idx(reps.size());
  for (size_t i = 0; i < idx.size(); ++i) idx[i] = i;
  std::sort(idx.begin(), idx.end(),
            [&](size_t a, size_t b) { return reps[a].r.totalMs < reps[b].r.totalMs; });
  return std::move(reps[idx[(idx.size() - 1) / 2]]);
}

FrameErrors measureErrors(const BenchEntry& e, GroupFrame& frame, const EncodedGBuffer& enc,
                          const TechniqueConfig& tc, const std::vector<glm::vec4>& image) {
  FrameErrors out;
  // A technique that draws the scene reads no G-buffer: its stored references are the fp32
  // planes', whatever the configuration's layout (as render --check's; docs/accuracy.md).
  const bool drawn = findTechnique(e.config.technique).drawsScene;
  const GBufferFormat format = drawn ? GBufferFormat::FP32 : e.config.format;
  const EncodedGBuffer& planes = drawn ? frame.encoded(format, tc.features) : enc;
  out.reference =
      &frame.storedReference(planes, format, int(tc.rangeModel), ReferencePositions::FromDepth);
  // What lies beyond the shadow tests' slack over the receiver's rounding (reference.h).
  const ReceiverSlack slack = ReceiverSlack::Allow;
  out.errorStored =
      compareToReference(image, *out.reference, kTolerance * out.reference->peak, slack);
  const ReferenceImage& shading =
      frame.storedReference(planes, format, int(tc.rangeModel), ReferencePositions::KernelFloat);
  out.errorShading = compareToReference(image, shading, kTolerance * shading.peak, slack);
  // fp32 with the scene's own ranges is the scene reference itself: not shaded twice.
  bool same = format == GBufferFormat::FP32 && e.config.lightThreshold <= 0.0f &&
              tc.rangeModel == RangeModel::Windowed;
  const ReferenceImage& truth = same ? *out.reference : frame.sceneReference();
  out.error = compareToReference(image, truth, kTolerance * truth.peak, slack);
  return out;
}

json measurementRow(const BenchEntry& e, const GroupFrame& frame, int f, const EncodedGBuffer& enc,
                    const TimedFrame& m, const FrameErrors& err, int warmup, int repeat) {
  const PreparedFrame& prepared = frame.prepared();
  json row = techniqueJson(e.config.technique, m.r, err.error, std::nullopt);
  row["config_id"] = e.config.id();
  row["config"] = configJson(e.config);
  row["device_name"] = e.deviceName;
  row["lanes_used"] = e.technique->lanes();
  row["frame"] = f;
  row["lights"] = prepared.lights.size();
  row["geometry_pixels"] = frame.geometryPixels();
  row["wall_ms"] = m.wallMs;
  row["upload_ms"] = m.uploadMs;
  row["compile_ms"] = e.compileMs;
  row["raster_ms"] = prepared.rasterMs;
  // Drawn once per frame for the group, like the G-buffer: 0 without a shadow-casting light.
  // Per-light storage: the technique drew the maps itself, light by light (their sum), into one
  // reused atlas (its bytes: the largest light's maps; written: every drawn light's).
  const std::optional<FrameShadowUse>& own = m.r.shadowUse;
  const uint64_t atlasBytes = frame.shadows() ? frame.shadows()->layout.bytes() : uint64_t(0);
  row["shadow_ms"] = own ? own->drawMs : frame.shadows() ? frame.shadows()->drawMs : 0.0;
  row["shadow_bytes"] = own ? own->residentBytes : atlasBytes;
  row["shadow_bytes_written"] = own ? own->writtenBytes : atlasBytes;
  row["features_used"] = e.features.describe();
  row["gbuffer_bytes_per_pixel"] = enc.bytesPerPixel();
  row["kernel_options"] = e.kernelOptions;
  row["warmup"] = warmup;
  row["repeat"] = repeat;
  row["limit"] = limitJson(e, frame.pixels(), enc, m, err.reference);
  if (err.reference) row["reference_contributing"] = err.reference->contributing;
  if (err.errorStored) row["error_vs_stored"] = errorJson(*err.errorStored);
  if (err.errorShading) row["error_shading"] = errorJson(*err.errorShading);
  if (err.exact && err.errorVsExact) {
    // Relative to the exact-shaded reference's peak, as render's error_vs_exact.
    const nlohmann::json& wrong = err.exact->stats.at("wrong_pairs");
    const double peak = err.errorVsExact->peak > 0.0 ? err.errorVsExact->peak : 1.0;
    row["shadow_error"] = {{"pairs", wrong.at("pairs")},
                           {"false_shadow", wrong.at("false_shadow")},
                           {"light_leak", wrong.at("light_leak")},
                           {"wrong_pct", 100.0 * wrong.at("fraction").get<double>()},
                           {"mean_abs_factor_error", wrong.at("mean_abs_factor_error")},
                           {"err_max_rel_peak", err.errorVsExact->maxRelPeak},
                           {"err_rmse", err.errorVsExact->rmse / peak},
                           {"err_p99", err.errorVsExact->p99 / peak},
                           {"err_p50", err.errorVsExact->p50 / peak},
                           {"err_psnr_db", jsonNumber(err.errorVsExact->psnr)},
                           {"maps_err_max", err.exact->stats.at("image_error").at("max_rel_peak")},
                           {"exact_ms", err.exact->stats.at("build_ms").get<double>() +
                                            err.exact->stats.at("query_ms").get<double>()}};
  } else if (err.shadowErrorWanted) {
    row["notes"].push_back(kNoShadowErrorNote);
  }
  return row;
}

}  // namespace ts
