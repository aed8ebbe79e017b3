#include "render/imported_frame.h"

#include <cmath>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "gbuffer/gbuffer_import.h"
#include "gbuffer/image_io.h"
#include "raster/shadow_maps.h"
#include "shading/shading_cpu.h"  // TS_SHADOW_FACE_RECORDS
#include "util/error.h"
#include "util/file_read.h"

namespace ts {
namespace {

// The depths of shadow_atlas.exr: one channel, the file's size, finite and >= 0 (0 in texels of
// no face, else linear depths), so no comparison of the kernels meets a NaN.
std::vector<float> readShadowAtlasImage(const ShadowAtlasFile& file) {
  FloatImage image = readImage(file.imagePath);
  if (image.width != file.width || image.height != file.height || image.channels.size() != 1)
    throw Error(file.imagePath + ": must be one channel of " + std::to_string(file.width) + "x" +
                std::to_string(file.height) + " (" + file.path + "), is " +
                std::to_string(image.channels.size()) + " of " + std::to_string(image.width) + "x" +
                std::to_string(image.height));
  for (size_t i = 0; i < image.data.size(); ++i)
    if (!(image.data[i] >= 0.0f && std::isfinite(image.data[i])))
      throw Error(file.imagePath + ": texel (" + std::to_string(i % size_t(file.width)) + ", " +
                  std::to_string(i / size_t(file.width)) + ") holds " +
                  std::to_string(image.data[i]) + ": depths must be finite and >= 0");
  return std::move(image.data);
}

// The shadow maps a G-buffer's files carry, attached to the lights of lights.json that name
// their first face ("shadow_face"): each light owns its 6 (point) or 1 (spot, directional)
// consecutive faces, every face one light; the kernels' face table (kernels/shadows.h) is built
// from the file's records, as attachShadowMaps builds it from a scene's atlas.
void attachImportedShadows(const GBufferDescriptor& d, ViewLights& lights) {
  struct Claim {
    int first, count;
  };
  std::vector<Claim> claims;
  for (size_t i = 0; i < lights.size(); ++i)
    if (lights.shadowOf(i) >= 0) claims.push_back({lights.shadowOf(i), lights.isSpot(i) ? 1 : 6});
  for (size_t i = 0; i < lights.directionalCount(); ++i)
    if (lights.directionalShadowOf(i) >= 0) claims.push_back({lights.directionalShadowOf(i), 1});
  if (claims.empty()) {
    if (!d.shadowAtlasPath.empty())
      throw Error(d.path + ": \"shadow_atlas\" names " + d.shadowAtlasPath + " but no light of " +
                  d.lightsPath + " has a \"shadow_face\"");
    return;
  }
  if (d.shadowAtlasPath.empty())
    throw Error(d.lightsPath + ": a light has a \"shadow_face\" but " + d.path +
                " names no \"shadow_atlas\" (render --dump writes shadow_atlas.json)");
  const ShadowAtlasFile file = parseShadowAtlasFile(
      readTextFile(d.shadowAtlasPath, "shadow atlas descriptor"), d.shadowAtlasPath);
  ShadowSampling sampling;
  try {
    sampling.taps = parseShadowFilter(file.filter);
  } catch (const Error& e) {
    throw Error(file.path + ": \"filter\": " + e.what());
  }
  sampling.biasConstant = file.biasConstant;
  sampling.biasSlope = file.biasSlope;
  sampling.receiverPlane = file.receiverPlane;

  const int faces = int(file.faces.size());
  std::vector<int> count(size_t(faces), 0);  // per face: its light's face count, 0 = no light
  for (const Claim& c : claims) {
    if (c.first + c.count > faces)
      throw Error(d.lightsPath + ": \"shadow_face\" " + std::to_string(c.first) + " (a light of " +
                  std::to_string(c.count) + " face(s)) is beyond the " + std::to_string(faces) +
                  " face(s) of " + file.path);
    for (int k = c.first; k < c.first + c.count; ++k) {
      if (count[size_t(k)] != 0)
        throw Error(d.lightsPath + ": face " + std::to_string(k) + " of " + file.path +
                    " belongs to two lights");
      count[size_t(k)] = c.count;
    }
  }
  for (int k = 0; k < faces; ++k)
    if (count[size_t(k)] == 0)
      throw Error(file.path + ": face " + std::to_string(k) + " belongs to no light of " +
                  d.lightsPath);

  lights.shadowFaces.clear();
  for (int k = 0; k < faces; ++k) {
    const ShadowAtlasFaceRecord& r = file.faces[size_t(k)];
    lights.shadowFaces.insert(lights.shadowFaces.end(),
                              {r.clipX, r.clipY, r.clipW, r.depth,
                               glm::vec4(float(r.x), float(r.y), float(r.size), float(file.width)),
                               glm::vec4(r.footprint, sampling.biasConstant, sampling.biasSlope),
                               glm::vec4(float(sampling.taps), float(count[size_t(k)]),
                                         sampling.receiverPlane ? 1.0f : 0.0f, 0.0f)});
  }
  if (lights.shadowFaces.size() != size_t(faces) * TS_SHADOW_FACE_RECORDS)
    throw Error("shadow face table out of step with kernels/shadows.h");
  lights.shadowAtlas = std::make_shared<const std::vector<float>>(readShadowAtlasImage(file));
  lights.shadowAtlasWidth = file.width;
}

}  // namespace

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
  attachImportedShadows(out.descriptor, f.lights);
  f.ambient = in.lights.ambient;
  f.features = SceneFeatures::general(out.descriptor.model);
  f.features.point = f.features.spot = false;
  for (const auto& s : f.lights.spot) (s.w < -0.5f ? f.features.point : f.features.spot) = true;
  f.features.directional = f.lights.directionalCount() > 0;
  f.features.normalMaps = false;  // the files' normals are taken as they are
  f.features.shadows = f.lights.hasShadows();
  return out;
}

}  // namespace ts
