#include "python_results.h"

#include <cerrno>
#include <cstdlib>
#include <fstream>
#include <regex>

namespace tileshade_python {

py::dict deviceDict(const ts::DeviceDescription& d) {
  py::dict out;
  out["index"] = d.index;
  out["platform"] = d.platform;
  out["name"] = d.name;
  out["type"] = d.type;
  out["compute_units"] = d.computeUnits;
  out["global_mem_bytes"] = d.globalMemBytes;
  out["local_mem_bytes"] = d.localMemBytes;
  return out;
}

py::dict frameInfoDict(const ts::FrameInfo& i) {
  py::dict d;
  d["scene_name"] = i.sceneName;
  d["source"] = i.source;
  d["source_detail"] = i.sourceDetail;
  d["triangles"] = i.triangles;
  d["frame"] = i.frame;
  d["width"] = i.width;
  d["height"] = i.height;
  d["layout"] = i.layout;
  d["shading_model"] = i.shadingModel;
  d["features"] = i.features;
  d["bytes_per_pixel"] = i.bytesPerPixel;
  d["geometry_pixels"] = i.geometryPixels;
  d["lights"] = i.lights;
  d["directional_lights"] = i.directionalLights;
  d["light_summary"] = i.lightSummary;
  d["raster_ms"] = i.rasterMs;
  d["raster_setup_ms"] = i.rasterSetupMs;
  d["draws_scene"] = i.drawsScene;
  d["shadow_casting_lights"] = i.shadowCastingLights;
  if (i.shadowMaps) {
    const ts::ShadowMapsInfo& s = *i.shadowMaps;
    py::list lights;
    for (const ts::ShadowMapLight& l : s.lights) {
      py::dict o;
      o["light"] = l.light;
      o["type"] = l.type;
      o["faces"] = l.faces;
      o["requested_size"] = l.requestedSize;
      o["size"] = l.size;
      lights.append(o);
    }
    py::dict m;
    m["faces"] = s.faces;
    m["atlas_width"] = s.atlasWidth;
    m["atlas_height"] = s.atlasHeight;
    m["bytes"] = s.bytes;
    m["triangles_drawn"] = s.trianglesDrawn;
    m["draw_ms"] = s.drawMs;
    m["rasterizer"] = s.rasterizer;
    m["read_ms"] = s.readMs;
    m["lights"] = lights;
    py::list notes;
    for (const std::string& n : s.notes) notes.append(n);
    m["notes"] = notes;
    d["shadow_maps"] = m;
  } else {
    d["shadow_maps"] = py::none();
  }
  return d;
}

py::dict errorDict(const ts::ErrorReport& e) {
  py::dict d;
  d["max_abs"] = e.maxAbs;
  d["rmse"] = e.rmse;
  d["psnr"] = e.psnr;
  d["max_rel_peak"] = e.maxRelPeak;
  d["p50"] = e.p50;
  d["p99"] = e.p99;
  d["p999"] = e.p999;
  d["tolerance"] = e.tolerance;
  d["pixels_above_tolerance"] = e.pixelsAboveTolerance;
  d["nonfinite_pixels"] = e.nonfinitePixels;
  d["peak"] = e.peak;
  return d;
}

py::object checkDict(const std::optional<ts::CheckReport>& check) {
  if (!check) return py::none();
  py::dict d;
  d["error"] = errorDict(check->error);
  d["shading_error"] = errorDict(check->shadingError);
  d["physical_error"] = errorDict(check->physicalError);
  d["missed"] = check->missed;
  d["contributing"] = check->contributing;
  d["missed_counted"] = check->missedCounted;
  d["reference_peak"] = check->referencePeak;
  return std::move(d);
}

py::list kernelsList(const std::vector<ts::KernelTiming>& kernels) {
  py::list list;
  for (const auto& k : kernels) {
    py::dict d;
    d["name"] = k.name;
    d["ms"] = k.ms;
    d["launches"] = k.launches;
    list.append(d);
  }
  return list;
}

py::dict countersDict(const ts::Counters& c) {
  py::dict d;
  d["lighting_computations"] = c.lightingComputations;
  d["evaluations"] = c.evaluations;
  d["gbuffer_bytes_read"] = c.gbufferBytesRead;
  d["list_min"] = c.listMin;
  d["list_max"] = c.listMax;
  d["list_mean"] = c.listMean;
  py::list notes;
  for (const auto& n : c.notes) notes.append(n);
  d["notes"] = notes;
  return d;
}

py::dict resultStats(const ts::ShadeResult& r) {
  py::dict d;
  d["technique"] = r.technique;
  d["width"] = r.width;
  d["height"] = r.height;
  d["total_ms"] = r.totalMs;
  d["kernels"] = kernelsList(r.kernels);
  d["lanes"] = r.lanes;
  d["counters"] = countersDict(r.counters);
  d["nonfinite_pixels"] = r.nonfinitePixels;
  d["check"] = checkDict(r.check);
  d["kernel_options"] = r.kernelOptions;
  if (r.shadowUse) {
    py::dict s;
    s["passes"] = r.shadowUse->passes;
    s["draw_ms"] = r.shadowUse->drawMs;
    s["resident_bytes"] = r.shadowUse->residentBytes;
    s["written_bytes"] = r.shadowUse->writtenBytes;
    s["triangles_drawn"] = r.shadowUse->trianglesDrawn;
    d["shadow_use"] = s;
  } else {
    d["shadow_use"] = py::none();
  }
  return d;
}

py::object benchValue(const std::string& column, const std::string& text) {
  static const std::regex identifier("config_id|.*_id|.*hash.*");
  static const std::regex integer("[-+]?[0-9]+");
  static const std::regex decimal(
      "[-+]?([0-9]+\\.?[0-9]*|\\.[0-9]+)([eE][-+]?[0-9]+)?|[-+]?(nan|inf)");
  if (std::regex_match(column, identifier)) return py::str(text);
  if (std::regex_match(text, integer)) {
    // Python's ints have no range: the text itself, not a C++ conversion.
    return py::reinterpret_steal<py::object>(PyLong_FromString(text.c_str(), nullptr, 10));
  }
  if (std::regex_match(text, decimal)) return py::float_(std::strtod(text.c_str(), nullptr));
  return py::str(text);
}

namespace {

// The header of bench.csv: its column names in order (names hold no comma or quote).
std::vector<std::string> csvHeader(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::vector<std::string> columns;
  if (!in || !std::getline(in, line)) return columns;
  if (!line.empty() && line.back() == '\r') line.pop_back();
  size_t start = 0;
  for (size_t comma; (comma = line.find(',', start)) != std::string::npos; start = comma + 1) {
    columns.push_back(line.substr(start, comma - start));
  }
  columns.push_back(line.substr(start));
  return columns;
}

}  // namespace

py::list benchRows(const std::vector<std::map<std::string, std::string>>& rows,
                   const std::string& csvPath) {
  const std::vector<std::string> order =
      rows.empty() ? std::vector<std::string>{} : csvHeader(csvPath);
  py::list list;
  for (const auto& row : rows) {
    py::dict d;
    for (const auto& column : order) {
      const auto it = row.find(column);
      if (it != row.end()) d[py::str(column)] = benchValue(column, it->second);
    }
    // Whatever the header did not name (or all of it, without a header), in the row's order.
    for (const auto& [column, text] : row) {
      if (!d.contains(column)) d[py::str(column)] = benchValue(column, text);
    }
    list.append(d);
  }
  return list;
}

}  // namespace tileshade_python
