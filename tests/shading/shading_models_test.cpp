// The metallic-roughness model, spot and directional lights of kernels/shading.h and the cone
// volumes of kernels/culling.h, compiled as C++: the textbook formulas, the hard cases (roughness
// and metallic at their ends, grazing light and view, lights on the surface), float against
// double within what fp32 rounding of the inputs explains, and the conservativeness of every
// cone bound.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>

#include "shading/shading_cpu.h"
#include "util/pi.h"
#include "random_draws.h"

namespace {

using glm::dvec3;
using glm::dvec4;
namespace sd = ts::shading_d;
namespace sf = ts::shading_f;

using ts::kPiDouble;

// A metallic-roughness surface and a light, as plain numbers (so both precisions see the same).
struct MrCase {
  dvec3 P, N, L;  // position, normal, light position (view space)
  dvec3 base{0.8, 0.5, 0.3};
  double metallic = 0.0, roughness = 0.5, range = 10.0;
  dvec3 color{2.0, 1.5, 1.0};
};

dvec3 shadeD(const MrCase& c) {
  dvec3 cDiff, kd, ks;
  double alpha;
  sd::ts_metallic_roughness_terms(c.base, c.metallic, c.roughness, &cDiff, &kd, &ks, &alpha);
  dvec3 V = glm::normalize(-c.P);
  sd::ts_shading_point p =
      sd::ts_make_shading_point(c.P, c.N, V, alpha, TS_SHADING_METALLIC_ROUGHNESS);
  return sd::ts_punctual_light(&p, kd, ks, dvec4(c.L, c.range), dvec4(c.color, 1.0),
                               dvec4(0, 0, 0, -1), TS_MODEL_WINDOWED, TS_SHADING_METALLIC_ROUGHNESS,
                               1, 1);
}

glm::dvec3 shadeF(const MrCase& c) {
  glm::vec3 cDiff, kd, ks;
  float alpha;
  sf::ts_metallic_roughness_terms(glm::vec3(c.base), float(c.metallic), float(c.roughness), &cDiff,
                                  &kd, &ks, &alpha);
  glm::vec3 P(c.P), N = glm::normalize(glm::vec3(c.N)), V = glm::normalize(-P);
  sf::ts_shading_point p = sf::ts_make_shading_point(P, N, V, alpha, TS_SHADING_METALLIC_ROUGHNESS);
  return dvec3(sf::ts_punctual_light(&p, kd, ks, glm::vec4(glm::vec3(c.L), float(c.range)),
                                     glm::vec4(glm::vec3(c.color), 1.0f), glm::vec4(0, 0, 0, -1),
                                     TS_MODEL_WINDOWED, TS_SHADING_METALLIC_ROUGHNESS, 1, 1));
}

// The same case with its float-rounded inputs, in double: what the float build sees.
MrCase rounded(MrCase c) {
  auto r3 = [](dvec3 v) { return dvec3(glm::vec3(v)); };
  c.P = r3(c.P);
  c.N = dvec3(glm::normalize(glm::vec3(c.N)));
  c.L = r3(c.L);
  c.base = r3(c.base);
  c.metallic = double(float(c.metallic));
  c.roughness = double(float(c.roughness));
  return c;
}

// How much the double result moves when one input component moves by `eps` of its size: the
// spread that fp32 rounding of the inputs alone explains (the function's conditioning there).
double inputSensitivity(const MrCase& c, double eps) {
  dvec3 f0 = shadeD(c);
  double worst = 0.0;
  auto probe = [&](MrCase m) {
    dvec3 f = shadeD(m);
    worst = std::max({worst, std::abs(f.x - f0.x), std::abs(f.y - f0.y), std::abs(f.z - f0.z)});
  };
  for (int k = 0; k < 3; ++k)
    for (double s : {-1.0, 1.0}) {
      MrCase m = c;
      m.P[k] += s * eps * std::max(std::abs(c.P[k]), glm::length(c.P));
      probe(m);
      m = c;
      m.N[k] += s * eps;
      m.N = glm::normalize(m.N);
      probe(m);
      m = c;
      m.L[k] += s * eps * std::max(std::abs(c.L[k]), glm::length(c.L));
      probe(m);
    }
  return worst;
}

// Float within what the float inputs and a few float roundings per operation explain.
void expectFloatWithinRounding(const MrCase& c, const std::string& what) {
  dvec3 d = shadeD(rounded(c)), f = shadeF(c);
  double sensitivity = inputSensitivity(rounded(c), 1.2e-7);
  double peak = std::max({std::abs(d.x), std::abs(d.y), std::abs(d.z)});
  for (int k = 0; k < 3; ++k) {
    ASSERT_TRUE(std::isfinite(f[k])) << what;
    EXPECT_LE(std::abs(f[k] - d[k]), 32.0 * sensitivity + 1e-5 * peak + 1e-30)
        << what << " channel " << k << ": float " << f[k] << " double " << d[k] << " sensitivity "
        << sensitivity;
  }
}

// The glTF specification's BRDF (Appendix B), written out directly: the reference for the
// shared function's rearranged form.
dvec3 textbookMr(const MrCase& c) {
  dvec3 V = glm::normalize(-c.P), N = glm::normalize(c.N);
  dvec3 v = c.L - c.P;
  double d = glm::length(v);
  dvec3 l = v / d;
  double q = (d / c.range) * (d / c.range);
  double window = std::pow(std::clamp(1.0 - q * q, 0.0, 1.0), 2.0);
  double falloff = window / std::max(d * d, TS_DMIN * TS_DMIN);
  double NL = std::max(glm::dot(N, l), 0.0);
  if (NL <= 0.0 || d >= c.range) return dvec3(0.0);
  double NV = std::clamp(glm::dot(N, V), 0.0, 1.0);
  dvec3 h = glm::normalize(l + V);
  double NH = glm::dot(N, h), VH = std::clamp(glm::dot(V, h), 0.0, 1.0);
  double r = std::clamp(c.roughness, TS_MIN_ROUGHNESS, 1.0), a = r * r, a2 = a * a;
  // chi+(N.H): no microfacet faces away from the normal.
  double D = NH > 0.0 ? a2 / (kPiDouble * std::pow(NH * NH * (a2 - 1.0) + 1.0, 2.0)) : 0.0;
  double Vis =
      1.0 / ((NL + std::sqrt(a2 + (1 - a2) * NL * NL)) * (NV + std::sqrt(a2 + (1 - a2) * NV * NV)));
  dvec3 f0 = glm::mix(dvec3(0.04), c.base, c.metallic);
  dvec3 F = f0 + (1.0 - f0) * std::pow(1.0 - VH, 5.0);
  dvec3 cDiff = c.base * (1.0 - c.metallic);
  dvec3 f = (1.0 - F) * cDiff / kPiDouble + F * D * Vis;
  return c.color * falloff * NL * kPiDouble * f;  // pi f: diffuse = c_diff, as Blinn-Phong's kd
}

MrCase randomCase(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  MrCase c;
  auto draw = [&] { return u(rng); };
  const auto p = ts::test::drawnLastFirst<3>(draw);
  c.P = dvec3(4 * p[0], 4 * p[1], -3 - 4 * std::abs(p[2]));
  const auto n = ts::test::drawnLastFirst<3>(draw);
  c.N = glm::normalize(dvec3(n[0], n[1], n[2]) + glm::normalize(-c.P));
  const auto l = ts::test::drawnLastFirst<3>(draw);
  c.L = c.P + 4.0 * dvec3(l[0], l[1], l[2]);
  const auto k = ts::test::drawnLastFirst<3>(draw);
  c.base = dvec3(0.5 + 0.5 * k[0], 0.5 + 0.5 * k[1], 0.5 + 0.5 * k[2]);
  c.metallic = 0.5 + 0.5 * u(rng);
  c.roughness = 0.3 + 0.35 * (1 + u(rng));
  return c;
}

TEST(MetallicRoughness, MatchesTheSpecificationsFormula) {
  std::mt19937 rng(21);
  int lit = 0;
  for (int i = 0; i < 2000; ++i) {
    MrCase c = randomCase(rng);
    dvec3 ours = shadeD(c), book = textbookMr(c);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(ours[k], book[k], 1e-10 * (1.0 + std::abs(book[k])));
    lit += book.x > 0.0;
  }
  EXPECT_GT(lit, 200);
}

TEST(MetallicRoughness, HardCasesStayFiniteAndWithinFloatRounding) {
  std::mt19937 rng(5);
  for (double roughness : {0.0, 1e-3, TS_MIN_ROUGHNESS, 0.2, 1.0}) {
    for (double metallic : {0.0, 1.0}) {
      const std::string what =
          "roughness " + std::to_string(roughness) + " metallic " + std::to_string(metallic);
      MrCase c;
      c.roughness = roughness;
      c.metallic = metallic;
      c.P = dvec3(0.3, -0.2, -5.0);
      c.N = glm::normalize(dvec3(0.0, 1.0, 0.2));
      dvec3 V = glm::normalize(-c.P);
      // The mirror direction (the GGX peak), grazing light, grazing view, light on the surface.
      dvec3 mirror = glm::reflect(-V, c.N);
      c.L = c.P + 2.0 * mirror;
      expectFloatWithinRounding(c, what + " mirror");
      dvec3 tangent = glm::normalize(glm::cross(c.N, dvec3(1, 0, 0)));
      for (double lift : {1e-6, 1e-3, 0.0, -1e-6}) {
        c.L = c.P + 2.0 * glm::normalize(tangent + lift * c.N);
        expectFloatWithinRounding(c, what + " grazing light " + std::to_string(lift));
      }
      MrCase g = c;  // grazing view: a normal perpendicular to V
      g.N = glm::normalize(glm::cross(V, dvec3(0, 1, 0)) + 1e-6 * V);
      g.L = g.P + 2.0 * glm::normalize(g.N + dvec3(0, 0.5, 0));
      expectFloatWithinRounding(g, what + " grazing view");
      c.L = c.P;  // on the surface point: nothing, no NaN
      EXPECT_EQ(shadeD(c), dvec3(0.0)) << what;
      EXPECT_EQ(shadeF(c), dvec3(0.0)) << what;
      c.L = c.P + 1e-7 * c.N;  // touching it: dmin keeps it finite
      dvec3 touch = shadeD(c);
      EXPECT_TRUE(std::isfinite(touch.x + touch.y + touch.z)) << what;
      expectFloatWithinRounding(c, what + " touching");
    }
  }
  for (int i = 0; i < 3000; ++i) {
    MrCase c = randomCase(rng);
    c.roughness = std::uniform_real_distribution<double>(0.0, 1.0)(rng);
    c.metallic = std::uniform_real_distribution<double>(0.0, 1.0)(rng) < 0.5 ? 0.0 : 1.0;
    expectFloatWithinRounding(c, "random " + std::to_string(i));
  }
}

// Every term carries N.l, so the light's contribution falls to 0 continuously as the light sinks
// into the surface's plane, for both models (the Blinn-Phong specular term used to switch off).
TEST(ShadingModels, ContinuousWhereTheLightCrossesTheSurfacePlane) {
  dvec3 P(0, 0, -5), N(0, 1, 0), V = glm::normalize(-P);
  for (int shading : {TS_SHADING_BLINN_PHONG, TS_SHADING_METALLIC_ROUGHNESS}) {
    double gloss = shading == TS_SHADING_BLINN_PHONG ? 64.0 : 0.05;
    sd::ts_shading_point p = sd::ts_make_shading_point(P, N, V, gloss, shading);
    double previous = -1.0;
    for (double lift : {1e-1, 1e-2, 1e-3, 1e-4, 1e-6, 1e-9, 0.0}) {
      dvec3 L = P + dvec3(0, lift, 2.0);  // towards the camera, almost in the plane
      dvec3 c = sd::ts_punctual_light(&p, dvec3(0.5), dvec3(0.9), dvec4(L, 10.0), dvec4(1.0),
                                      dvec4(0, 0, 0, -1), TS_MODEL_WINDOWED, shading, 1, 0);
      if (previous >= 0.0) {
        EXPECT_LE(c.x, previous * 1.0001 + 1e-300) << shading << " " << lift;
      }
      EXPECT_LE(c.x, 10.0 * lift + 1e-300) << shading << " lift " << lift;
      previous = c.x;
    }
    EXPECT_EQ(previous, 0.0);
  }
}

// glTF's spot falloff: 1 inside the inner cone, 0 outside the outer one, the squared linear ramp
// of the cosine in between; a point light's entry gives exactly 1.
TEST(SpotLights, AngularFalloffIsTheExtensions) {
  dvec3 P(0, 0, -5), N(0, 0, 1), V = glm::normalize(-P);
  sd::ts_shading_point p = sd::ts_make_shading_point(P, N, V, 1.0, TS_SHADING_BLINN_PHONG);
  const double inner = 0.2, outer = 0.5, cosIn = std::cos(inner), cosOut = std::cos(outer);
  const double scale = 1.0 / (cosIn - cosOut);
  dvec3 axis(0, 0, -1);  // pointing away from the camera, down the view axis
  auto at = [&](double angle) {
    dvec3 dir(std::sin(angle), 0, -std::cos(angle));
    dvec3 L = P - 2.0 * dir;  // the surface point lies `angle` off the axis, 2 away
    return sd::ts_punctual_light(&p, dvec3(1.0), dvec3(0.0), dvec4(L, 10.0),
                                 dvec4(1.0, 1.0, 1.0, scale), dvec4(axis, cosOut),
                                 TS_MODEL_PHYSICAL, TS_SHADING_BLINN_PHONG, 0, 1)
        .x;
  };
  auto point = [&](double angle) {
    dvec3 dir(std::sin(angle), 0, -std::cos(angle));
    return sd::ts_punctual_light(&p, dvec3(1.0), dvec3(0.0), dvec4(P - 2.0 * dir, 10.0), dvec4(1.0),
                                 dvec4(0, 0, 0, -1), TS_MODEL_PHYSICAL, TS_SHADING_BLINN_PHONG, 0,
                                 1)
        .x;
  };
  EXPECT_DOUBLE_EQ(at(0.0), point(0.0));
  EXPECT_DOUBLE_EQ(at(0.15), point(0.15));
  EXPECT_EQ(at(0.55), 0.0);
  double mid = 0.35, t = (std::cos(mid) - cosOut) * scale;
  EXPECT_NEAR(at(mid), point(mid) * t * t, 1e-12);
}

TEST(DirectionalLights, LambertAndSpecularWithoutFalloff) {
  dvec3 P(1, 2, -5), N = glm::normalize(dvec3(0, 1, 1)), V = glm::normalize(-P);
  sd::ts_shading_point p = sd::ts_make_shading_point(P, N, V, 16.0, TS_SHADING_BLINN_PHONG);
  dvec3 toLight = glm::normalize(dvec3(0.2, 1, 0.3));
  dvec3 c = sd::ts_directional_light(&p, dvec3(0.5), dvec3(0.0), toLight, dvec3(2.0),
                                     TS_SHADING_BLINN_PHONG, 1);
  EXPECT_NEAR(c.x, 2.0 * 0.5 * glm::dot(N, toLight), 1e-14);
  // From below the surface: nothing.
  EXPECT_EQ(sd::ts_directional_light(&p, dvec3(0.5), dvec3(1.0), -toLight, dvec3(2.0),
                                     TS_SHADING_BLINN_PHONG, 1),
            dvec3(0.0));
}

// ---- cone volumes ------------------------------------------------------------------------------

struct Cone {
  dvec3 apex, axis;
  double range, outer;
  dvec4 posRange() const { return dvec4(apex, range); }
  dvec4 spot() const { return dvec4(axis, std::cos(outer)); }
};

// A point of the sector (inside the range ball and the cone), uniform enough for bounds tests.
dvec3 samplePoint(const Cone& c, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  dvec3 t = glm::normalize(
      glm::cross(c.axis, std::abs(c.axis.x) < 0.9 ? dvec3(1, 0, 0) : dvec3(0, 1, 0)));
  dvec3 b = glm::cross(c.axis, t);
  double theta = c.outer * std::sqrt(u(rng)), phi = 2 * kPiDouble * u(rng);
  if (u(rng) < 0.3) theta = c.outer;  // the cone's surface
  double r = c.range * (u(rng) < 0.3 ? 1.0 : std::cbrt(u(rng)));
  dvec3 dir = std::cos(theta) * c.axis + std::sin(theta) * (std::cos(phi) * t + std::sin(phi) * b);
  return c.apex + r * dir;
}

Cone randomCone(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Cone c;
  auto draw = [&] { return u(rng); };
  const auto p = ts::test::drawnLastFirst<3>(draw);
  c.apex = dvec3(6 * p[0], 4 * p[1], -8 * std::abs(p[2]) + 1.0);
  const auto a = ts::test::drawnLastFirst<3>(draw);
  c.axis = glm::normalize(dvec3(a[0], a[1], a[2]));
  c.range = 0.5 + 5 * std::abs(u(rng));
  c.outer = (1.0 + 89.0 * std::abs(u(rng))) * kPiDouble / 180.0;
  return c;
}

TEST(ConeVolumes, BoundsHoldEveryPointOfTheSector) {
  std::mt19937 rng(17);
  const double znear = 0.2, tx = 0.9, ty = 0.5;
  for (int i = 0; i < 400; ++i) {
    Cone c = randomCone(rng);
    sd::ts_light_volume v = sd::ts_make_light_volume(c.posRange(), c.spot(), TS_SPOT_CULL_CONE);
    sd::ts_light_volume s =
        sd::ts_make_light_volume(c.posRange(), c.spot(), TS_SPOT_CULL_BOUND_SPHERE);
    dvec4 b = sd::ts_light_ndc_bounds(&v, znear, tx, ty);
    // The tight sphere is no larger than the range sphere.
    EXPECT_LE(v.radius, c.range * (1 + 2e-5));
    for (int k = 0; k < 300; ++k) {
      dvec3 p = samplePoint(c, rng);
      ASSERT_LE(glm::length(p - v.center), v.radius * (1 + 1e-12)) << "cone " << i;
      ASSERT_LE(glm::length(p - s.center), s.radius * (1 + 1e-12)) << "cone " << i;
      for (int a = 0; a < 3; ++a) {
        ASSERT_GE(p[a], v.lo[a] - 1e-12) << "cone " << i << " axis " << a;
        ASSERT_LE(p[a], v.hi[a] + 1e-12) << "cone " << i << " axis " << a;
      }
      double w = -p.z;
      if (w < znear) continue;
      double nx = p.x / (w * tx), ny = p.y / (w * ty);
      ASSERT_GE(nx, b.x - 1e-9) << "cone " << i;
      ASSERT_LE(nx, b.z + 1e-9) << "cone " << i;
      ASSERT_GE(ny, b.y - 1e-9) << "cone " << i;
      ASSERT_LE(ny, b.w + 1e-9) << "cone " << i;
      ASSERT_TRUE(sd::ts_light_meets_depth_range(&v, w - 1e-9, w + 1e-9)) << "cone " << i;
    }
  }
}

// The per-tile cone test (and each culling mode on top of it) never rejects a tile that a point
// of the sector falls into within the tile's depth range; and it does reject tiles.
TEST(ConeVolumes, PerTileTestsAreConservative) {
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const int width = 320, height = 180, tile = 16;
  const double tx = 0.8, ty = 0.45;
  int rejected = 0, tested = 0;
  for (int i = 0; i < 300; ++i) {
    Cone c = randomCone(rng);
    c.apex.z -= 4.0;
    for (int mode : {TS_CULL_RECT, TS_CULL_FRUSTUM, TS_CULL_AABB}) {
      sd::ts_light_volume v = sd::ts_make_light_volume(c.posRange(), c.spot(), TS_SPOT_CULL_CONE);
      for (int t = 0; t < 20; ++t) {
        int px0 = tile * int(u(rng) * (width / tile)), py0 = tile * int(u(rng) * (height / tile));
        int px1 = std::min(px0 + tile, width), py1 = std::min(py0 + tile, height);
        const double zmin = 0.5 + 12 * u(rng);
        const double spread = 6 * u(rng);  // one draw per statement (random_draws.h)
        const double zmax = zmin + spread * u(rng);
        bool inside = false;
        for (int k = 0; k < 1500 && !inside; ++k) {
          dvec3 p = samplePoint(c, rng);
          double w = -p.z;
          if (w < zmin || w > zmax) continue;
          double px = (p.x / (w * tx) + 1) * 0.5 * width, py = (1 - p.y / (w * ty)) * 0.5 * height;
          inside = px >= px0 && px <= px1 && py >= py0 && py <= py1;
        }
        int pass = sd::ts_light_meets_tile(&v, mode, px0, py0, px1, py1, width, height, tx, ty,
                                           zmin, zmax);
        if (inside) {
          ASSERT_TRUE(pass) << "cone " << i << " mode " << mode;
        }
        ++tested;
        rejected += !pass;
      }
    }
  }
  EXPECT_GT(rejected, tested / 10);
}

// A spot whose outer cone reaches 90 degrees or more is a half-space or more: its range sphere.
TEST(ConeVolumes, WideConesAndPointLightsAreTheirSpheres) {
  dvec4 pr(1, 2, -6, 3);
  for (dvec4 spot : {dvec4(0, 0, 0, -1), dvec4(0, 0, -1, 0.0), dvec4(1, 0, 0, -0.5)}) {
    sd::ts_light_volume v = sd::ts_make_light_volume(pr, spot, TS_SPOT_CULL_CONE);
    EXPECT_FALSE(v.cone);
    EXPECT_EQ(v.center, dvec3(pr));
    EXPECT_EQ(v.radius, pr.w);
  }
}

}  // namespace
