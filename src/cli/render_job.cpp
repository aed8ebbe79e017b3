#include "cli/render_job.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <iostream>
#include <optional>
#include <sstream>

#include <nlohmann/json.hpp>

#include "api/api_internal.h"
#include "cli/exact_visibility_job.h"
#include "gbuffer/image_io.h"
#include "reference/error_metrics.h"
#include "render/stats.h"
#include "techniques/math_mode_note.h"
#include "techniques/technique.h"
#include "tileshade/tileshade.h"
#include "util/error.h"
#include "util/file_write.h"
#include "util/option_values.h"
#include "util/progress.h"

namespace fs = std::filesystem;

namespace ts {
namespace {

// Progress of the double-precision reference on stderr when it is long (1e5-1e6 lights: minutes
// per pass); nothing for the usual few-second ones.
class ReferenceProgress {
 public:
  ReferenceProgress(size_t pixels, size_t lights, int passes, int rows)
      : progress_(size_t(passes) * size_t(rows),
                  double(pixels) * double(lights) * passes >= kLongReferenceEvaluations,
                  "tileshade: reference") {}
  // The RowProgress of one pass called `label`.
  RowProgress pass(const std::string& label) {
    return [this, label](int, int) { progress_.step(label); };
  }

 private:
  // About 5-10 s of reference shading on two cores.
  static constexpr double kLongReferenceEvaluations = 2e9;
  Progress progress_;
};

// "all": every technique, in the registry's order (techniquesForFrame leaves out those that
// cannot run on the frame); other names as given.
std::vector<std::string> expandTechniques(const std::vector<std::string>& names) {
  std::vector<std::string> out;
  for (const auto& n : names) {
    if (n == "all") {
      for (const TechniqueDescription& t : listTechniques()) out.push_back(t.name);
    } else {
      out.push_back(n);
    }
  }
  if (out.empty()) throw Error("no technique given");
  return out;
}

// The registry's description of `name` (ts::Error naming the known techniques if none).
TechniqueDescription describeTechnique(const std::string& name) {
  for (const TechniqueDescription& t : listTechniques())
    if (t.name == name) return t;
  findTechnique(name);  // throws
  return {};
}

// Why a technique cannot render this frame: `all` leaves it out saying `reason`; one named
// explicitly is refused with `refusal`'s line (none: refused later, by Renderer, before any
// file).
struct Exclusion {
  std::function<bool(const TechniqueDescription&)> applies;
  std::string reason;
  std::function<std::string(const TechniqueDescription&)> refusal;
};

// The techniques to render on a frame described by `info`: the first exclusion that applies to
// a technique decides. Said (and refused) before any file is written.
std::vector<std::string> techniquesForFrame(const RenderOptions& options, const FrameInfo& info) {
  const size_t glass = info.transparentDraws;
  const std::vector<Exclusion> exclusions = {
      // Per-light shadow storage: `all` means the techniques that can reuse one map per light.
      {[&](const TechniqueDescription& t) {
         return options.shadowStorage == ShadowStorage::PerLight && !t.reusesShadowMaps;
       },
       "--shadow-storage per-light: it shades every light at once and needs every map resident",
       nullptr},
      // The G-buffer holds the opaque surfaces only: never a G-buffer image without the glass.
      {[&](const TechniqueDescription& t) {
         return glass > 0 && !t.drawsScene && !t.hybridTransparency;
       },
       "it shades the G-buffer, which holds the opaque surfaces only, and has no transparent pass",
       [&](const TechniqueDescription& t) { return transparencyRefusal(t.name, glass); }},
      // --msaa: only the techniques that take it (TechniqueInfo::multisamples).
      {[&](const TechniqueDescription& t) { return info.msaa > 1 && !t.multisamples; },
       "--msaa " + std::to_string(info.msaa) + " is not done for it",
       [&](const TechniqueDescription& t) { return msaaRefusal(t.name, info.msaa); }},
      // A frame without a scene to draw (software raster, imported G-buffer).
      {[&](const TechniqueDescription& t) { return t.drawsScene && !info.drawsScene; },
       "it draws the scene: --raster gl",
       [](const TechniqueDescription& t) {
         return t.name +
                " draws the scene: it needs a frame rasterized with --raster gl (not the "
                "software rasterizer or an imported G-buffer)";
       }},
  };
  std::vector<std::string> out;
  for (const std::string& name : expandTechniques(options.techniques)) {
    const TechniqueDescription& t = describeTechnique(name);
    const bool named = std::count(options.techniques.begin(), options.techniques.end(), name) > 0;
    auto e = std::find_if(exclusions.begin(), exclusions.end(),
                          [&](const Exclusion& x) { return x.applies(t); });
    if (e == exclusions.end() || (named && !e->refusal)) {
      out.push_back(name);
    } else if (named) {
      throw Error(e->refusal(t));
    } else {
      std::cout << "tileshade: --technique all leaves out " << name << " (" << e->reason << ")\n";
    }
  }
  return out;
}

}  // namespace

void validateRenderOptions(const RenderOptions& o) {
  checkInteger("--light-count", o.lightCount, -1, kMaxLightCount);
  checkNumber("--light-range", o.lightRange, NumberRule::AtLeastZero);
  checkNumber("--light-threshold", o.lightThreshold, NumberRule::AtLeastZero);
  checkInteger("--width", o.width, 1, kMaxImageSide);
  checkInteger("--height", o.height, 1, kMaxImageSide);
  checkInteger("--frame", o.frame, 0, INT32_MAX);
  checkInteger("--tile", o.tileWidth, 1, kMaxTileSide);
  checkInteger("--tile", o.tileHeight, 1, kMaxTileSide);
  checkInteger("--slices", o.clusterSlices, 1, kMaxClusterSlices);
  checkNumber("--exposure", o.exposure, NumberRule::AboveZero);
  if (o.heatmap && !o.check) throw Error("--heatmap needs --check (it maps the error)");
  if (o.exactVisibility && !o.gbufferIn.empty())
    throw Error(
        "--exact-visibility needs the scene's triangles: an imported G-buffer "
        "(--gbuffer-in) has none");
  checkMsaa(o.msaa, o.raster);
  if (o.msaa > 1 && !o.gbufferIn.empty())
    throw Error("--msaa needs a scene to draw: an imported G-buffer (--gbuffer-in) has one sample");
  if (o.msaa > 1 && o.exactVisibility)
    throw Error("--exact-visibility with --msaa " + std::to_string(o.msaa) +
                " is not done: exact visibility is traced per pixel, not per sample");
  if (o.shadingModel != "auto") parseShadingModel(o.shadingModel);
  for (const auto& t : expandTechniques(o.techniques)) findTechnique(t);
}

namespace {

// stats.json's shadow_maps: null without a shadow-casting light.
nlohmann::json shadowMapsJson(const FrameInfo& info, const RenderOptions& o) {
  if (!info.shadowMaps) return nullptr;
  const ShadowMapsInfo& s = *info.shadowMaps;
  nlohmann::json lights = nlohmann::json::array();
  for (const ShadowMapLight& l : s.lights)
    lights.push_back({{"light", l.light},
                      {"type", l.type},
                      {"faces", l.faces},
                      {"requested_size", l.requestedSize},
                      {"size", l.size}});
  return {{"map_size", o.shadowMapSize},
          {"budget_mb", o.shadowBudgetMB},
          {"filter", o.shadowFilter},
          {"bias", o.shadowBias},
          {"faces", s.faces},
          {"atlas_width", s.atlasWidth},
          {"atlas_height", s.atlasHeight},
          {"bytes", s.bytes},
          {"triangles_drawn", s.trianglesDrawn},
          {"draw_ms", s.drawMs},
          {"rasterizer", s.rasterizer},
          {"read_ms", s.readMs},
          {"lights", lights},
          {"notes", s.notes}};
}

// A technique's record of the maps it drew itself (per-light storage), null where it sampled the
// frame's atlas (shadow_maps) or no light casts a shadow.
nlohmann::json shadowUseJson(const ShadeResult& r) {
  if (!r.shadowUse) return nullptr;
  const ShadowUse& s = *r.shadowUse;
  return {{"passes", s.passes},
          {"draw_ms", s.drawMs},
          {"resident_bytes", s.residentBytes},
          {"written_bytes", s.writtenBytes},
          {"triangles_drawn", s.trianglesDrawn}};
}

std::string kernelSummary(const ShadeResult& r) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(3);
  for (size_t i = 0; i < r.kernels.size(); ++i)
    s << (i ? " " : "") << r.kernels[i].name << "=" << r.kernels[i].ms;
  return s.str();
}

// The frame `render` shades: its scene rasterized, or its --gbuffer-in files.
Frame loadFrame(Device& device, const RenderOptions& o) {
  if (!o.gbufferIn.empty()) {
    Frame frame =
        Frame::fromFiles(device, o.gbufferIn, o.keepInputLayout ? "" : toString(o.format));
    overrideFrameFeatures(frame, o.features);
    return frame;
  }
  SceneRequest r;
  r.scene = o.scene;
  r.lights = o.lightSet;
  r.lightCount = o.lightCount;
  r.lightRange = o.lightRange;
  r.lightThreshold = o.lightThreshold;
  r.variant = o.variant;
  r.normalMaps = o.normalMaps;
  r.shadows = o.shadows;
  r.shadowMapSize = o.shadowMapSize;
  r.shadowBudgetMB = o.shadowBudgetMB;
  r.blend = toString(o.blend);
  r.shadowFilter = o.shadowFilter;
  r.shadowBias = o.shadowBias;
  r.shadingModel = o.shadingModel;
  r.features = o.features;
  r.seed = o.seed;
  r.width = o.width;
  r.height = o.height;
  r.frame = o.frame;
  r.layout = toString(o.format);
  r.raster = toString(o.raster);
  r.msaa = o.msaa;
  return Frame::fromScene(device, r);
}

Settings settingsOf(const RenderOptions& o, const std::string& technique) {
  Settings s;
  s.technique = technique;
  s.tileWidth = o.tileWidth;
  s.tileHeight = o.tileHeight;
  s.slices = o.clusterSlices;
  s.culling = toString(o.culling);
  s.spotCulling = toString(o.spotCulling);
  s.depthSplit = o.depthSplit;
  s.math = toString(o.math);
  s.lanes = lanesName(o.lanes);
  s.shadowStorage = toString(o.shadowStorage);
  return s;
}

ErrorStats errorStats(const ErrorReport& e) {
  ErrorStats s;
  s.maxAbs = e.maxAbs;
  s.rmse = e.rmse;
  s.psnr = e.psnr;
  s.maxRelPeak = e.maxRelPeak;
  s.p50 = e.p50;
  s.p99 = e.p99;
  s.p999 = e.p999;
  s.tolerance = e.tolerance;
  s.pixelsAboveTolerance = e.pixelsAboveTolerance;
  s.nonfinitePixels = e.nonfinitePixels;
  s.peak = e.peak;
  s.receiverSlack = e.receiverSlack;
  s.slackPixels = e.slackPixels;
  s.ambiguousShadowPairs = e.ambiguousShadowPairs;
  return s;
}

// stats.json's record of one technique (techniqueJson reads a FrameResult).
FrameResult frameResultOf(const ShadeResult& r, std::vector<glm::vec4> image) {
  FrameResult f;
  f.image = std::move(image);
  for (const auto& k : r.kernels) f.kernels.push_back({k.name, k.ms, k.launches});
  f.totalMs = r.totalMs;
  f.counters.lightingComputations = r.counters.lightingComputations;
  f.counters.evaluations = r.counters.evaluations;
  f.counters.gbufferBytesRead = r.counters.gbufferBytesRead;
  f.counters.listMin = r.counters.listMin;
  f.counters.listMean = r.counters.listMean;
  f.counters.listMax = r.counters.listMax;
  f.counters.notes = r.counters.notes;
  if (r.counters.msaaSamples > 1)
    f.counters.sampleShading = SampleShading{
        r.counters.msaaSamples, r.counters.pixelsShadedPerSample, r.counters.msaaGBufferBytes};
  return f;
}

}  // namespace

void runRender(const RenderOptions& options) {
  // Every option is checked before any work, so a bad one never follows written images.
  validateRenderOptions(options);
  Device device(options.device);  // a bad --device fails before the scene is loaded
  Frame frame = loadFrame(device, options);
  const FrameInfo& info = frame.info();
  // Shadow maps that lost resolution to the budget (or cover less than a spot cone): never silent.
  if (info.shadowMaps)
    for (const std::string& note : info.shadowMaps->notes)
      std::cerr << "tileshade: note: " << note << "\n";
  const std::string mathNote = mathModeNote(options.math, device.name(), device.type());
  if (!mathNote.empty()) std::cerr << "tileshade: note: " << mathNote << "\n";
  const std::vector<std::string> techniques = techniquesForFrame(options, info);
  const bool multisampled = info.msaa > 1;
  const RenderOptions& o = options;
  const int width = info.width, height = info.height;  // an imported G-buffer decides the size

  // Every technique is created (its configuration checked, its kernels built) before the first
  // one renders: one that refuses the configuration (e.g. slices beyond the device's local
  // memory) fails before any file is written.
  std::vector<Renderer> renderers;
  for (const auto& name : techniques) {
    renderers.emplace_back(device, settingsOf(o, name));
    renderers.back().prepare(frame);
  }

  // Before any file: a frame without a shadow-casting light is refused here.
  std::optional<ExactVisibilityResult> exact;
  if (o.exactVisibility) exact = exactVisibility(frame);

  std::error_code ec;
  fs::create_directories(o.outDir, ec);
  if (ec) throw Error("cannot create output folder " + o.outDir + ": " + ec.message());

  // Three references (FrameReferences; docs/accuracy.md), computed once for every technique.
  // --msaa: three per sample, averaged (those of the techniques that draw the scene where one
  // does, else tiled's, in the frame's layout).
  ReferenceProgress progress(size_t(width) * size_t(height), info.lights - info.directionalLights,
                             3 * info.msaa, height);
  const FrameReferences* references =
      o.check
          ? &frameReferences(
                frame, [&](const std::string& label) { return progress.pass(label); },
                multisampled &&
                    std::any_of(techniques.begin(), techniques.end(),
                                [](const std::string& t) { return findTechnique(t).drawsScene; }))
          : nullptr;

  std::cout << "tileshade: " << info.sceneName << " (" << info.triangles << " triangles, "
            << info.lightSummary << "), frame " << info.frame << ", " << width << "x" << height
            << ", G-buffer " << info.layout << " (" << info.bytesPerPixel << " B/pixel), tile "
            << o.tileWidth << "x" << o.tileHeight << "\n"
            << "features: " << info.features << "\n"
            << "raster: " << info.sourceDetail << ", " << std::fixed << std::setprecision(1)
            << info.rasterMs << " ms (setup " << info.rasterSetupMs << " ms)\n"
            << std::defaultfloat;
  if (info.shadowMaps)
    std::cout << "shadow maps: " << info.shadowMaps->faces << " face(s) of "
              << info.shadowMaps->lights.size() << " light(s) in a " << info.shadowMaps->atlasWidth
              << "x" << info.shadowMaps->atlasHeight << " atlas (" << std::fixed
              << std::setprecision(1) << double(info.shadowMaps->bytes) / double(1 << 20)
              << " MB), " << info.shadowMaps->drawMs << " ms (" << info.shadowMaps->rasterizer
              << ", depth only)\n"
              << std::defaultfloat;
  if (exact) std::cout << exact->summary << "\n";
  std::cout << "device: " << device.name() << "\n";
  if (references)
    std::cout << "reference: " << references->reference.contributing
              << " contributing light evaluations (the ideal), peak " << references->reference.peak
              << "\n";

  nlohmann::json results = nlohmann::json::array();
  std::string kernelOptions;
  std::ostringstream table;
  table << std::left << std::setw(18) << "technique" << std::right << std::setw(6) << "lanes"
        << std::setw(10) << "total ms" << std::setw(16) << "lighting comp." << std::setw(15)
        << "evaluations" << std::setw(13) << "max err/peak" << std::setw(13) << "shading err"
        << std::setw(8) << "missed" << std::setw(12) << "G-buf MB"
        << "  per-kernel ms\n";
  for (size_t t = 0; t < techniques.size(); ++t) {
    const std::string& name = techniques[t];
    ShadeOptions shadeOptions;
    shadeOptions.check = o.check;
    const ShadeResult r = renderers[t].shade(frame, shadeOptions);
    kernelOptions = r.kernelOptions;
    std::vector<glm::vec4> image(size_t(width) * size_t(height));
    for (size_t i = 0; i < image.size(); ++i)
      image[i] = {r.rgba[4 * i], r.rgba[4 * i + 1], r.rgba[4 * i + 2], r.rgba[4 * i + 3]};

    std::string dir = techniques.size() == 1 ? o.outDir : o.outDir + "/" + name;
    fs::create_directories(dir, ec);
    if (ec) throw Error("cannot create output folder " + dir + ": " + ec.message());
    writeExrRgb(dir + "/image.exr", width, height, image);
    writePngToneMapped(dir + "/image.png", width, height, image, o.exposure);

    std::optional<ErrorStats> error, errorShading, errorPhysical;
    std::optional<uint64_t> missed;
    if (r.check) {
      error = errorStats(r.check->error);
      errorShading = errorStats(r.check->shadingError);
      errorPhysical = errorStats(r.check->physicalError);
      if (r.check->missedCounted) missed = r.check->missed;
      if (o.heatmap) {
        // A technique that draws the scene has its own references (fp32 planes; the check's).
        const ReferenceImage& reference =
            findTechnique(name).drawsScene || multisampled
                ? frameReferences(frame, {}, findTechnique(name).drawsScene).reference
                : references->reference;
        writeHeatMapPng(dir + "/error.png", width, height, errorMap(image, reference),
                        float(1e-7 * reference.peak), float(1e-2 * reference.peak));
      }
    }
    // Against the perfect shadow: the reference shaded with exact visibility.
    std::optional<ErrorStats> errorVsExact;
    if (exact)
      errorVsExact =
          compareToReference(image, exact->exactReference, 1e-4 * exact->exactReference.peak);
    results.push_back(techniqueJson(name, frameResultOf(r, std::move(image)), error, missed));
    results.back()["lanes"] = r.lanes;
    if (errorShading) results.back()["error_shading"] = errorJson(*errorShading);
    if (errorPhysical) results.back()["error_vs_physical"] = errorJson(*errorPhysical);
    if (errorVsExact) results.back()["error_vs_exact"] = errorJson(*errorVsExact);
    results.back()["shadow_use"] = shadowUseJson(r);

    auto relPeak = [](const std::optional<ErrorStats>& e) {
      std::ostringstream text;
      if (e) text << std::scientific << std::setprecision(2) << e->maxRelPeak;
      else text << "-";
      return text.str();
    };
    table << std::left << std::setw(18) << name << std::right << std::setw(6) << r.lanes
          << std::fixed << std::setprecision(3) << std::setw(10) << r.totalMs << std::setw(16)
          << r.counters.lightingComputations << std::setw(15) << r.counters.evaluations
          << std::setw(13) << relPeak(error) << std::setw(13) << relPeak(errorShading)
          << std::setw(8) << (missed ? std::to_string(*missed) : std::string("-")) << std::setw(12)
          << std::setprecision(1) << double(r.counters.gbufferBytesRead) / 1e6 << "  "
          << kernelSummary(r) << "\n";
    if (errorVsExact)
      table << "    vs exact visibility (the perfect shadow): max err/peak "
            << relPeak(errorVsExact) << ", rmse " << std::scientific << std::setprecision(2)
            << errorVsExact->rmse << std::defaultfloat << "\n";
    if (r.shadowUse)
      table << "    shadow maps per light: " << r.shadowUse->passes << " pass(es), " << std::fixed
            << std::setprecision(1) << r.shadowUse->drawMs << " ms drawing, "
            << double(r.shadowUse->residentBytes) / double(1 << 20) << " MB resident, "
            << double(r.shadowUse->writtenBytes) / double(1 << 20) << " MB written"
            << std::defaultfloat << "\n";
    if (r.counters.msaaSamples > 1)
      table << "    per-sample shading: " << r.counters.pixelsShadedPerSample << " of "
            << uint64_t(width) * uint64_t(height) << " pixels are edges (their "
            << r.counters.msaaSamples << " samples differ), shaded per sample; G-buffer "
            << std::fixed << std::setprecision(1) << double(r.counters.msaaGBufferBytes) / 1e6
            << " MB over the samples" << std::defaultfloat << "\n";
    for (const auto& note : r.counters.notes) table << "    note: " << note << "\n";
    if (r.check && r.check->error.slackPixels)
      table << "    note: " << r.check->error.ambiguousShadowPairs
            << " (pixel, light) pair(s) whose shadow test lies within float rounding of the "
               "receiver's position: either answer allowed on "
            << r.check->error.slackPixels << " pixel(s) (error.receiver_slack in stats.json)\n";
    if (r.nonfinitePixels)
      table << "    note: " << r.nonfinitePixels
            << " pixel(s) NaN or inf (nonfinite_pixels in stats.json)\n";
  }
  std::cout << table.str();

  nlohmann::json stats = {
      {"device", device.name()},
      {"device_type", device.type()},
      {"scene", info.sceneName},
      {"scene_spec", o.gbufferIn.empty() ? o.scene : "gbuffer-in:" + o.gbufferIn},
      {"light_set", o.lightSet},
      {"lights", info.lights},
      {"directional_lights", info.directionalLights},
      {"triangles", info.triangles},
      {"frame", info.frame},
      {"width", width},
      {"height", height},
      {"gbuffer", info.layout},
      {"gbuffer_bytes_per_pixel", info.bytesPerPixel},
      {"shading_model", info.shadingModel},
      {"features", info.features},
      {"kernel_options", kernelOptions},
      {"variant", o.variant},
      {"normal_maps", o.normalMaps},
      {"shadows", o.shadows.empty() ? "scene" : o.shadows},
      {"blend", toString(o.blend)},
      {"shadow_casting_lights", info.shadowCastingLights},
      {"shadow_maps", shadowMapsJson(info, o)},
      {"shadow_storage", toString(o.shadowStorage)},
      {"exact_visibility", exact ? exact->stats : nlohmann::json(nullptr)},
      {"geometry_pixels", info.geometryPixels},
      {"tile", {o.tileWidth, o.tileHeight}},
      {"culling", toString(o.culling)},
      {"spot_culling", toString(o.spotCulling)},
      {"depth_split", o.depthSplit},
      {"slices", o.clusterSlices},
      {"math", toString(o.math)},
      {"lanes_requested", lanesName(o.lanes)},
      {"light_threshold", o.lightThreshold},
      {"raster", info.source},
      {"raster_renderer", info.sourceDetail},
      {"raster_ms", info.rasterMs},
      {"raster_setup_ms", info.rasterSetupMs},
      {"msaa", info.msaa},
      // The forward passes' colour (RGBA32F) and depth (float) targets, per sample; the id
      // targets are instrumentation and left out.
      {"forward_target_bytes",
       {{"colour", uint64_t(width) * uint64_t(height) * uint64_t(info.msaa) * 16u},
        {"depth", uint64_t(width) * uint64_t(height) * uint64_t(info.msaa) * 4u}}},
      {"compile_ms", device.compileMs()},
      {"techniques", results},
  };
  if (references)
    stats["reference"] = {{"contributing", references->reference.contributing},
                          {"peak", references->reference.peak}};
  if (exact) {
    writeExr(o.outDir + "/visibility_exact.exr", exact->width, exact->height, exact->channels,
             exact->image);
    // Per pixel: the map-shaded reference's largest channel difference from the exact-shaded one,
    // and its wrong pairs.
    std::vector<float> planes;
    for (size_t i = 0; i < exact->shadowError.size(); ++i)
      planes.insert(planes.end(), {exact->shadowError[i], exact->wrongPairs[i]});
    writeExr(o.outDir + "/shadow_error.exr", exact->width, exact->height, {"error", "wrong"},
             planes);
  }
  writeFile(o.outDir + "/stats.json", stats.dump(2) + "\n");
  if (o.dump) frame.dump(o.outDir);
  std::cout << "wrote " << o.outDir << "/\n";
}

}  // namespace ts
