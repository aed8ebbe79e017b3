// A CPU-native yardstick for the tiled techniques (issue #19): the per-tile loop of `tiled-single`
// (kernels/tiled_single.cl) as a plain serial C++ program, like ISPC's examples/cpu/deferred
// dynamic_c.cpp, compiled by the system compiler at -O3 -march=native (bench/yardstick/
// CMakeLists.txt). Per 16x16 tile: the geometry's depth bounds, every light tested against the
// tile with kernels/culling.h's default test (the light's tile rectangle, then the depth range),
// then every pixel shaded over the tile's list with kernels/shading.h in float: the same source
// text as the kernels, so no second copy of the model. It reads a `render --dump` folder and
// prints the median time of N runs and its image's error, against the double reference or an
// image of tileshade's from the same dump.
//
//   tileshade-yardstick DUMP_DIR [--runs N] [--threads T] [--tile N] [--simd 0|8|16]
//                       [--compare IMAGE.exr] [--reference] [--max-error E]
//
// --threads 0 is every core (tiles handed out one at a time); 1 (default) is one thread.
// --simd 8|16 is the SIMD form, ISPC's examples/cpu/deferred ShadeTile in C++: the same tile loop
// with the rectangle test on 8 or 16 lights at once and each tile's pixels shaded in blocks of 8
// or 16 in vector lanes (shading.h's lane functions, as kernels/lanes.h runs them in OpenCL).
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <CLI/CLI.hpp>
#include <glm/glm.hpp>

#include "gbuffer/image_io.h"
#include "reference/reference.h"
#include "render/imported_frame.h"
#include "util/error.h"

// kernels/shading.h and kernels/culling.h in float, in a namespace of this program's own: its
// inline functions are compiled for -march=native here and must not be confused with the
// libraries' copies (src/shading/shading_cpu.h).
namespace yardstick {
inline float sqrt(float x) { return std::sqrt(x); }
inline float rsqrt(float x) { return 1.0f / std::sqrt(x); }
inline float max(float a, float b) { return a > b ? a : b; }
inline float min(float a, float b) { return a < b ? a : b; }
inline float clamp(float x, float lo, float hi) { return std::min(std::max(x, lo), hi); }
inline float floor(float x) { return std::floor(x); }
inline float dot(const glm::vec3& a, const glm::vec3& b) { return glm::dot(a, b); }
// The kernels' precise power for x in [0, 1] (kernels/gbuffer.h, ts_pow_unit): exp2(s log2 x),
// 0 below FLT_MIN, 1 for s = 0.
inline float pow(float x, float s) {
  if (s == 0.0f) return 1.0f;
  return x >= 1.17549435e-38f ? std::exp2(s * std::log2(x)) : 0.0f;
}
#define TS_REAL float
#define TS_REAL3 glm::vec3
#define TS_REAL4 glm::vec4
#define TS_MAKE3(x, y, z) glm::vec3((x), (y), (z))
#define TS_MAKE4(x, y, z, w) glm::vec4((x), (y), (z), (w))
#include "kernels/shading.h"
#include "kernels/culling.h"
}  // namespace yardstick

// The SIMD form: kernels/shading.h again, with its light terms on vectors of 8 or 16 floats
// (TS_LANE: bench/yardstick/vector_lanes.h), one namespace per width, as kernels/lanes.h compiles
// it for OpenCL with floatN. Of shading.h's spellings only TS_CAST changes: a C cast cannot turn
// a scalar into a vector in C++, so it broadcasts (a scalar cast stays a cast).
#include "vector_lanes.h"
#undef TS_LANE
#undef TS_ANY
#undef TS_CAST
#define TS_CAST(type, x) (::yardstick::cast<type>(x))
#define TS_ANY(c) (::yardstick::any(c))
#define TS_LANES 8
#define TS_LANE ::yardstick::Floats8
namespace yardstick::lanes8 {
#include "kernels/shading.h"
}  // namespace yardstick::lanes8
#undef TS_LANES
#undef TS_LANE
#define TS_LANES 16
#define TS_LANE ::yardstick::Floats16
namespace yardstick::lanes16 {
#include "kernels/shading.h"
}  // namespace yardstick::lanes16
#undef TS_LANES
#undef TS_LANE

namespace {

// One width of the SIMD form: its vector types, shading.h's lane functions of that width and the
// shape of the pixel block one vector shades (kernels/lanes.h's: 4x4 for 16 lanes, 4x2 for 8, so
// a vector's pixels lie close together and more lights reach none of them and exit early).
struct Lanes8 {
  using Floats = yardstick::Floats8;
  using Mask = yardstick::Mask8;
  using Point = yardstick::lanes8::ts_shading_point;
  using Weights = yardstick::lanes8::ts_light_weights_t;
  static constexpr int count = 8, blockW = 4, blockH = 2;
  template <typename... A>
  static Weights punctual(A... a) {
    return yardstick::lanes8::ts_punctual_weights(a...);
  }
  template <typename... A>
  static Weights directional(A... a) {
    return yardstick::lanes8::ts_directional_weights(a...);
  }
};
struct Lanes16 {
  using Floats = yardstick::Floats16;
  using Mask = yardstick::Mask16;
  using Point = yardstick::lanes16::ts_shading_point;
  using Weights = yardstick::lanes16::ts_light_weights_t;
  static constexpr int count = 16, blockW = 4, blockH = 4;
  template <typename... A>
  static Weights punctual(A... a) {
    return yardstick::lanes16::ts_punctual_weights(a...);
  }
  template <typename... A>
  static Weights directional(A... a) {
    return yardstick::lanes16::ts_directional_weights(a...);
  }
};

}  // namespace

namespace {

using Clock = std::chrono::steady_clock;

// The frame as the kernels read it (fp32 layout: float4 planes).
struct Frame {
  int width = 0, height = 0;
  float tanX = 1, tanY = 1, znear = 0.1f;
  int shading = 0;  // TS_SHADING_*
  bool spot = false, directional = false;
  std::vector<float> depth;
  std::vector<glm::vec4> normal, diffuse, specular, emissive;
  glm::vec3 ambient{0.0f};
  ts::ViewLights lights;
};

// An fp32 plane as float4s; an absent plane (empty) is what a material without the term has (0).
std::vector<glm::vec4> planeOf(const std::vector<uint8_t>& bytes, size_t pixels, const char* name) {
  std::vector<glm::vec4> v(pixels, glm::vec4(0.0f));
  if (bytes.empty()) return v;
  if (bytes.size() != pixels * sizeof(glm::vec4))
    throw ts::Error(std::string("the ") + name + " plane is not one float4 per pixel");
  std::memcpy(v.data(), bytes.data(), bytes.size());
  return v;
}

Frame loadFrame(const std::string& dir, ts::PreparedFrame& prepared) {
  prepared = ts::importGBuffer(dir, ts::GBufferFormat::FP32).frame;
  const ts::EncodedGBuffer& e = prepared.encoded;
  Frame f;
  f.width = e.width;
  f.height = e.height;
  f.tanX = prepared.intrinsics.tanHalfFovX;
  f.tanY = prepared.intrinsics.tanHalfFovY;
  f.znear = prepared.intrinsics.znear;
  f.shading = int(e.model);
  f.spot = prepared.features.spot;
  f.directional = prepared.features.directional;
  f.depth = e.depth;
  size_t n = e.pixelCount();
  f.normal = planeOf(e.normal, n, "normal");
  f.diffuse = planeOf(e.diffuse, n, "diffuse");
  f.specular = planeOf(e.specular, n, "specular");
  f.emissive = planeOf(e.emissive, n, "emissive");
  f.ambient = prepared.ambient;
  f.lights = prepared.lights;
  return f;
}

// A decoded pixel, as kernels/gbuffer.h's ts_load_surface forms it (fp32 layout).
struct Surface {
  yardstick::ts_shading_point p;
  glm::vec3 kd, ks, base;
};

bool loadSurface(const Frame& f, int x, int y, Surface& s) {
  size_t i = size_t(y) * size_t(f.width) + size_t(x);
  float depth = f.depth[i];
  if (depth <= 0.0f) return false;
  glm::vec3 P = yardstick::ts_view_position(x, y, depth, f.tanX, f.tanY, f.width, f.height);
  glm::vec3 V = glm::normalize(-P);
  glm::vec4 normal = f.normal[i];
  glm::vec3 N = glm::normalize(glm::vec3(normal));
  glm::vec4 diffuse = f.diffuse[i];
  glm::vec3 cDiff;
  float gloss = 1.0f;
  if (f.shading == TS_SHADING_METALLIC_ROUGHNESS) {
    yardstick::ts_metallic_roughness_terms(glm::vec3(diffuse), diffuse.w, normal.w, &cDiff, &s.kd,
                                           &s.ks, &gloss);
  } else {
    cDiff = s.kd = glm::vec3(diffuse);
    s.ks = glm::vec3(f.specular[i]);
    gloss = f.specular[i].w;
  }
  s.p = yardstick::ts_make_shading_point(P, N, V, gloss, f.shading);
  s.base = yardstick::ts_surface_base(glm::vec3(f.emissive[i]), cDiff, f.ambient);
  return true;
}

// The per-frame light data the tile loop reads: each light's culling volume and tile rectangle
// (tiled-single recomputes both in every tile; they depend on the light alone).
struct LightRect {
  yardstick::ts_light_volume volume;
  int x0, y0, x1, y1;
  bool onScreen;
};

// Thread time of a render's two phases, summed over its threads.
struct Phases {
  double cullMs = 0.0;   // depth bounds and light culling
  double shadeMs = 0.0;  // the tile's pixels over its list
};

struct Renderer {
  const Frame& f;
  int tile;
  int simd;  // 0: serial (one pixel, one light at a time); 8 or 16: lanes (Lanes8, Lanes16)
  int tilesX, tilesY;
  std::vector<LightRect> rects;
  // The rectangles again, one array per bound, padded with empty ones to whole vectors, for the
  // SIMD form's culling (16 or 8 lights per test); off-screen lights are empty (x0 > x1) too.
  std::vector<int> rectX0, rectY0, rectX1, rectY1;
  std::vector<glm::vec4> image;
  uint64_t listed = 0;  // sum over tiles of the lights listed (a check that culling ran)
  Phases phases;

  Renderer(const Frame& frame, int tileSize, int simdLanes)
      : f(frame),
        tile(tileSize),
        simd(simdLanes),
        tilesX((frame.width + tileSize - 1) / tileSize),
        tilesY((frame.height + tileSize - 1) / tileSize),
        image(size_t(frame.width) * size_t(frame.height)) {}

  void prepareLights() {
    rects.resize(f.lights.size());
    size_t padded = (rects.size() + 15) / 16 * 16;
    rectX0.assign(padded, 1);
    rectX1.assign(padded, 0);
    rectY0.assign(padded, 1);
    rectY1.assign(padded, 0);
    for (size_t i = 0; i < f.lights.size(); ++i) {
      LightRect& r = rects[i];
      r.volume = yardstick::ts_make_light_volume(f.lights.positionRange[i], f.lights.spot[i],
                                                 TS_SPOT_CULL_CONE);
      glm::vec4 b = yardstick::ts_light_ndc_bounds(&r.volume, f.znear, f.tanX, f.tanY);
      r.onScreen = yardstick::ts_ndc_bounds_to_tiles(b, f.width, f.height, tile, tile, &r.x0, &r.y0,
                                                     &r.x1, &r.y1);
      if (r.onScreen) {
        rectX0[i] = r.x0;
        rectX1[i] = r.x1;
        rectY0[i] = r.y0;
        rectY1[i] = r.y1;
      }
    }
  }

  // One tile: depth bounds, culling, shading; returns the lights it listed.
  uint32_t shadeTile(int tx, int ty, std::vector<uint32_t>& list, Phases& ph) {
    auto t0 = Clock::now();
    int px0 = tx * tile, py0 = ty * tile;
    int px1 = std::min(px0 + tile, f.width), py1 = std::min(py0 + tile, f.height);
    float zmin = 3.402823466e38f, zmax = 0.0f;
    for (int y = py0; y < py1; ++y)
      for (int x = px0; x < px1; ++x) {
        float z = f.depth[size_t(y) * size_t(f.width) + size_t(x)];
        if (z > 0.0f) {
          zmin = std::min(zmin, z);
          zmax = std::max(zmax, z);
        }
      }
    list.clear();
    if (zmin <= zmax) {
      if (simd == 16) cullLanes<Lanes16>(tx, ty, px0, py0, px1, py1, zmin, zmax, list);
      else if (simd == 8) cullLanes<Lanes8>(tx, ty, px0, py0, px1, py1, zmin, zmax, list);
      else
        for (uint32_t i = 0; i < rects.size(); ++i) {
          const LightRect& r = rects[i];
          if (!r.onScreen || tx < r.x0 || tx > r.x1 || ty < r.y0 || ty > r.y1) continue;
          listIfMeets(i, px0, py0, px1, py1, zmin, zmax, list);
        }
    }
    auto t1 = Clock::now();
    if (simd == 16) shadeLanes<Lanes16>(px0, py0, px1, py1, list);
    else if (simd == 8) shadeLanes<Lanes8>(px0, py0, px1, py1, list);
    else if (f.spot) shadePixels<1>(px0, py0, px1, py1, list);
    else shadePixels<0>(px0, py0, px1, py1, list);
    auto t2 = Clock::now();
    ph.cullMs += std::chrono::duration<double, std::milli>(t1 - t0).count();
    ph.shadeMs += std::chrono::duration<double, std::milli>(t2 - t1).count();
    return uint32_t(list.size());
  }

  // The tests after the rectangle's: the depth range, then kernels/culling.h's tile test.
  void listIfMeets(uint32_t i, int px0, int py0, int px1, int py1, float zmin, float zmax,
                   std::vector<uint32_t>& list) const {
    const LightRect& r = rects[i];
    if (!yardstick::ts_light_meets_depth_range(&r.volume, zmin, zmax)) return;
    if (yardstick::ts_light_meets_tile(&r.volume, TS_CULL_RECT, px0, py0, px1, py1, f.width,
                                       f.height, f.tanX, f.tanY, zmin, zmax))
      list.push_back(i);
  }

  // The rectangle test on L::count lights at once (most lights miss a tile's rectangle); the
  // lights that pass go through the scalar tests in order, so the list is the serial form's.
  template <class L>
  void cullLanes(int tx, int ty, int px0, int py0, int px1, int py1, float zmin, float zmax,
                 std::vector<uint32_t>& list) const {
    using Mask = typename L::Mask;
    for (size_t g = 0; g < rectX0.size(); g += L::count) {
      Mask x0, y0, x1, y1;
      std::memcpy(&x0, &rectX0[g], sizeof(Mask));
      std::memcpy(&x1, &rectX1[g], sizeof(Mask));
      std::memcpy(&y0, &rectY0[g], sizeof(Mask));
      std::memcpy(&y1, &rectY1[g], sizeof(Mask));
      Mask in = (x0 <= tx) & (x1 >= tx) & (y0 <= ty) & (y1 >= ty);
      if (!yardstick::any(in)) continue;
      for (int k = 0; k < L::count; ++k)
        if (in[k]) listIfMeets(uint32_t(g) + uint32_t(k), px0, py0, px1, py1, zmin, zmax, list);
    }
  }

  // Lights in list order, then the directional ones, then the base: the kernels' order.
  template <int Spot>
  void shadePixels(int px0, int py0, int px1, int py1, const std::vector<uint32_t>& list) {
    const glm::vec4* posRange = f.lights.positionRange.data();
    const glm::vec4* color = f.lights.color.data();
    const glm::vec4* spot = f.lights.spot.data();
    for (int y = py0; y < py1; ++y)
      for (int x = px0; x < px1; ++x) {
        Surface s;
        glm::vec4& out = image[size_t(y) * size_t(f.width) + size_t(x)];
        if (!loadSurface(f, x, y, s)) {
          out = glm::vec4(0.0f);
          continue;
        }
        glm::vec3 sum(0.0f);
        for (uint32_t i : list)
          sum += yardstick::ts_punctual_light(&s.p, s.kd, s.ks, posRange[i], color[i], spot[i],
                                              TS_MODEL_WINDOWED, f.shading, 1, Spot);
        for (size_t k = 0; f.directional && k < f.lights.directionalCount(); ++k)
          sum += yardstick::ts_directional_light(
              &s.p, s.kd, s.ks, glm::vec3(f.lights.directionalDir[k]),
              glm::vec3(f.lights.directionalColor[k]), f.shading, 1);
        out = glm::vec4(sum + s.base, 0.0f);
      }
  }

  // The SIMD form: the tile in blocks of L::count pixels, each block's surfaces in lanes (decoded
  // one pixel at a time by loadSurface, as the lanes kernels do), then every light of the list
  // for all of the block's pixels at once with shading.h's lane functions; the same order of
  // terms as shadePixels, lane by lane. Lanes outside the tile or on the background are unlit
  // slots (kernels/lanes.h's: far away, black, no normal), which no light reaches.
  template <class L>
  void shadeLanes(int px0, int py0, int px1, int py1, const std::vector<uint32_t>& list) {
    if (f.spot) {
      if (f.shading == TS_SHADING_METALLIC_ROUGHNESS)
        shadeLanes<L, 1, TS_SHADING_METALLIC_ROUGHNESS>(px0, py0, px1, py1, list);
      else shadeLanes<L, 1, TS_SHADING_BLINN_PHONG>(px0, py0, px1, py1, list);
    } else {
      if (f.shading == TS_SHADING_METALLIC_ROUGHNESS)
        shadeLanes<L, 0, TS_SHADING_METALLIC_ROUGHNESS>(px0, py0, px1, py1, list);
      else shadeLanes<L, 0, TS_SHADING_BLINN_PHONG>(px0, py0, px1, py1, list);
    }
  }

  template <class L, int Spot, int Shading>
  void shadeLanes(int px0, int py0, int px1, int py1, const std::vector<uint32_t>& list) {
    using V = typename L::Floats;
    constexpr int N = L::count;
    auto all = [](float x) { return yardstick::cast<V>(x); };
    const glm::vec4* posRange = f.lights.positionRange.data();
    const glm::vec4* color = f.lights.color.data();
    const glm::vec4* spot = f.lights.spot.data();
    for (int by = py0; by < py1; by += L::blockH)
      for (int bx = px0; bx < px1; bx += L::blockW) {
        typename L::Point p;
        V kdr, kdg, kdb, ksr, ksg, ksb;
        glm::vec3 base[N];
        bool inTile[N], lit[N], anyLit = false;
        for (int k = 0; k < N; ++k) {
          int x = bx + k % L::blockW, y = by + k / L::blockW;
          Surface s;
          inTile[k] = x < px1 && y < py1;
          lit[k] = inTile[k] && loadSurface(f, x, y, s);
          anyLit |= lit[k];
          if (!lit[k]) {
            s.p = {0.0f, 0.0f, -1e18f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 1.0f, 1.0f};
            s.kd = s.ks = s.base = glm::vec3(0.0f);
          }
          p.px[k] = s.p.px, p.py[k] = s.p.py, p.pz[k] = s.p.pz;
          p.nx[k] = s.p.nx, p.ny[k] = s.p.ny, p.nz[k] = s.p.nz;
          p.vx[k] = s.p.vx, p.vy[k] = s.p.vy, p.vz[k] = s.p.vz;
          p.gloss[k] = s.p.gloss, p.view_term[k] = s.p.view_term;
          kdr[k] = s.kd.x, kdg[k] = s.kd.y, kdb[k] = s.kd.z;
          ksr[k] = s.ks.x, ksg[k] = s.ks.y, ksb[k] = s.ks.z;
          base[k] = s.base;
        }
        V r{}, g{}, b{};
        for (size_t li = 0; anyLit && li < list.size(); ++li) {
          uint32_t i = list[li];
          const glm::vec4 pr = posRange[i], c = color[i], sp = spot[i];
          typename L::Weights w = L::punctual(
              &p, all(pr.x), all(pr.y), all(pr.z), all(pr.w), all(1.0f / (pr.w * pr.w)), all(sp.x),
              all(sp.y), all(sp.z), all(sp.w), all(c.w), TS_MODEL_WINDOWED, Shading, 1, Spot);
          r += c.x * (w.wd * kdr + w.ws * ksr + w.wf);
          g += c.y * (w.wd * kdg + w.ws * ksg + w.wf);
          b += c.z * (w.wd * kdb + w.ws * ksb + w.wf);
        }
        for (size_t k = 0; anyLit && f.directional && k < f.lights.directionalCount(); ++k) {
          const glm::vec4 d = f.lights.directionalDir[k], c = f.lights.directionalColor[k];
          typename L::Weights w = L::directional(&p, all(d.x), all(d.y), all(d.z), Shading, 1);
          r += c.x * (w.wd * kdr + w.ws * ksr + w.wf);
          g += c.y * (w.wd * kdg + w.ws * ksg + w.wf);
          b += c.z * (w.wd * kdb + w.ws * ksb + w.wf);
        }
        for (int k = 0; k < N; ++k) {
          if (!inTile[k]) continue;
          int x = bx + k % L::blockW, y = by + k / L::blockW;
          image[size_t(y) * size_t(f.width) + size_t(x)] =
              lit[k] ? glm::vec4(glm::vec3(r[k], g[k], b[k]) + base[k], 0.0f) : glm::vec4(0.0f);
        }
      }
  }

  void render(int threads) {
    prepareLights();
    const int tiles = tilesX * tilesY;
    std::atomic<int> next{0};
    std::atomic<uint64_t> total{0};
    std::mutex phasesMutex;
    phases = Phases{};
    auto worker = [&] {
      std::vector<uint32_t> list;
      list.reserve(rects.size());
      uint64_t mine = 0;
      Phases ph;
      for (int t; (t = next++) < tiles;) mine += shadeTile(t % tilesX, t / tilesX, list, ph);
      total += mine;
      std::lock_guard<std::mutex> lock(phasesMutex);
      phases.cullMs += ph.cullMs;
      phases.shadeMs += ph.shadeMs;
    };
    if (threads <= 1) {
      worker();
    } else {
      std::vector<std::thread> pool;
      for (int i = 0; i < threads; ++i) pool.emplace_back(worker);
      for (auto& th : pool) th.join();
    }
    listed = total;
  }
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// Largest channel difference over the peak channel value of `truth`.
struct ImageError {
  double maxAbs = 0.0, peak = 0.0;
  double relPeak() const { return peak > 0 ? maxAbs / peak : maxAbs; }
};

template <typename Truth>
ImageError compare(const std::vector<glm::vec4>& image, size_t pixels, Truth truth) {
  ImageError e;
  for (size_t i = 0; i < pixels; ++i)
    for (int c = 0; c < 3; ++c) {
      double t = truth(i, c), v = double(image[i][c]);
      e.peak = std::max(e.peak, std::fabs(t));
      e.maxAbs = std::max(e.maxAbs, std::isfinite(v) ? std::fabs(v - t) : INFINITY);
    }
  return e;
}

int run(int argc, char** argv) {
  std::string dir, compareImage;
  int runs = 5, threads = 1, tile = 16, simd = 0;
  bool reference = false;
  double maxError = -1.0;
  CLI::App app{
      "tileshade-yardstick: the per-tile loop of tiled-single as serial C++ "
      "(-O3 -march=native) on a `render --dump` folder"};
  app.add_option("dump", dir, "folder written by `tileshade render --dump`")->required();
  app.add_option("--runs", runs, "timed runs (after one warm-up); the median is printed")
      ->check(CLI::Range(1, 1000));
  app.add_option("--threads", threads, "threads over tiles (0: every core)")
      ->check(CLI::Range(0, 256));
  app.add_option("--tile", tile, "tile size in pixels (square)")->check(CLI::Range(1, 1024));
  app.add_option("--simd", simd,
                 "the SIMD form: each tile's pixels shaded 8 or 16 at a time in vector lanes, "
                 "lights culled as many at a time (0: serial, the default)")
      ->check(CLI::IsMember({0, 8, 16}));
  app.add_option("--compare", compareImage,
                 "an image.exr of tileshade's from the same dump: print the error against it");
  app.add_flag("--reference", reference, "print the error against the double-precision reference");
  app.add_option("--max-error", maxError,
                 "exit 1 when an error (max abs / peak) printed is above this");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  if (threads == 0) threads = int(std::max(1u, std::thread::hardware_concurrency()));

  ts::PreparedFrame prepared;
  Frame f = loadFrame(dir, prepared);
  Renderer r(f, tile, simd);
  r.render(threads);  // warm-up
  std::vector<double> ms;
  std::vector<std::pair<double, Phases>> byTime;
  for (int i = 0; i < runs; ++i) {
    auto t0 = Clock::now();
    r.render(threads);
    ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
    byTime.emplace_back(ms.back(), r.phases);
  }
  std::sort(byTime.begin(), byTime.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  const Phases& middle = byTime[byTime.size() / 2].second;
  size_t pixels = size_t(f.width) * size_t(f.height);
  std::printf(
      "yardstick: %dx%d, %zu lights, tile %d, threads %d, %s: median %.3f ms of %d runs "
      "(min %.3f, max %.3f); %.1f lights listed per tile\n",
      f.width, f.height, f.lights.size(), tile, threads,
      simd ? (simd == 16 ? "simd 16 lanes" : "simd 8 lanes") : "serial", median(ms), runs,
      *std::min_element(ms.begin(), ms.end()), *std::max_element(ms.begin(), ms.end()),
      double(r.listed) / double(r.tilesX * r.tilesY));
  std::printf(
      "phases (thread time of the middle run): depth bounds + culling %.3f ms, shading %.3f ms\n",
      middle.cullMs, middle.shadeMs);
  bool tooLarge = false;
  auto report = [&](const char* against, const ImageError& e) {
    std::printf("error against %s: max abs %.3g, peak %.6g, max abs / peak %.3g\n", against,
                e.maxAbs, e.peak, e.relPeak());
    if (maxError >= 0 && !(e.relPeak() <= maxError)) tooLarge = true;
  };
  if (reference) {
    ts::ReferenceImage ref =
        ts::shadeReference(prepared.encoded, prepared.intrinsics, prepared.lights, prepared.ambient,
                           TS_MODEL_WINDOWED, 0, {}, ts::ReferencePositions::KernelFloat);
    report("the double reference (kernel positions)",
           compare(r.image, pixels, [&](size_t i, int c) { return ref.rgb[i][c]; }));
  }
  if (!compareImage.empty()) {
    ts::FloatImage img = ts::readImage(compareImage);
    int R = img.channel("R"), G = img.channel("G"), B = img.channel("B");
    if (img.width != f.width || img.height != f.height || R < 0 || G < 0 || B < 0)
      throw ts::Error(compareImage + ": not an RGB image of " + std::to_string(f.width) + "x" +
                      std::to_string(f.height));
    const int ch[3] = {R, G, B};
    size_t stride = img.channels.size();
    report(compareImage.c_str(), compare(r.image, pixels, [&](size_t i, int c) {
             return double(img.data[i * stride + size_t(ch[c])]);
           }));
  }
  if (tooLarge) {
    std::fprintf(stderr, "tileshade-yardstick: error: an error is above --max-error %g\n",
                 maxError);
    return 1;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "tileshade-yardstick: error: %s\n", e.what());
    return 1;
  }
}
