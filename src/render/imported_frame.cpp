#include "render/imported_frame.h"

#include <cmath>
#include <utility>

#include "gbuffer/gbuffer_import.h"

namespace ts {

ImportedFrame importGBuffer(const std::string& dirOrFile, std::optional<GBufferFormat> format) {
  ImportedGBuffer in = readGBufferFiles(dirOrFile);
  ImportedFrame out;
  out.descriptor = std::move(in.descriptor);
  PreparedFrame& f = out.frame;
  f.intrinsics = in.intrinsics;
  f.camera.viewFromWorld = glm::mat4(1.0f);
  f.camera.yfov = 2.0f * std::atan(f.intrinsics.tanHalfFovY);
  f.camera.znear = f.intrinsics.znear;
  f.camera.zfar = f.intrinsics.zfar;
  f.gbuffer = std::move(in.gbuffer);
  f.encoded =
      encode(f.gbuffer, format ? *format : out.descriptor.layout.value_or(GBufferFormat::FP32));
  f.lights = std::move(in.lights.lights);
  f.ambient = in.lights.ambient;
  f.features = SceneFeatures::general(out.descriptor.model);
  f.features.point = f.features.spot = false;
  for (const auto& s : f.lights.spot) (s.w < -0.5f ? f.features.point : f.features.spot) = true;
  f.features.directional = f.lights.directionalCount() > 0;
  f.features.normalMaps = false;  // the files' normals are taken as they are
  return out;
}

}  // namespace ts
