// tiled's light binning (kernels/tiled.cl through TileLightGrid): every tile's list is exactly the
// lights a brute per-tile test on the host keeps (kernels/culling.h in float, against the
// device's own tile depth ranges), in light index order, whichever path bins a light (one
// work-item per light, or a work-group per big light), on frames with thousands of lights of
// mixed sizes, spot lights, lights behind the camera and volumes through the near plane, in
// every culling mode, with the depth split and odd tile sizes, through a list that has to grow.
#include <gtest/gtest.h>

#include <algorithm>
#include <cfloat>
#include <random>
#include <string>
#include <vector>

#include "shading/shading_cpu.h"
#include "techniques/tile_light_grid.h"
#include "reference_check.h"
#include "test_support.h"

namespace ts {
namespace {

using Lists = std::vector<std::vector<uint32_t>>;  // per tile, its light indices

// The frame's G-buffer lit by `count` view-space lights: sizes from a fraction of a tile to
// the whole screen (log-uniform ranges), a third of them spot lights of any axis and angle, some
// behind the camera, and one in ten within a range of the eye (the near plane cuts the volume,
// or the eye is inside it).
PreparedFrame withMixedLights(PreparedFrame f, int count, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  ViewLights lights;
  for (int i = 0; i < count; ++i) {
    const auto p = test::drawnLastFirst<3>([&] { return u(rng); });
    glm::vec3 position(60.0f * p[0] - 30.0f, 30.0f * p[1] - 15.0f, 5.0f - 70.0f * p[2]);
    float range = 0.05f * std::pow(1000.0f, u(rng));  // 0.05 .. 50
    if (i % 10 == 0) {
      position *= 0.02f;  // within ~1 of the eye
      range = std::max(range, 0.5f);
    }
    const glm::vec3 colour(0.1f);
    if (i % 3 == 1) {
      const auto a = test::drawnLastFirst<3>([&] { return u(rng); });
      glm::vec3 axis = glm::vec3(a[0], a[1], a[2]) * 2.0f - 1.0f;
      axis = glm::length(axis) > 1e-3f ? glm::normalize(axis) : glm::vec3(0, 0, -1);
      const float outer = 0.05f + 1.5f * u(rng);
      lights.addSpot(position, range, colour, axis, 0.5f * outer, outer);
    } else {
      lights.addPoint(position, range, colour);
    }
  }
  f.lights = std::move(lights);
  return f;
}

struct Binned {
  Lists lists;
  std::vector<glm::vec4> depth;  // the tile depth ranges binning tested against
  std::vector<std::string> notes;
};

// Bins the frame's lights on the device with tiled.cl built for `config`; aloneTiles < 0 keeps
// the device's default split between the two paths.
Binned binOnDevice(const PreparedFrame& f, const TechniqueConfig& config, int aloneTiles) {
  ClContext& cl = test::context();
  const cl::Program program = cl.build(
      "tiled.cl", config.kernelOptions() + " -DTILE_W=" + std::to_string(config.tileWidth) +
                      " -DTILE_H=" + std::to_string(config.tileHeight));
  TileLightGrid grid(cl, program);
  if (aloneTiles >= 0) grid.setAloneTiles(aloneTiles);
  DeviceFrame frame = f.upload(cl);
  const int w = frame.width(), h = frame.height();
  grid.allocate(w, h, config.tileWidth, config.tileHeight);
  FrameTimer timer;
  Binned b;
  const uint32_t total = grid.runUntilListFits(
      [&] {
        timer.clear();
        grid.enqueueClear(timer);
        grid.enqueueDepthBounds(frame.depth, w, h, timer);
        grid.enqueueBinning(frame, timer);
      },
      b.notes);
  const std::vector<uint32_t> counts = grid.readCounts(), offsets = grid.readOffsets();
  const std::vector<uint32_t> lights = grid.readLights(total);
  for (size_t t = 0; t < counts.size(); ++t)
    b.lists.emplace_back(lights.begin() + offsets[t], lights.begin() + offsets[t] + counts[t]);
  b.depth.resize(counts.size());
  cl.queue().enqueueReadBuffer(grid.depthBounds(), CL_TRUE, 0, b.depth.size() * sizeof(glm::vec4),
                               b.depth.data());
  return b;
}

// Light i's volume and tile rectangle, as the kernels compute them (culling.h in float).
struct HostRect {
  shading_f::ts_light_volume volume;
  int x0 = 0, y0 = 0, x1 = -1, y1 = -1;
  int tiles() const { return x1 < x0 ? 0 : (x1 - x0 + 1) * (y1 - y0 + 1); }
};
HostRect hostRect(const PreparedFrame& f, const TileGrid& g, size_t i, SpotCulling spot) {
  HostRect r;
  r.volume =
      shading_f::ts_make_light_volume(f.lights.positionRange[i], f.lights.spot[i], int(spot));
  const CameraIntrinsics& cam = f.intrinsics;
  glm::vec4 b =
      shading_f::ts_light_ndc_bounds(&r.volume, cam.znear, cam.tanHalfFovX, cam.tanHalfFovY);
  if (!shading_f::ts_ndc_bounds_to_tiles(b, g.width, g.height, g.tileW, g.tileH, &r.x0, &r.y0,
                                         &r.x1, &r.y1))
    r.x1 = r.x0 - 1;
  return r;
}

// The brute per-tile test: every tile of every light's rectangle against each of the tile's
// depth ranges (the second is empty without the depth split) and the culling test.
Lists hostLists(const PreparedFrame& f, const TileGrid& g, const std::vector<glm::vec4>& depth,
                CullTest cull, SpotCulling spot) {
  const CameraIntrinsics& cam = f.intrinsics;
  Lists lists(size_t(g.count()));
  for (size_t i = 0; i < f.lights.size(); ++i) {
    const HostRect r = hostRect(f, g, i, spot);
    for (int ty = r.y0; ty <= r.y1; ++ty)
      for (int tx = r.x0; tx <= r.x1; ++tx) {
        const int t = ty * g.tilesX + tx;
        auto meets = [&](float zmin, float zmax) {
          return shading_f::ts_light_meets_depth_range(&r.volume, zmin, zmax) &&
                 shading_f::ts_light_meets_tile(
                     &r.volume, int(cull), tx * g.tileW, ty * g.tileH,
                     std::min((tx + 1) * g.tileW, g.width), std::min((ty + 1) * g.tileH, g.height),
                     g.width, g.height, cam.tanHalfFovX, cam.tanHalfFovY, zmin, zmax);
        };
        const glm::vec4 z = depth[size_t(t)];
        if (meets(z.x, z.y) || (z.z <= z.w && meets(z.z, z.w)))
          lists[size_t(t)].push_back(uint32_t(i));
      }
  }
  return lists;
}

// Lights whose rectangle holds more than `tiles` tiles.
int lightsAbove(const PreparedFrame& f, const TileGrid& g, SpotCulling spot, int tiles) {
  int n = 0;
  for (size_t i = 0; i < f.lights.size(); ++i) n += hostRect(f, g, i, spot).tiles() > tiles;
  return n;
}

void expectSameLists(const Lists& device, const Lists& host, const std::string& label) {
  ASSERT_EQ(device.size(), host.size()) << label;
  size_t entries = 0, differing = 0;
  for (size_t t = 0; t < host.size(); ++t) {
    entries += host[t].size();
    if (device[t] != host[t] && differing++ < 3)
      ADD_FAILURE() << label << ": tile " << t << " lists " << device[t].size()
                    << " lights, the host " << host[t].size();
  }
  EXPECT_EQ(differing, 0u) << label;
  EXPECT_GT(entries, 0u) << label << ": nothing binned, nothing tested";
}

struct GridCase {
  int tileW, tileH;
  CullTest cull;
  bool depthSplit;
  SpotCulling spot;
};

TEST(TileLightGrid, ListsEqualTheBrutePerTileTestOnBothPaths) {
  const GridCase cases[] = {{16, 16, CullTest::Rect, false, SpotCulling::Cone},
                            {7, 5, CullTest::Aabb, true, SpotCulling::Cone},
                            {32, 16, CullTest::Frustum, false, SpotCulling::BoundSphere}};
  const auto cameras = test::randomCameraFrames(23, 2);
  for (const GridCase& k : cases) {
    TechniqueConfig config;
    config.tileWidth = k.tileW;
    config.tileHeight = k.tileH;
    config.culling = k.cull;
    config.depthSplit = k.depthSplit;
    config.spotCulling = k.spot;
    for (size_t c = 0; c < cameras.size(); ++c) {
      const PreparedFrame f = withMixedLights(cameras[c].frame, 3000, uint32_t(c) + 1);
      const TileGrid g(f.intrinsics.width, f.intrinsics.height, k.tileW, k.tileH);
      // Both paths have lights to bin: most lights are small, some cover the screen.
      const int big = lightsAbove(f, g, k.spot, 16);
      ASSERT_GT(big, 0) << cameras[c].label;
      ASSERT_LT(big, lightsAbove(f, g, k.spot, 0)) << cameras[c].label;
      const std::string label = cameras[c].label + " tile " + std::to_string(k.tileW) + "x" +
                                std::to_string(k.tileH) + " " + toString(k.cull) +
                                (k.depthSplit ? " split" : "") + " " + toString(k.spot);
      // The device default, every light by a work-group, and a mix of both.
      for (int alone : {-1, 0, 16}) {
        Binned b = binOnDevice(f, config, alone);
        expectSameLists(b.lists, hostLists(f, g, b.depth, k.cull, k.spot),
                        label + " alone " + std::to_string(alone));
      }
    }
  }
}

// The list starts at the small default buffer: it grows and the frame re-runs, and the lists
// are still complete (no entry dropped) on both paths.
TEST(TileLightGrid, GrownListLosesNothingOnBothPaths) {
  const auto cameras = test::randomCameraFrames(29, 1);
  const PreparedFrame f = withMixedLights(cameras[0].frame, 2000, 7);
  TechniqueConfig config;
  const TileGrid g(f.intrinsics.width, f.intrinsics.height, config.tileWidth, config.tileHeight);
  for (int alone : {TileLightGrid::kNoBigLights, 0, 16}) {
    Binned b = binOnDevice(f, config, alone);
    ASSERT_FALSE(b.notes.empty()) << "the list never had to grow";
    EXPECT_NE(b.notes[0].find("grown"), std::string::npos);
    expectSameLists(b.lists, hostLists(f, g, b.depth, config.culling, config.spotCulling),
                    "alone " + std::to_string(alone));
  }
}

// What the Oclgrind run checks (tests/extra_tests.cmake): both paths on a frame of a few tiles.
TEST(TileLightGrid, TinyFrameOnBothPaths) {
  PreparedFrame f =
      prepareFrame(test::builtinScene("street", "many"), 0, 40, 24, GBufferFormat::FP32);
  f = withMixedLights(std::move(f), 40, 3);
  TechniqueConfig config;
  config.tileWidth = config.tileHeight = 8;
  const TileGrid g(40, 24, 8, 8);
  for (int alone : {TileLightGrid::kNoBigLights, 0, 4}) {
    Binned b = binOnDevice(f, config, alone);
    expectSameLists(b.lists, hostLists(f, g, b.depth, config.culling, config.spotCulling),
                    "alone " + std::to_string(alone));
  }
}

}  // namespace
}  // namespace ts
