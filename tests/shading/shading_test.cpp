// The shared shading and culling headers (kernels/shading.h, kernels/culling.h) compiled as C++:
// analytic cases of the model and numerical checks of the conservative sphere bounds.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "shading/shading_cpu.h"
#include "util/pi.h"
#include "random_draws.h"

namespace {

using glm::dvec3;
using glm::dvec4;
using namespace ts::shading_d;

TEST(Shading, DiffuseOnlyMatchesHandComputedValue) {
  dvec3 P(0, 0, -5), N(0, 0, 1), V = glm::normalize(-P);
  dvec3 Lp(0, 0, -3);  // 2 units straight above the surface
  double r = 4.0;
  dvec3 c =
      ts_point_light(P, N, V, dvec3(0.5), dvec3(0.0), 16.0, Lp, dvec3(1.0), r, TS_MODEL_WINDOWED);
  double q = 4.0 / 16.0;
  double window = (1 - q * q) * (1 - q * q);
  EXPECT_NEAR(c.x, 0.5 * window / 4.0, 1e-15);
}

TEST(Shading, NothingAtOrBeyondTheRangeButPhysicalModelIgnoresRange) {
  dvec3 P(0, 0, -5), N(0, 0, 1), V = glm::normalize(-P);
  dvec3 Lp(0, 0, -3);
  EXPECT_EQ(ts_point_light(P, N, V, dvec3(1), dvec3(1), 8, Lp, dvec3(1), 2.0, TS_MODEL_WINDOWED),
            dvec3(0.0));
  dvec3 phys = ts_point_light(P, N, V, dvec3(1), dvec3(0), 8, Lp, dvec3(1), 2.0, TS_MODEL_PHYSICAL);
  EXPECT_NEAR(phys.x, 1.0 / 4.0, 1e-15);
}

TEST(Shading, WindowFallsContinuouslyToZeroAtTheRange) {
  dvec3 P(0, 0, -5), N(0, 0, 1), V = glm::normalize(-P);
  double r = 3.0;
  double prev = 1e30;
  for (double d = 0.5; d < r; d += 0.01) {
    dvec3 c = ts_point_light(P, N, V, dvec3(1), dvec3(0), 8, P + dvec3(0, 0, d), dvec3(1), r,
                             TS_MODEL_WINDOWED);
    EXPECT_LT(c.x, prev);
    prev = c.x;
  }
  EXPECT_LT(prev, 1e-5);
}

TEST(Shading, DegenerateCasesStayFinite) {
  dvec3 P(0, 0, -5), N(0, 0, 1), V = glm::normalize(-P);
  // Light exactly on the point: no direction, no contribution.
  EXPECT_EQ(ts_point_light(P, N, V, dvec3(1), dvec3(1), 8, P, dvec3(1), 1.0, TS_MODEL_WINDOWED),
            dvec3(0.0));
  // Light touching the surface: falloff clamped by dmin, finite.
  dvec3 c = ts_point_light(P, N, V, dvec3(1), dvec3(1), 8, P + dvec3(0, 0, 1e-9), dvec3(1), 1.0,
                           TS_MODEL_WINDOWED);
  EXPECT_TRUE(std::isfinite(c.x));
  EXPECT_LE(c.x, 2.0 / (TS_DMIN * TS_DMIN) * (1.0 + 1e-12));
  // Half vector of zero length (light exactly opposite the viewer): specular is 0, no NaN.
  dvec3 Pside(0, 0, -1), Nside(1, 0, 0), Vside = glm::normalize(-Pside);
  dvec3 behind = Pside + dvec3(0, 0, -1);  // l = -V
  dvec3 s = ts_point_light(Pside, Nside, Vside, dvec3(0), dvec3(1), 8, behind, dvec3(1), 5.0,
                           TS_MODEL_WINDOWED);
  EXPECT_EQ(s, dvec3(0.0));
  // Light below the surface: nothing.
  EXPECT_EQ(ts_point_light(P, N, V, dvec3(1), dvec3(1), 8, P - dvec3(0, 0, 1), dvec3(1), 5.0,
                           TS_MODEL_WINDOWED),
            dvec3(0.0));
}

// A light crossing the surface's plane (N.l from -1e-3 to 1e-3, through the float rounding of
// the positions): the contribution falls continuously to 0 as the light reaches the plane, and
// the float build stays within rounding of the double one. With the specular term gated on
// N.l > 0 but not weighted by it (the model before issue #12), the whole highlight switched on at
// N.l = 0+ (here ks/(kd+ks) = 0.4 of the peak) and float and double disagreed on the side.
TEST(Shading, ContinuousAsTheLightCrossesTheSurfacePlane) {
  const dvec3 P(0.3, -1.0, -5.0), N(0, 1, 0), V = glm::normalize(-P);
  const dvec3 kd(0.6), ks(0.4);
  const double s = 2.0, r = 10.0;
  auto shadeD = [&](dvec3 Lp) {
    return ts_point_light(P, N, V, kd, ks, s, Lp, dvec3(1.0), r, TS_MODEL_WINDOWED);
  };
  auto shadeF = [&](dvec3 Lp) {
    glm::vec3 Pf(P);
    return glm::dvec3(ts::shading_f::ts_point_light(
        Pf, glm::vec3(N), glm::normalize(-Pf), glm::vec3(kd), glm::vec3(ks), float(s),
        glm::vec3(Lp), glm::vec3(1.0f), float(r), TS_MODEL_WINDOWED));
  };
  const double peak = shadeD(P + dvec3(0, 2, 0)).x;  // 2 units straight above
  ASSERT_GT(peak, 0.0);
  for (double e : {-1e-3, -1e-5, -1e-6, -1e-7, -1e-8, 0.0, 1e-8, 1e-7, 1e-6, 1e-5, 1e-3}) {
    dvec3 Lp = P + dvec3(0.1, e, -2.0);  // 2 units away along the surface, e above it
    dvec3 d = shadeD(Lp), f = shadeF(Lp);
    double ndl = std::max(e / glm::length(Lp - P), 0.0);
    for (int c = 0; c < 3; ++c) {
      // Every term carries ndl: at most falloff * ndl * (kd + ks), falloff <= 1/4 here.
      EXPECT_LE(d[c], 0.25 * ndl * (kd[c] + ks[c]) * (1 + 1e-12)) << "N.l offset " << e;
      // Float positions round the light's height by ~1e-7: the error stays of that order.
      EXPECT_NEAR(f[c], d[c], 1e-6 * peak) << "N.l offset " << e;
    }
  }
}

TEST(Shading, FloatBuildAgreesWithDoubleToFloatRounding) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 1000; ++i) {
    auto draw = [&] { return u(rng); };
    const auto p = ts::test::drawnLastFirst<3>(draw);
    dvec3 P(p[0] * 5, p[1] * 5, -3 - 5 * std::abs(p[2]));
    const auto n = ts::test::drawnLastFirst<3>(draw);
    dvec3 N = glm::normalize(dvec3(n[0], n[1], n[2]) + dvec3(0, 0, 1.5));
    const auto l = ts::test::drawnLastFirst<3>(draw);
    dvec3 Lp = P + 3.0 * dvec3(l[0], l[1], l[2]);
    dvec3 d = ts_point_light(P, N, glm::normalize(-P), dvec3(0.7), dvec3(0.3), 24, Lp, dvec3(2.0),
                             4.0, TS_MODEL_WINDOWED);
    glm::vec3 Pf(P), Nf(N), Lf(Lp);
    glm::vec3 f =
        ts::shading_f::ts_point_light(Pf, Nf, glm::normalize(-Pf), glm::vec3(0.7f), glm::vec3(0.3f),
                                      24.0f, Lf, glm::vec3(2.0f), 4.0f, TS_MODEL_WINDOWED);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(f[c], d[c], 1e-4 * std::max(1.0, std::abs(d[c])));
  }
}

TEST(Shading, ViewPositionProjectsBackToThePixelCentre) {
  double tx = 0.7, ty = 0.4;
  dvec3 p = ts_view_position(10, 20, 7.0, tx, ty, 64, 48);
  EXPECT_DOUBLE_EQ(p.z, -7.0);
  double ndcx = p.x / (7.0 * tx), ndcy = p.y / (7.0 * ty);
  EXPECT_NEAR((ndcx + 1) * 0.5 * 64, 10.5, 1e-12);
  EXPECT_NEAR((1 - ndcy) * 0.5 * 48, 20.5, 1e-12);
}

// Projects sample points of the sphere that lie in front of the near plane and checks they stay
// inside the bounds (conservative) and that the bounds are not much larger (tight).
void checkSphereBounds(dvec3 c, double r, double znear, double tx, double ty) {
  dvec4 b = ts_sphere_ndc_bounds(c, r, znear, tx, ty);
  double lo[2] = {1e30, 1e30}, hi[2] = {-1e30, -1e30};
  int visible = 0;
  const int n = 400;
  for (int i = 0; i <= n; ++i) {
    double theta = ts::kPiDouble * i / n;
    for (int j = 0; j < 2 * n; ++j) {
      double phi = ts::kPiDouble * j / n;
      // Points on the surface and inside (the clipped solid's extremes can be on the near cap).
      for (double s : {1.0, 0.5}) {
        dvec3 p = c + s * r *
                          dvec3(std::sin(theta) * std::cos(phi), std::cos(theta),
                                std::sin(theta) * std::sin(phi));
        if (-p.z < znear) {
          // Points on the near plane inside the sphere's cross-section, approached from in front.
          continue;
        }
        ++visible;
        double nx = p.x / (-p.z * tx), ny = p.y / (-p.z * ty);
        lo[0] = std::min(lo[0], nx);
        hi[0] = std::max(hi[0], nx);
        lo[1] = std::min(lo[1], ny);
        hi[1] = std::max(hi[1], ny);
        ASSERT_GE(nx, b.x - 1e-9) << "sphere " << c.x << "," << c.y << "," << c.z << " r " << r;
        ASSERT_LE(nx, b.z + 1e-9);
        ASSERT_GE(ny, b.y - 1e-9);
        ASSERT_LE(ny, b.w + 1e-9);
      }
    }
  }
  if (visible == 0) return;
  // Tightness where the sphere is wholly in front and away from the eye: the bounds are within a
  // few percent of the sampled extent (the widely copied tile-frustum shortcut is ~2 tiles wide).
  if (-c.z - r > znear && glm::length(c) > 2 * r) {
    double width = hi[0] - lo[0];
    EXPECT_LT((b.z - b.x) - width, 0.02 * width + 1e-3);
    double height = hi[1] - lo[1];
    EXPECT_LT((b.w - b.y) - height, 0.02 * height + 1e-3);
  }
}

TEST(Culling, SphereBoundsAreConservativeAndTight) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 60; ++i) {
    const auto p = ts::test::drawnLastFirst<3>([&] { return u(rng); });
    dvec3 c(10 * p[0], 6 * p[1], -1 - 20 * std::abs(p[2]));
    checkSphereBounds(c, 0.2 + 4 * std::abs(u(rng)), 0.1, 0.9, 0.5);
  }
}

TEST(Culling, SpheresStraddlingOrBehindTheNearPlane) {
  const double znear = 0.5;
  checkSphereBounds(dvec3(3, 1, -0.6), 1.0, znear, 0.9, 0.5);   // straddles, off to the side
  checkSphereBounds(dvec3(0.5, 0, 0.5), 1.5, znear, 0.9, 0.5);  // centre behind the camera
  checkSphereBounds(dvec3(0, 0, -0.2), 5.0, znear, 0.9, 0.5);   // contains the camera
  checkSphereBounds(dvec3(4, -2, 1.0), 1.8, znear, 0.9, 0.5);   // mostly behind, pokes through
  // Wholly behind the near plane: empty.
  dvec4 b = ts_sphere_ndc_bounds(dvec3(0, 0, 2), 1.0, znear, 0.9, 0.5);
  EXPECT_GT(b.x, b.z);
  // Containing the camera: the whole screen.
  b = ts_sphere_ndc_bounds(dvec3(0, 0, -0.2), 5.0, znear, 0.9, 0.5);
  EXPECT_LE(b.x, -1.0);
  EXPECT_GE(b.z, 1.0);
}

TEST(Culling, TileRectangleCoversBoundsAndClampsToTheGrid) {
  int x0, y0, x1, y1;
  // NDC [-1,1] maps to the whole 100x50 screen in 16-pixel tiles: 7 x 4 tiles.
  ASSERT_TRUE(ts_ndc_bounds_to_tiles(dvec4(-5, -5, 5, 5), 100, 50, 16, 16, &x0, &y0, &x1, &y1));
  EXPECT_EQ(x0, 0);
  EXPECT_EQ(y0, 0);
  EXPECT_EQ(x1, 6);
  EXPECT_EQ(y1, 3);
  // A small box in the upper-left quadrant (NDC y up, rows down).
  ASSERT_TRUE(
      ts_ndc_bounds_to_tiles(dvec4(-0.9, 0.5, -0.5, 0.9), 100, 50, 16, 16, &x0, &y0, &x1, &y1));
  EXPECT_EQ(x0, 0);  // px 5
  EXPECT_EQ(x1, 1);  // px 25
  EXPECT_EQ(y0, 0);  // py 2.5
  EXPECT_EQ(y1, 0);  // py 12.5
  EXPECT_FALSE(ts_ndc_bounds_to_tiles(dvec4(1.5, 0, 2, 1), 100, 50, 16, 16, &x0, &y0, &x1, &y1));
}

TEST(Culling, DepthRangeTest) {
  EXPECT_TRUE(ts_sphere_meets_depth_range(dvec3(0, 0, -10), 1.0, 10.5, 20.0));
  EXPECT_FALSE(ts_sphere_meets_depth_range(dvec3(0, 0, -10), 1.0, 11.5, 20.0));
  EXPECT_FALSE(ts_sphere_meets_depth_range(dvec3(0, 0, -10), 1.0, 2.0, 8.9));
  EXPECT_FALSE(ts_sphere_meets_depth_range(dvec3(0, 0, -10), 100.0, 1e30, 0.0));  // empty tile
}

// The per-tile tests (frustum planes, frustum box) never reject a sphere that has a point inside
// the tile's frustum between its zmin and zmax; and they do reject some (else they are no test).
TEST(Culling, PerTileTestsAreConservative) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const int width = 320, height = 180, tile = 16;
  const double tx = 0.8, ty = 0.45;
  int rejected[3] = {0, 0, 0};
  for (int i = 0; i < 4000; ++i) {
    int px0 = tile * int(u(rng) * (width / tile)), py0 = tile * int(u(rng) * (height / tile));
    int px1 = std::min(px0 + tile, width), py1 = std::min(py0 + tile, height);
    const double zmin = 1 + 20 * u(rng);
    const double spread = 10 * u(rng);  // one draw per statement (random_draws.h)
    const double zmax = zmin + spread * u(rng);
    auto draw = [&] { return u(rng); };
    const auto p = ts::test::drawnLastFirst<3>(draw);
    dvec3 c((p[0] - 0.5) * 30, (p[1] - 0.5) * 16, -(p[2] * 35));
    double r = 0.2 + 3 * u(rng);
    bool inside = false;  // does a sampled point of the sphere lie in the tile's frustum piece?
    for (int k = 0; k < 3000 && !inside; ++k) {
      const auto q = ts::test::drawnLastFirst<3>(draw);
      dvec3 d(q[0] - 0.5, q[1] - 0.5, q[2] - 0.5);
      if (glm::length(d) > 0.5) continue;
      dvec3 p = c + 2.0 * r * d;
      double w = -p.z;
      if (w < zmin || w > zmax) continue;
      double px = (p.x / (w * tx) + 1) * 0.5 * width, py = (1 - p.y / (w * ty)) * 0.5 * height;
      inside = px >= px0 && px <= px1 && py >= py0 && py <= py1;
    }
    for (int mode : {TS_CULL_FRUSTUM, TS_CULL_AABB}) {
      int pass =
          ts_sphere_meets_tile(c, r, mode, px0, py0, px1, py1, width, height, tx, ty, zmin, zmax);
      if (inside) {
        ASSERT_TRUE(pass) << "mode " << mode << " rejected a sphere inside the tile";
      }
      if (!pass) ++rejected[mode];
    }
  }
  EXPECT_GT(rejected[TS_CULL_FRUSTUM], 100);
  EXPECT_GT(rejected[TS_CULL_AABB], 100);
}

}  // namespace
