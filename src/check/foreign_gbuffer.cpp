#include "check/foreign_gbuffer.h"

#include <filesystem>
#include <fstream>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "gbuffer/gbuffer_files.h"
#include "render/imported_frame.h"
#include "gbuffer/image_io.h"
#include "util/error.h"
#include "util/pi.h"

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace ts {
namespace {

// The folder goes when the import is done, also when it throws.
struct TemporaryFolder {
  fs::path path;
  TemporaryFolder()
      : path(fs::temp_directory_path() / ("tileshade_check_import_" + std::to_string(::getpid()))) {
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TemporaryFolder() {
    std::error_code ignored;  // a leftover temporary folder is not worth failing the check for
    fs::remove_all(path, ignored);
  }
};

}  // namespace

PreparedFrame throughForeignGBufferFiles(const PreparedFrame& frame, GBufferFormat format) {
  const GBuffer& g = frame.gbuffer;
  if (g.model != ShadingModel::BlinnPhong)
    throw Error("check: the import case writes Blinn-Phong planes only");
  const double n = frame.intrinsics.znear;
  std::vector<float> data;
  data.reserve(g.pixelCount() * 14);
  for (int row = 0; row < g.height; ++row)
    for (int x = 0; x < g.width; ++x) {
      const size_t i = size_t(g.height - 1 - row) * size_t(g.width) + size_t(x);  // bottom first
      // Reversed Z, infinite far: window depth n / depth, 0 = cleared (background).
      data.push_back(g.depth[i] > 0.0f ? float(n / double(g.depth[i])) : 0.0f);
      for (int c = 0; c < 3; ++c) data.push_back(0.5f * g.normal[i][c] + 0.5f);
      for (int c = 0; c < 3; ++c) data.push_back(g.diffuse[i][c]);
      for (int c = 0; c < 4; ++c) data.push_back(g.specular[i][c]);
      for (int c = 0; c < 3; ++c) data.push_back(g.emissive[i][c]);
    }
  TemporaryFolder dir;
  writeExr((dir.path / "frame.exr").string(), g.width, g.height,
           {"depth", "nx", "ny", "nz", "albedo.R", "albedo.G", "albedo.B", "spec.R", "spec.G",
            "spec.B", "gloss", "emit.R", "emit.G", "emit.B"},
           data);
  std::ofstream(dir.path / "lights.json") << lightsJson(frame.lights, frame.ambient).dump();
  const json descriptor = {
      {"tileshade_gbuffer", kGBufferFilesVersion},
      {"image", "frame.exr"},
      {"origin", "bottom"},
      {"camera", {{"yfov_degrees", double(frame.camera.yfov) * 180.0 / kPiDouble}}},
      {"depth",
       {{"channel", "depth"},
        {"encoding", "hardware"},
        {"near", n},
        {"far", nullptr},
        {"range", "zero_to_one"},
        {"reversed", true}}},
      {"normal", {"nx", "ny", "nz"}},
      {"normal_encoding", "unorm"},
      {"diffuse", {"albedo.R", "albedo.G", "albedo.B"}},
      {"specular", {"spec.R", "spec.G", "spec.B"}},
      {"shininess", "gloss"},
      {"emissive", {"emit.R", "emit.G", "emit.B"}}};
  std::ofstream(dir.path / "renderer.json") << descriptor.dump(2);
  return importGBuffer((dir.path / "renderer.json").string(), format).frame;
}

}  // namespace ts
