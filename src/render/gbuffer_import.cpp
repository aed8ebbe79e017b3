#include "render/gbuffer_import.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "render/image_io.h"
#include "util/error.h"
#include "util/short_text.h"

namespace ts {
namespace {

std::string pixelText(int x, int y) {
  return "pixel (" + std::to_string(x) + ", " + std::to_string(y) + ")";
}

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

}  // namespace

ImportedFrame importGBuffer(const std::string& dirOrFile, std::optional<GBufferFormat> format) {
  ImportedFrame out;
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
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const int row = d.bottomRowFirst ? H - 1 - y : y;
      const float* px = image.data.data() + (size_t(row) * size_t(W) + size_t(x)) * stride;
      const size_t i = size_t(y) * size_t(W) + size_t(x);
      const float raw = px[depthChannel];
      if (std::isnan(raw))
        throw Error(d.imagePath + ": depth channel '" + d.depthChannel + "' is NaN at " +
                    pixelText(x, y));
      const double depth = linearDepth(d, raw);
      bool geometry = depth > 0.0 && std::isfinite(depth);
      if (maskChannel >= 0) {
        const float m = px[maskChannel];
        if (!std::isfinite(m))
          throw Error(d.imagePath + ": mask channel '" + d.maskChannel + "' is not finite at " +
                      pixelText(x, y));
        if (m > 0.5f && !geometry)
          throw Error(d.imagePath + ": mask channel '" + d.maskChannel +
                      "' marks geometry at " + pixelText(x, y) + " but depth channel '" +
                      d.depthChannel + "' gives no depth in front of the camera (" +
                      std::to_string(raw) + ")");
        geometry = m > 0.5f;
      }
      if (!geometry) continue;
      g.depth[i] = float(depth);
      if (!(g.depth[i] > 0.0f) || !std::isfinite(g.depth[i]))
        throw Error(d.imagePath + ": depth " + std::to_string(depth) + " at " + pixelText(x, y) +
                    " is out of float range");
      minDepth = std::min(minDepth, double(g.depth[i]));
      maxDepth = std::max(maxDepth, double(g.depth[i]));
      for (const GBufferField* f : fallbacks)
        for (int c = 0; c < f->components; ++c)
          (*planes[int(f->plane)])[i][f->first + c] = f->fallback;
      for (const Source& s : sources)
        for (size_t c = 0; c < s.channels.size(); ++c) {
          float v = px[s.channels[c]];
          if (!std::isfinite(v))
            throw Error(d.imagePath + ": channel '" + image.channels[size_t(s.channels[c])] +
                        "' (\"" + s.field->key + "\") is " + (std::isnan(v) ? "NaN" : "infinite") +
                        " at " + pixelText(x, y));
          if (s.field->plane == GBufferPlane::Normal && d.normalUnorm) v = 2.0f * v - 1.0f;
          (*planes[int(s.field->plane)])[i][s.field->first + int(c)] = v;
        }
      for (int p = 0; p < 4; ++p)
        (*planes[p])[i] = fixedComponents(GBufferPlane(p), d.model, (*planes[p])[i]);
      if (glm::vec3(g.normal[i]) == glm::vec3(0.0f))
        throw Error(d.imagePath + ": the normal (\"normal\") is zero at " + pixelText(x, y));
    }

  PreparedFrame& f = out.frame;
  CameraIntrinsics& in = f.intrinsics;
  in.width = W;
  in.height = H;
  in.tanHalfFovY = d.tanHalfFovY;
  in.tanHalfFovX = d.tanHalfFovX ? *d.tanHalfFovX : d.tanHalfFovY * float(W) / float(H);
  // Without a near plane, the nearest surface serves: light-sphere clipping at it loses nothing
  // visible (docs/output-formats.md).
  in.znear = d.znear ? *d.znear : float(std::isfinite(minDepth) ? minDepth : 0.1);
  in.zfar = d.zfar ? *d.zfar : std::max(float(maxDepth), 2.0f * in.znear);
  f.camera.viewFromWorld = glm::mat4(1.0f);
  f.camera.yfov = 2.0f * std::atan(in.tanHalfFovY);
  f.camera.znear = in.znear;
  f.camera.zfar = in.zfar;
  f.gbuffer = std::move(g);
  f.encoded = encode(f.gbuffer, format ? *format : d.layout.value_or(GBufferFormat::FP32));
  LightsFile lights = readLightsFile(d.lightsPath);
  f.lights = std::move(lights.lights);
  f.ambient = lights.ambient;
  f.features = SceneFeatures::general(d.model);
  f.features.point = f.features.spot = false;
  for (const auto& s : f.lights.spot) (s.w < -0.5f ? f.features.point : f.features.spot) = true;
  f.features.directional = f.lights.directionalCount() > 0;
  return out;
}

}  // namespace ts
