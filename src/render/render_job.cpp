#include "render/render_job.h"

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
#include "reference/shading_cpu.h"
#include "render/frame_setup.h"
#include "render/gbuffer_dump.h"
#include "render/image_io.h"
#include "render/render_input.h"
#include "render/stats.h"
#include "scene/light_range.h"
#include "scene/scene_loader.h"
#include "techniques/technique.h"
#include "util/error.h"

namespace fs = std::filesystem;

namespace ts {
namespace {

// Relative tolerance (of the reference peak) used for the "pixels above tolerance" count.
constexpr double kReportTolerance = 1e-4;

std::vector<std::string> expandTechniques(const std::vector<std::string>& names) {
  std::vector<std::string> out;
  for (const auto& n : names) {
    if (n == "all") {
      for (const auto& t : techniqueNames()) out.push_back(t);
    } else {
      out.push_back(n);
    }
  }
  if (out.empty()) throw Error("no technique given");
  return out;
}

std::string kernelSummary(const FrameResult& r) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(3);
  for (size_t i = 0; i < r.kernels.size(); ++i)
    s << (i ? " " : "") << r.kernels[i].name << "=" << r.kernels[i].ms;
  return s.str();
}

}  // namespace

void runRender(const RenderOptions& options) {
  std::vector<std::string> techniques = expandTechniques(options.techniques);
  for (const auto& t : techniques) findTechnique(t);  // bad names fail before any work
  const RenderInput input = loadRenderInput(options);
  const PreparedFrame& prepared = input.frame;
  const SceneFeatures& features = prepared.features;
  RenderOptions o = options;  // an imported G-buffer decides the size and maybe the layout
  o.width = prepared.intrinsics.width;
  o.height = prepared.intrinsics.height;
  o.format = prepared.encoded.format;

  ClContext cl(o.device);
  DeviceFrame frame = prepared.upload(cl);
  TechniqueConfig config;
  config.format = o.format;
  config.features = features;
  config.tileWidth = o.tileWidth;
  config.tileHeight = o.tileHeight;
  config.clusterSlices = o.clusterSlices;
  config.culling = parseCulling(o.culling);
  config.spotCulling = parseSpotCulling(o.spotCulling);
  config.depthSplit = o.depthSplit;
  config.math = o.math;
  config.lanes = parseLanes(o.lanes);
  config.kernelOptions();  // rejects a bad --math before any work

  std::error_code ec;
  fs::create_directories(o.outDir, ec);
  if (ec) throw Error("cannot create output folder " + o.outDir + ": " + ec.message());

  // Two references: the windowed model from the very values the kernels read (isolates culling
  // and arithmetic), and the physical model (no range cut) from the fp32 G-buffer (adds the bias
  // of the range cut and of the storage precision).
  std::optional<ReferenceImage> reference, physical;
  if (o.check) {
    reference = shadeReference(prepared.encoded, prepared.intrinsics, prepared.lights,
                               prepared.ambient, config.shadingModel);
    const EncodedGBuffer fp32 = o.format == GBufferFormat::FP32
                                    ? prepared.encoded
                                    : encode(prepared.gbuffer, GBufferFormat::FP32);
    physical = shadeReference(fp32, prepared.intrinsics, prepared.lights, prepared.ambient,
                              TS_MODEL_PHYSICAL);
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
        << std::setw(10) << "total ms"
        << std::setw(16) << "lighting comp." << std::setw(15) << "evaluations" << std::setw(13)
        << "max err/peak" << std::setw(8) << "missed" << std::setw(12) << "G-buf MB"
        << "  per-kernel ms\n";
  for (const auto& name : techniques) {
    auto technique = createTechnique(name, cl, config);
    FrameRequest request;
    request.wantAssignment = o.check;
    FrameResult r = technique->render(frame, request);

    std::string dir = techniques.size() == 1 ? o.outDir : o.outDir + "/" + name;
    fs::create_directories(dir, ec);
    writeExrRgb(dir + "/image.exr", o.width, o.height, r.image);
    writePngToneMapped(dir + "/image.png", o.width, o.height, r.image, o.exposure);

    std::optional<ErrorStats> error, errorPhysical;
    std::optional<uint64_t> missed;
    if (reference) {
      error = compareToReference(r.image, *reference, kReportTolerance * reference->peak);
      errorPhysical = compareToReference(r.image, *physical, kReportTolerance * physical->peak);
      if (o.heatmap)
        writeHeatMapPng(dir + "/error.png", o.width, o.height, errorMap(r.image, *reference),
                        float(1e-7 * reference->peak), float(1e-2 * reference->peak));
      if (r.assignment)
        missed = countMissedContributions(*r.assignment, prepared.encoded, prepared.intrinsics,
                                          prepared.lights, config.shadingModel);
    }
    results.push_back(techniqueJson(name, r, error, missed));
    results.back()["lanes"] = technique->lanes();
    if (errorPhysical) results.back()["error_vs_physical"] = errorJson(*errorPhysical);

    std::ostringstream err;
    if (error) err << std::scientific << std::setprecision(2) << error->maxRelPeak;
    else err << "-";
    table << std::left << std::setw(18) << name << std::right << std::setw(6) << technique->lanes()
          << std::fixed << std::setprecision(3) << std::setw(10) << r.totalMs << std::setw(16) << r.counters.lightingComputations
          << std::setw(15) << r.counters.evaluations << std::setw(13) << err.str() << std::setw(8)
          << (missed ? std::to_string(*missed) : std::string("-")) << std::setw(12)
          << std::setprecision(1) << double(r.counters.gbufferBytesRead) / 1e6 << "  "
          << kernelSummary(r)
          << "\n";
    for (const auto& note : r.counters.notes) table << "    note: " << note << "\n";
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
      {"culling", o.culling},
      {"spot_culling", o.spotCulling},
      {"math", o.math},
      {"lanes_requested", o.lanes},
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
  std::ofstream(o.outDir + "/stats.json") << stats.dump(2) << "\n";
  if (o.dump) writeGBufferDump(cl, frame, prepared, input.sceneName, input.raster, o.outDir);
  std::cout << "wrote " << o.outDir << "/\n";
}

}  // namespace ts
