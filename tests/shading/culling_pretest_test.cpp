// The single-kernel technique's cheap pre-test (kernels/culling.h, ts_light_may_meet_tile) in
// float, as the kernels compute it: it must never reject a light whose volume's tile rectangle
// holds the tile and whose depth extent meets the tile's range (the full tests, in float too),
// for points, cones of every angle and every spot culling mode, lights straddling the near plane
// or around the camera; and it must reject most lights that miss the tile (else it buys nothing).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "shading/shading_cpu.h"
#include "random_draws.h"

namespace {

using glm::vec3;
using glm::vec4;
using namespace ts::shading_f;

struct Tile {
  int x, y, tileW, tileH, width, height;
  float zmin, zmax;
};

// ts_light_tile_rect (kernels/light_lists.h) and the depth-range test: what the full test
// decides before its per-tile test, which can only reject more.
bool fullTestsAccept(const ts_light_volume& v, const Tile& t, float znear, float tanX, float tanY) {
  vec4 b = ts_light_ndc_bounds(&v, znear, tanX, tanY);
  int x0, y0, x1, y1;
  if (!ts_ndc_bounds_to_tiles(b, t.width, t.height, t.tileW, t.tileH, &x0, &y0, &x1, &y1))
    return false;
  if (t.x < x0 || t.x > x1 || t.y < y0 || t.y > y1) return false;
  return ts_light_meets_depth_range(&v, t.zmin, t.zmax);
}

bool pretestAccepts(vec4 posRange, vec4 spot, const Tile& t, float tanX, float tanY) {
  vec4 s = ts_pretest_slopes(t.x * t.tileW, t.y * t.tileH, (t.x + 1) * t.tileW, (t.y + 1) * t.tileH,
                             t.width, t.height, tanX, tanY);
  return ts_light_may_meet_tile(posRange, spot, s, ts_pretest_norms(s), t.zmin, t.zmax);
}

TEST(CullingPretest, NeverRejectsWhatTheFullTestsAcceptAndRejectsMostMisses) {
  std::mt19937 rng(19);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  auto draw = [&] { return u(rng); };
  const float znear = 0.1f, tanX = 0.8f, tanY = 0.45f;
  int accepted = 0, missed = 0, rejectedMisses = 0;
  for (int i = 0; i < 200000; ++i) {
    const auto d = ts::test::drawnLastFirst<12>(draw);
    int tileSize = d[0] < 0.5f ? 16 : 64;
    Tile t{0, 0, tileSize, tileSize, 320, 180, 0, 0};
    t.x = int(d[1] * float((t.width + tileSize - 1) / tileSize));
    t.y = int(d[2] * float((t.height + tileSize - 1) / tileSize));
    t.zmin = 0.1f + 30.0f * d[3];
    t.zmax = t.zmin + 10.0f * d[4] * d[4];
    // Centres in and around the view frustum, some behind or around the camera.
    float w = -2.0f + 40.0f * d[5];
    vec4 posRange((d[6] - 0.5f) * 2.5f * std::abs(w) + (d[6] - 0.5f),
                  (d[7] - 0.5f) * 1.5f * std::abs(w) + (d[7] - 0.5f), -w,
                  0.05f + 6.0f * d[8] * d[8]);
    vec4 spot(0, 0, 0, -1);  // a point light
    if (d[9] < 0.6f) {       // a spot light of any angle, on any axis
      const auto a = ts::test::drawnLastFirst<3>(draw);
      vec3 axis(a[0] - 0.5f, a[1] - 0.5f, a[2] - 0.5f);
      if (glm::length(axis) < 1e-3f) continue;
      axis = glm::normalize(axis);
      spot = vec4(axis, -1.0f + 2.0f * d[10]);
    }
    int mode = int(d[11] * 3.0f) % 3;  // TS_SPOT_CULL_CONE, _BOUND_SPHERE, _RANGE_SPHERE
    ts_light_volume v = ts_make_light_volume(posRange, spot, mode);
    bool full = fullTestsAccept(v, t, znear, tanX, tanY);
    bool pre = pretestAccepts(posRange, spot, t, tanX, tanY);
    if (full) {
      ++accepted;
      ASSERT_TRUE(pre) << "light " << i << " at (" << posRange.x << ", " << posRange.y << ", "
                       << posRange.z << ") range " << posRange.w << " spot w " << spot.w << " mode "
                       << mode << ", tile " << t.x << "," << t.y;
    } else {
      ++missed;
      if (!pre) ++rejectedMisses;
    }
  }
  EXPECT_GT(accepted, 1000);
  EXPECT_GT(rejectedMisses, missed / 2) << rejectedMisses << " of " << missed << " misses rejected";
}

}  // namespace
