#include "raster/shadow_maps.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <thread>

#include "raster/draw_batches.h"
#include "raster/scene_validation.h"

namespace ts {
namespace {

constexpr int kSmallFace = 64;  // one tile of the rasterizer

}  // namespace

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
  ShadowAtlas atlas;
  atlas.layout = std::move(layout);
  const ShadowAtlasLayout& l = atlas.layout;
  atlas.depth.assign(size_t(l.width) * size_t(l.height), 0.0f);
  atlas.faceTriangles.assign(l.faces.size(), 0);
  if (!l.faces.empty()) {
    validateForRaster(scene);
    const std::vector<DrawBatch> batches = drawBatches(scene);
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
