#include "raster/shadow_maps.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <thread>

#include "raster/draw_batches.h"
#include "raster/scene_validation.h"
#include "shading/shading_cpu.h"
#include "util/error.h"
#include "util/option_values.h"
#include "util/short_text.h"

namespace ts {
namespace {

constexpr int kSmallFace = 64;  // one tile of the rasterizer

// Shortest text that reads back as the same float (a bias's canonical form).
std::string shortestFloat(float v) {
  char buf[32];
  for (int p = 1; p <= 9; ++p) {
    std::snprintf(buf, sizeof buf, "%.*g", p, double(v));
    if (std::strtof(buf, nullptr) == v) break;
  }
  return buf;
}

glm::vec4 row(const glm::dmat4& m, int r) {
  return glm::vec4(glm::dvec4(m[0][r], m[1][r], m[2][r], m[3][r]));
}

}  // namespace

int parseShadowFilter(const std::string& name) {
  if (name == "none") return 1;
  if (name == "pcf2") return 2;
  if (name == "pcf3") return 3;
  if (name == "pcf5") return 5;
  throw Error("--shadow-filter: unknown filter '" + shortText(name) +
              "' (known: none, pcf2, pcf3, pcf5)");
}

std::string shadowFilterName(int taps) { return taps == 1 ? "none" : "pcf" + std::to_string(taps); }

void parseShadowBias(const std::string& text, ShadowSampling& sampling) {
  std::vector<std::string> parts = splitList(text);
  const bool receiver = !parts.empty() && parts[0] == "receiver";
  if (receiver) parts.erase(parts.begin());
  const size_t count = receiver ? 1 : 2;
  char* end = nullptr;
  float v[2] = {0.0f, 0.0f};
  bool ok = parts.size() == count;
  for (size_t i = 0; ok && i < count; ++i) {
    v[i] = std::strtof(parts[i].c_str(), &end);
    ok = !parts[i].empty() && *end == '\0' && std::isfinite(v[i]) && v[i] >= 0.0f;
  }
  if (!ok)
    throw Error(
        "--shadow-bias: expected CONSTANT,SLOPE or receiver,CONSTANT (finite numbers >= 0, in "
        "texel footprints), got '" +
        shortText(text) + "'");
  sampling.biasConstant = v[0];
  sampling.biasSlope = v[1];
  sampling.receiverPlane = receiver;
}

std::string shadowBiasText(const ShadowSampling& sampling) {
  if (sampling.receiverPlane) return "receiver," + shortestFloat(sampling.biasConstant);
  return shortestFloat(sampling.biasConstant) + "," + shortestFloat(sampling.biasSlope);
}

void attachShadowMaps(const std::shared_ptr<const ShadowAtlas>& atlas,
                      const std::vector<SceneLight>& sceneLights, const glm::dmat4& viewFromWorld,
                      const ShadowSampling& sampling, ViewLights& lights) {
  const ShadowAtlasLayout& layout = atlas->layout;
  if (layout.faces.empty()) return;
  const glm::dmat4 worldFromView = glm::inverse(viewFromWorld);
  // The scene's light index -> its slot among the point/spot or the directional lights.
  std::vector<int> slot(sceneLights.size(), -1);
  int punctual = 0, directional = 0;
  for (size_t i = 0; i < sceneLights.size(); ++i)
    slot[i] = sceneLights[i].type == SceneLightType::Directional ? directional++ : punctual++;
  lights.shadow.resize(lights.size(), -1);
  lights.directionalShadow.resize(lights.directionalCount(), -1);
  lights.shadowFaces.clear();
  for (size_t f = 0; f < layout.faces.size(); ++f) {
    const ShadowFace& face = layout.faces[f];
    const SceneLight& light = sceneLights.at(face.light);
    int faces = light.type == SceneLightType::Point ? 6 : 1;
    if (face.face == 0) {
      std::vector<int>& first =
          light.type == SceneLightType::Directional ? lights.directionalShadow : lights.shadow;
      first.at(size_t(slot[face.light])) = int(f);
    }
    const glm::dmat4 clip = face.mapFromWorld * worldFromView;
    const glm::dmat4 faceView = face.view.viewFromWorld * worldFromView;
    const double texel = 2.0 * face.view.halfX / double(face.size);
    lights.shadowFaces.push_back(row(clip, 0));
    lights.shadowFaces.push_back(row(clip, 1));
    lights.shadowFaces.push_back(row(clip, 3));
    lights.shadowFaces.push_back(-row(faceView, 2));
    lights.shadowFaces.emplace_back(float(face.x), float(face.y), float(face.size),
                                    float(layout.width));
    // A texel's footprint: a constant across an orthographic map, in proportion to the depth
    // across a perspective one.
    lights.shadowFaces.emplace_back(face.view.orthographic ? float(texel) : 0.0f,
                                    face.view.orthographic ? 0.0f : float(texel),
                                    sampling.biasConstant, sampling.biasSlope);
    lights.shadowFaces.emplace_back(float(sampling.taps), float(faces),
                                    sampling.receiverPlane ? 1.0f : 0.0f, 0.0f);
  }
  if (lights.shadowFaces.size() != layout.faces.size() * TS_SHADOW_FACE_RECORDS)
    throw Error("shadow face table out of step with kernels/shadows.h");
  lights.shadowAtlas = std::shared_ptr<const std::vector<float>>(atlas, &atlas->depth);
  lights.shadowAtlasWidth = layout.width;
}

uint64_t ShadowAtlas::trianglesDrawn() const {
  uint64_t n = 0;
  for (uint64_t t : faceTriangles) n += t;
  return n;
}

bool touchesFace(const Bounds& world, const ShadowFace& face) {
  const ViewBox b = viewBox(world, face.view.viewFromWorld);
  const DepthView& v = face.view;
  // Depth is -Z: the box spans [-max.z, -min.z].
  if (double(-b.max.z) > v.zfar || double(-b.min.z) < v.znear) return false;
  if (v.orthographic)
    return !(b.min.x > v.halfX || b.max.x < -v.halfX || b.min.y > v.halfY || b.max.y < -v.halfY);
  // Inside the side plane x <= halfX * depth means x + halfX * z <= 0; the box lies wholly
  // outside when even its least value, at (min.x, min.z), is > 0. Likewise for -x, y and -y.
  const double z = double(b.min.z);
  return !(double(b.min.x) + v.halfX * z > 0.0 || -double(b.max.x) + v.halfX * z > 0.0 ||
           double(b.min.y) + v.halfY * z > 0.0 || -double(b.max.y) + v.halfY * z > 0.0);
}

ShadowAtlas drawShadowAtlas(const Scene& scene, ShadowAtlasLayout layout, int threads) {
  const auto t0 = std::chrono::steady_clock::now();
  if (layout.faces.empty()) return drawShadowAtlas(scene, {}, std::move(layout), threads);
  validateForRaster(scene);
  ShadowAtlas atlas = drawShadowAtlas(scene, drawBatches(scene), std::move(layout), threads);
  atlas.drawMs =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return atlas;
}

ShadowAtlas drawShadowAtlas(const Scene& scene, const std::vector<DrawBatch>& batches,
                            ShadowAtlasLayout layout, int threads) {
  const auto t0 = std::chrono::steady_clock::now();
  ShadowAtlas atlas;
  atlas.layout = std::move(layout);
  const ShadowAtlasLayout& l = atlas.layout;
  atlas.depth.assign(size_t(l.width) * size_t(l.height), 0.0f);
  atlas.faceTriangles.assign(l.faces.size(), 0);
  if (!l.faces.empty()) {
    const int workers =
        threads > 0 ? threads : int(std::max(1u, std::thread::hardware_concurrency()));
    auto draw = [&](size_t k, std::vector<uint32_t>& triangles, int faceThreads) {
      const ShadowFace& f = l.faces[k];
      triangles.clear();
      for (const DrawBatch& b : batches)
        if (touchesFace(b.bounds, f))
          for (uint32_t t = 0; t < b.triangles; ++t) triangles.push_back(b.firstTriangle + t);
      atlas.faceTriangles[k] = triangles.size();
      float* origin = atlas.depth.data() + size_t(f.y) * size_t(l.width) + size_t(f.x);
      rasterizeDepth(scene, f.view, triangles, f.size, f.size, origin, size_t(l.width),
                     float(f.view.zfar), faceThreads);
    };
    // A big face keeps every thread busy by itself (its tiles); small ones (one tile: serial
    // inside the rasterizer) are drawn side by side instead. Faces own disjoint rectangles, and
    // a face's depths do not depend on its thread count: the same atlas either way.
    std::vector<size_t> small;
    std::vector<uint32_t> triangles;
    for (size_t k = 0; k < l.faces.size(); ++k) {
      if (l.faces[k].size <= kSmallFace) small.push_back(k);
      else draw(k, triangles, threads);
    }
    std::atomic<size_t> next{0};
    auto worker = [&] {
      std::vector<uint32_t> own;
      for (size_t i; (i = next.fetch_add(1, std::memory_order_relaxed)) < small.size();)
        draw(small[i], own, 1);
    };
    std::vector<std::thread> pool;
    for (int w = 1; w < std::min<int>(workers, int(small.size())); ++w) pool.emplace_back(worker);
    worker();
    for (std::thread& t : pool) t.join();
  }
  atlas.drawMs =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return atlas;
}

}  // namespace ts
