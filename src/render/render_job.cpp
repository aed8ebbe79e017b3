#include "render/render_job.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <optional>
#include <sstream>

#include <nlohmann/json.hpp>

#include "cl/cl_context.h"
#include "cl/work_group.h"
#include "reference/error_metrics.h"
#include "reference/reference.h"
#include "render/frame_setup.h"
#include "render/gbuffer_dump.h"
#include "gbuffer/image_io.h"
#include "render/render_input.h"
#include "render/stats.h"
#include "scene/light_range.h"
#include "scene/scene_loader.h"
#include "shading/shading_cpu.h"
#include "techniques/technique.h"
#include "util/error.h"
#include "util/file_write.h"
#include "util/option_values.h"
#include "util/progress.h"

namespace fs = std::filesystem;

namespace ts {
namespace {

// Relative tolerance (of the reference peak) used for the "pixels above tolerance" count.
constexpr double kReportTolerance = 1e-4;

// "all": every technique that can run on the frame; without a scene to draw (withScene false:
// software raster, imported G-buffer) the G-buffer techniques only.
std::vector<std::string> expandTechniques(const std::vector<std::string>& names,
                                          bool withScene = true) {
  std::vector<std::string> out;
  for (const auto& n : names) {
    if (n == "all") {
      for (const auto& t : withScene ? techniqueNames() : gbufferTechniqueNames()) out.push_back(t);
    } else {
      out.push_back(n);
    }
  }
  if (out.empty()) throw Error("no technique given");
  return out;
}

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

std::string frameText(const RenderOptions& o) {
  return std::to_string(o.width) + "x" + std::to_string(o.height);
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
  if (o.shadingModel != "auto") parseShadingModel(o.shadingModel);
  for (const auto& t : expandTechniques(o.techniques)) findTechnique(t);
}

namespace {

std::string kernelSummary(const FrameResult& r) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(3);
  for (size_t i = 0; i < r.kernels.size(); ++i)
    s << (i ? " " : "") << r.kernels[i].name << "=" << r.kernels[i].ms;
  return s.str();
}

}  // namespace

void runRender(const RenderOptions& options) {
  // Every option is checked before any work, so a bad one never follows written images.
  validateRenderOptions(options);
  ClContext cl(options.device);  // a bad --device fails before the scene is loaded
  const RenderInput input = outOfMemoryAs(
      "loading and rasterizing " + (options.gbufferIn.empty() ? options.scene : options.gbufferIn),
      [&] { return loadRenderInput(options); });
  std::vector<std::string> techniques =
      expandTechniques(options.techniques, input.forward != nullptr);
  if (!input.forward && std::count(options.techniques.begin(), options.techniques.end(), "all"))
    for (const auto& t : techniqueNames())
      if (findTechnique(t).drawsScene)
        std::cout << "tileshade: --technique all leaves out " << t
                  << " (it draws the scene: --raster gl)\n";
  for (const auto& t : techniques)  // before any file is written
    if (findTechnique(t).drawsScene && !input.forward)
      throw Error(t +
                  " draws the scene: it needs a frame rasterized with --raster gl (not the "
                  "software rasterizer or an imported G-buffer)");
  const PreparedFrame& prepared = input.frame;
  const SceneFeatures& features = prepared.features;
  RenderOptions o = options;  // an imported G-buffer decides the size and maybe the layout
  o.width = prepared.intrinsics.width;
  o.height = prepared.intrinsics.height;
  o.format = prepared.encoded.format;

  DeviceFrame frame = prepared.upload(cl);
  frame.forward = input.forward.get();
  const TechniqueConfig config = o.techniqueConfig(features);
  // Every technique is created (its configuration checked, its kernels built) before the first
  // one renders: one that refuses the configuration (e.g. slices beyond the device's local
  // memory) fails before any file is written.
  std::vector<std::unique_ptr<Technique>> created;
  for (const auto& name : techniques) created.push_back(createTechnique(name, cl, config));

  std::error_code ec;
  fs::create_directories(o.outDir, ec);
  if (ec) throw Error("cannot create output folder " + o.outDir + ": " + ec.message());

  // Three references: the windowed model from the stored values, positions rebuilt from depth in
  // double (culling, arithmetic and the kernels' float positions); the same with the kernels'
  // float positions (culling and shading arithmetic only); and the physical model (no range cut)
  // from the fp32 G-buffer (adds the bias of the range cut and of the storage precision).
  std::optional<ReferenceImage> reference, shadingOnly, physical;
  ReferenceProgress progress(prepared.encoded.pixelCount(), prepared.lights.size(),
                             3 + int(techniques.size()), o.height);
  if (o.check) {
    outOfMemoryAs("computing the double-precision reference of a " + frameText(o) + " frame", [&] {
      reference =
          shadeReference(prepared.encoded, prepared.intrinsics, prepared.lights, prepared.ambient,
                         int(config.rangeModel), 0, progress.pass("windowed model"));
      shadingOnly = shadeReference(prepared.encoded, prepared.intrinsics, prepared.lights,
                                   prepared.ambient, int(config.rangeModel), 0,
                                   progress.pass("windowed model, kernel positions"),
                                   ReferencePositions::KernelFloat);
      const EncodedGBuffer fp32 = o.format == GBufferFormat::FP32
                                      ? prepared.encoded
                                      : encode(prepared.gbuffer, GBufferFormat::FP32);
      physical = shadeReference(fp32, prepared.intrinsics, prepared.lights, prepared.ambient,
                                int(RangeModel::Physical), 0, progress.pass("physical model"));
    });
  }

  std::cout << "tileshade: " << input.sceneName << " (" << input.triangles << " triangles, "
            << input.lightSummary << "), frame " << prepared.frame << ", " << o.width << "x"
            << o.height << ", G-buffer " << toString(o.format) << " ("
            << prepared.encoded.bytesPerPixel() << " B/pixel), tile " << o.tileWidth << "x"
            << o.tileHeight << "\n"
            << "features: " << features.describe() << "\n"
            << "raster: " << input.rasterDetail << ", " << std::fixed << std::setprecision(1)
            << prepared.rasterMs << " ms (setup " << input.rasterSetupMs << " ms)\n"
            << std::defaultfloat << "device: " << cl.deviceName() << "\n";
  if (reference)
    std::cout << "reference: " << reference->contributing
              << " contributing light evaluations (the ideal), peak " << reference->peak << "\n";

  nlohmann::json results = nlohmann::json::array();
  std::ostringstream table;
  table << std::left << std::setw(18) << "technique" << std::right << std::setw(6) << "lanes"
        << std::setw(10) << "total ms" << std::setw(16) << "lighting comp." << std::setw(15)
        << "evaluations" << std::setw(13) << "max err/peak" << std::setw(13) << "shading err"
        << std::setw(8) << "missed" << std::setw(12) << "G-buf MB"
        << "  per-kernel ms\n";
  for (size_t t = 0; t < techniques.size(); ++t) {
    const std::string& name = techniques[t];
    Technique* technique = created[t].get();
    FrameRequest request;
    request.wantAssignment = o.check;
    FrameResult r = technique->render(frame, request);

    std::string dir = techniques.size() == 1 ? o.outDir : o.outDir + "/" + name;
    fs::create_directories(dir, ec);
    if (ec) throw Error("cannot create output folder " + dir + ": " + ec.message());
    writeExrRgb(dir + "/image.exr", o.width, o.height, r.image);
    writePngToneMapped(dir + "/image.png", o.width, o.height, r.image, o.exposure);

    std::optional<ErrorStats> error, errorShading, errorPhysical;
    std::optional<uint64_t> missed;
    if (reference) {
      error = compareToReference(r.image, *reference, kReportTolerance * reference->peak);
      errorShading =
          compareToReference(r.image, *shadingOnly, kReportTolerance * shadingOnly->peak);
      errorPhysical = compareToReference(r.image, *physical, kReportTolerance * physical->peak);
      if (o.heatmap)
        writeHeatMapPng(dir + "/error.png", o.width, o.height, errorMap(r.image, *reference),
                        float(1e-7 * reference->peak), float(1e-2 * reference->peak));
      if (r.assignment)
        missed = countMissedContributions(*r.assignment, prepared.encoded, prepared.intrinsics,
                                          prepared.lights, int(config.rangeModel),
                                          progress.pass("missed lights of " + name));
    }
    results.push_back(techniqueJson(name, r, error, missed));
    results.back()["lanes"] = technique->lanes();
    if (errorShading) results.back()["error_shading"] = errorJson(*errorShading);
    if (errorPhysical) results.back()["error_vs_physical"] = errorJson(*errorPhysical);

    auto relPeak = [](const std::optional<ErrorStats>& e) {
      std::ostringstream text;
      if (e) text << std::scientific << std::setprecision(2) << e->maxRelPeak;
      else text << "-";
      return text.str();
    };
    table << std::left << std::setw(18) << name << std::right << std::setw(6) << technique->lanes()
          << std::fixed << std::setprecision(3) << std::setw(10) << r.totalMs << std::setw(16)
          << r.counters.lightingComputations << std::setw(15) << r.counters.evaluations
          << std::setw(13) << relPeak(error) << std::setw(13) << relPeak(errorShading)
          << std::setw(8) << (missed ? std::to_string(*missed) : std::string("-")) << std::setw(12)
          << std::setprecision(1) << double(r.counters.gbufferBytesRead) / 1e6 << "  "
          << kernelSummary(r) << "\n";
    for (const auto& note : r.counters.notes) table << "    note: " << note << "\n";
    if (uint64_t bad = countNonFinitePixels(r.image))
      table << "    note: " << bad << " pixel(s) NaN or inf (nonfinite_pixels in stats.json)\n";
  }
  std::cout << table.str();

  nlohmann::json stats = {
      {"device", cl.deviceName()},
      {"device_type", cl.info().type},
      {"scene", input.sceneName},
      {"scene_spec", o.gbufferIn.empty() ? o.scene : "gbuffer-in:" + o.gbufferIn},
      {"light_set", o.lightSet},
      {"lights", prepared.lights.size() + prepared.lights.directionalCount()},
      {"directional_lights", prepared.lights.directionalCount()},
      {"triangles", input.triangles},
      {"frame", prepared.frame},
      {"width", o.width},
      {"height", o.height},
      {"gbuffer", toString(o.format)},
      {"gbuffer_bytes_per_pixel", prepared.encoded.bytesPerPixel()},
      {"shading_model", toString(features.model)},
      {"features", features.describe()},
      {"kernel_options", config.kernelOptions()},
      {"variant", o.variant},
      {"geometry_pixels", prepared.gbuffer.geometryPixels()},
      {"tile", {o.tileWidth, o.tileHeight}},
      {"culling", toString(o.culling)},
      {"spot_culling", toString(o.spotCulling)},
      {"depth_split", o.depthSplit},
      {"slices", o.clusterSlices},
      {"math", toString(o.math)},
      {"lanes_requested", lanesName(o.lanes)},
      {"light_threshold", o.lightThreshold},
      {"raster", input.raster},
      {"raster_renderer", input.rasterDetail},
      {"raster_ms", prepared.rasterMs},
      {"raster_setup_ms", input.rasterSetupMs},
      {"compile_ms", cl.compileMs()},
      {"techniques", results},
  };
  if (reference)
    stats["reference"] = {{"contributing", reference->contributing}, {"peak", reference->peak}};
  writeFile(o.outDir + "/stats.json", stats.dump(2) + "\n");
  if (o.dump) writeGBufferDump(cl, frame, prepared, input.sceneName, input.raster, o.outDir);
  std::cout << "wrote " << o.outDir << "/\n";
}

}  // namespace ts
