#include "gbuffer/gbuffer_import.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <limits>
#include <sstream>
#include <tuple>

#include "gbuffer/gbuffer_checks.h"
#include "gbuffer/image_io.h"
#include "scene/shading_range.h"
#include "util/error.h"
#include "util/short_text.h"

namespace ts {
namespace {

// Linear view depth from the depth channel's value; 0 for "no geometry" (a hardware depth at
// the far plane), possibly negative or infinite (the caller decides what is background).
double linearDepth(const GBufferDescriptor& d, double v) {
  switch (d.depthEncoding) {
    case DepthEncoding::Linear: return v;
    case DepthEncoding::ViewZ: return -v;
    case DepthEncoding::Hardware: break;
  }
  const double n = d.hardwareNear;
  if (d.hardwareReversed) {
    if (v <= 0.0) return 0.0;  // cleared to the far plane
    if (!d.hardwareFar) return n / v;
    const double f = *d.hardwareFar;
    return n * f / (n + v * (f - n));  // d' = 1 - d in the zero_to_one formula below
  }
  if (v >= 1.0) return 0.0;
  const double f = *d.hardwareFar;
  if (d.hardwareRange == DepthRange::MinusOneToOne) {
    const double ndc = 2.0 * v - 1.0;  // glDepthRange(0, 1)
    return 2.0 * n * f / (f + n - ndc * (f - n));
  }
  return n * f / (f - v * (f - n));
}

void checkInFrontOfNearPlane(const GBufferDescriptor& d, float depth, int x, int y) {
  if (!d.znear || !inFrontOfNearPlane(depth, *d.znear)) return;
  const bool fromHardware =
      d.depthEncoding == DepthEncoding::Hardware && float(d.hardwareNear) == *d.znear;
  throw Error(d.imagePath + ": depth " + fullPrecision(depth) + " at " + pixelText(x, y) +
              " is in front of the near plane " + fullPrecision(*d.znear) + " (" + d.path +
              (fromHardware ? " \"depth\": \"near\"" : " \"camera\": \"znear\"") +
              "); nothing nearer than the near plane is drawn, and the culling would drop lights "
              "there: fix it, or leave \"znear\" out to take the nearest surface's depth");
}

// What the image held when no pixel turned out to be geometry.
struct EmptyFrameClues {
  size_t depthGeometry = 0;  // pixels the depth alone makes geometry
  double maxMask = 0.0;
  // A linear / view_z depth of the other sign: the first one
  std::optional<std::tuple<int, int, float>> oppositeSign;
};

// No geometry: the frame would be ambient-black with nothing said. A depth of the other sign is
// a sign mistake (view_z holds negative values in front of the camera); else a warning.
void reportEmptyFrame(const GBufferDescriptor& d, const EmptyFrameClues& clues) {
  if (clues.oppositeSign && clues.depthGeometry == 0) {
    const auto [x, y, v] = *clues.oppositeSign;
    const bool viewZ = d.depthEncoding == DepthEncoding::ViewZ;
    throw Error(d.imagePath + ": no pixel is in front of the camera: depth channel '" +
                d.depthChannel + "' (\"encoding\": \"" + (viewZ ? "view_z" : "linear") + "\", " +
                (viewZ ? "negative" : "positive") + " in front) holds " + fullPrecision(v) +
                " at " + pixelText(x, y) + "; is it \"" + (viewZ ? "linear" : "view_z") + "\"?");
  }
  std::cerr << "tileshade: warning: " << d.imagePath << ": no pixel holds geometry";
  if (!d.maskChannel.empty() && clues.depthGeometry > 0)
    std::cerr << " (mask channel '" << d.maskChannel << "' is at most "
              << fullPrecision(clues.maxMask) << ", geometry is > 0.5, while depth channel '"
              << d.depthChannel << "' has " << clues.depthGeometry << " pixels in front)";
  std::cerr << "; the frame is background only\n";
}

}  // namespace

ImportedGBuffer readGBufferFiles(const std::string& dirOrFile) {
  ImportedGBuffer out;
  const GBufferDescriptor& d = out.descriptor = readGBufferDescriptor(dirOrFile);
  const FloatImage image = readImage(d.imagePath);
  const int W = image.width, H = image.height;
  if ((d.width && *d.width != W) || (d.height && *d.height != H))
    throw Error(d.imagePath + " is " + std::to_string(W) + "x" + std::to_string(H) + " but " +
                d.path + " says " + std::to_string(d.width.value_or(W)) + "x" +
                std::to_string(d.height.value_or(H)));
  if (W < 1 || H < 1) throw Error(d.imagePath + " has no pixels");

  auto channel = [&](const std::string& name, const std::string& field) {
    const int c = image.channel(name);
    if (c >= 0) return c;
    std::string all;
    for (const auto& n : image.channels) all += (all.empty() ? "" : ", ") + n;
    throw Error(d.imagePath + ": no channel '" + shortText(name) + "' (" + d.path + " \"" + field +
                "\"); its channels: " + all);
  };
  const int depthChannel = channel(d.depthChannel, "depth");
  const int maskChannel = d.maskChannel.empty() ? -1 : channel(d.maskChannel, "mask");
  struct Source {
    const GBufferField* field;
    std::vector<int> channels;
  };
  std::vector<Source> sources;
  for (const auto& [field, names] : d.fields) {
    Source s{field, {}};
    for (const auto& n : names) s.channels.push_back(channel(n, field->key));
    sources.push_back(s);
  }
  // Optional fields the descriptor leaves out take their fallback on geometry pixels.
  std::vector<const GBufferField*> fallbacks;
  for (const GBufferField* f : gbufferFields(d.model))
    if (std::none_of(sources.begin(), sources.end(), [&](const Source& s) { return s.field == f; }))
      fallbacks.push_back(f);

  GBuffer g;
  g.resize(W, H);
  g.model = d.model;
  std::vector<glm::vec4>* planes[] = {&g.normal, &g.diffuse, &g.specular, &g.emissive};
  const size_t stride = image.channels.size();
  double minDepth = std::numeric_limits<double>::infinity(), maxDepth = 0.0;
  EmptyFrameClues clues;
  ShadingRangeTerms range;  // what fp32 shading must hold: the surfaces', then the lights' values
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const int row = d.bottomRowFirst ? H - 1 - y : y;
      const float* px = image.data.data() + (size_t(row) * size_t(W) + size_t(x)) * stride;
      const size_t i = size_t(y) * size_t(W) + size_t(x);
      const float raw = px[depthChannel];
      if (std::isnan(raw))
        throw Error(d.imagePath + ": depth channel '" + d.depthChannel + "' is NaN at " +
                    pixelText(x, y));
      if (d.depthEncoding == DepthEncoding::Hardware && !(raw >= 0.0f && raw <= 1.0f))
        throw Error(d.imagePath + ": depth channel '" + d.depthChannel + "' holds window depth " +
                    fullPrecision(raw) + " at " + pixelText(x, y) +
                    ", outside [0, 1] (a depth buffer holds nothing in front of its near plane "
                    "or behind its far plane)");
      const double depth = linearDepth(d, raw);
      bool geometry = depth > 0.0 && std::isfinite(depth);
      clues.depthGeometry += geometry;
      if (!geometry && std::isfinite(raw) && raw != 0.0f &&
          (d.depthEncoding == DepthEncoding::ViewZ || d.depthEncoding == DepthEncoding::Linear))
        if (!clues.oppositeSign) clues.oppositeSign.emplace(x, y, raw);
      if (maskChannel >= 0) {
        const float m = px[maskChannel];
        if (!std::isfinite(m))
          throw Error(d.imagePath + ": mask channel '" + d.maskChannel + "' is not finite at " +
                      pixelText(x, y));
        if (m > 0.5f && !geometry)
          throw Error(d.imagePath + ": mask channel '" + d.maskChannel + "' marks geometry at " +
                      pixelText(x, y) + " but depth channel '" + d.depthChannel +
                      "' gives no depth in front of the camera (" + fullPrecision(raw) + ")");
        clues.maxMask = std::max(clues.maxMask, double(m));
        geometry = m > 0.5f;
      }
      if (!geometry) continue;
      g.depth[i] = float(depth);
      if (!(g.depth[i] > 0.0f) || !std::isfinite(g.depth[i]))
        throw Error(d.imagePath + ": depth " + std::to_string(depth) + " at " + pixelText(x, y) +
                    " is out of float range");
      checkInFrontOfNearPlane(d, g.depth[i], x, y);
      minDepth = std::min(minDepth, double(g.depth[i]));
      maxDepth = std::max(maxDepth, double(g.depth[i]));
      for (const GBufferField* f : fallbacks)
        for (int c = 0; c < f->components; ++c)
          (*planes[int(f->plane)])[i][f->first + c] = f->fallback;
      for (const Source& s : sources)
        for (size_t c = 0; c < s.channels.size(); ++c) {
          const std::string& name = image.channels[size_t(s.channels[c])];
          float v = px[s.channels[c]];
          const std::string what = "channel '" + name + "' (\"" + s.field->key + "\")";
          checkFiniteValue(d.imagePath, what, v, x, y);
          const bool normal = s.field->plane == GBufferPlane::Normal;
          if (normal && d.normalUnorm && !(v >= 0.0f && v <= 1.0f))
            throw Error(d.imagePath + ": channel '" + name +
                        "' (\"normal\", \"normal_encoding\": "
                        "\"unorm\") is " +
                        fullPrecision(v) + " at " + pixelText(x, y) + ", outside [0, 1]");
          if (!normal) checkNotNegative(d.imagePath, what, v, x, y);
          if (normal && d.normalUnorm) v = 2.0f * v - 1.0f;
          (*planes[int(s.field->plane)])[i][s.field->first + int(c)] = v;
        }
      for (int p = 0; p < 4; ++p)
        (*planes[p])[i] = fixedComponents(GBufferPlane(p), d.model, (*planes[p])[i]);
      checkNormalLength(d.imagePath, glm::vec3(g.normal[i]), x, y);
      range.addSurface(glm::vec3(g.diffuse[i]),
                       d.model == ShadingModel::BlinnPhong ? glm::vec3(g.specular[i])
                                                           : glm::vec3(0.0f),  // ks.R: roughness
                       glm::vec3(g.emissive[i]));
    }
  if (g.geometryPixels() == 0) reportEmptyFrame(d, clues);

  CameraIntrinsics& in = out.intrinsics;
  in.width = W;
  in.height = H;
  in.tanHalfFovY = d.tanHalfFovY;
  in.tanHalfFovX = d.tanHalfFovX ? *d.tanHalfFovX : d.tanHalfFovY * float(W) / float(H);
  // Without a near plane, the nearest surface serves: light-sphere clipping at it loses nothing
  // visible (docs/output-formats.md).
  in.znear = d.znear ? *d.znear : float(std::isfinite(minDepth) ? minDepth : 0.1);
  in.zfar = d.zfar ? *d.zfar : std::max(float(maxDepth), 2.0f * in.znear);
  out.gbuffer = std::move(g);
  LightsFile& lights = out.lights = readLightsFile(d.lightsPath);
  for (const glm::vec4& c : lights.lights.color) range.addLight(glm::vec3(c));
  for (const glm::vec4& c : lights.lights.directionalColor) range.addLight(glm::vec3(c));
  range.ambient = std::max({lights.ambient.x, lights.ambient.y, lights.ambient.z});
  checkShadingRange(range, d.path + " with " + d.lightsPath);
  return out;
}

}  // namespace ts
