// Exact visibility (src/visibility/exact_visibility.*) against hand-made cases with analytic
// answers: a box floating over a floor, a wall, lights above, and the same far from the origin.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "scene/mesh_builder.h"
#include "test_scenes.h"
#include "util/error.h"
#include "visibility/exact_visibility.h"

namespace {

using ts::ExactVisibility;
using ts::Scene;
using ts::SceneLight;
using ts::SurfacePoints;

constexpr float kFloor = 10.0f;   // the floor spans [-kFloor, kFloor] in x and z, at y = 0
constexpr double kMargin = 0.05;  // points this close to an analytic outline are not asserted

// The floor, a box [-1, 1] x [1, 2] x [-1, 1] floating over it (all six faces) and, at x = 5, a
// wall facing -x; everything moved by `offset` (a scene far from the origin).
Scene floorBoxWall(glm::vec3 offset = glm::vec3(0.0f)) {
  Scene s;
  ts::MeshBuilder b(s);
  const uint32_t m = b.addMaterial(ts::Material{});
  ts::test::addFloor(b, kFloor, m, offset);
  b.box(offset + glm::vec3(-1.0f, 1.0f, -1.0f), offset + glm::vec3(1.0f, 2.0f, 1.0f), m, true);
  b.quad(offset + glm::vec3(5.0f, 0.0f, kFloor), offset + glm::vec3(5.0f, 0.0f, -kFloor),
         offset + glm::vec3(5.0f, 10.0f, -kFloor), offset + glm::vec3(5.0f, 10.0f, kFloor), m);
  return s;
}

// Floor points (normal +y) on a grid over x, z in [-4.5, 4.5] (left of the wall), stored as floats
// as a G-buffer's would be, moved by `offset`.
SurfacePoints floorGrid(glm::dvec3 offset = glm::dvec3(0.0), int n = 91) {
  SurfacePoints p;
  p.width = n;
  p.height = n;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const glm::dvec3 q(-4.5 + 9.0 * i / (n - 1), 0.0, -4.5 + 9.0 * j / (n - 1));
      p.position.push_back(glm::dvec3(glm::vec3(q + offset)));
      p.normal.push_back({0.0f, 1.0f, 0.0f});
      p.geometry.push_back(1);
    }
  return p;
}

// Floor points inside the square |x|, |z| < h (less the margin) must be occluded, those outside
// it (beyond the margin) lit. Returns how many were asserted either way.
void expectSquareShadow(const SurfacePoints& p, const std::vector<uint8_t>& v, glm::dvec3 offset,
                        glm::dvec2 lo, glm::dvec2 hi, int& inside, int& outside) {
  ASSERT_EQ(v.size(), p.size());
  for (size_t i = 0; i < p.size(); ++i) {
    const glm::dvec3 q = p.position[i] - offset;
    const bool in = q.x > lo.x + kMargin && q.x < hi.x - kMargin && q.z > lo.y + kMargin &&
                    q.z < hi.y - kMargin;
    const bool out = q.x < lo.x - kMargin || q.x > hi.x + kMargin || q.z < lo.y - kMargin ||
                     q.z > hi.y + kMargin;
    if (in) {
      EXPECT_EQ(v[i], ts::kVisibilityOccluded) << "at " << q.x << ", " << q.z;
      ++inside;
    } else if (out) {
      EXPECT_EQ(v[i], ts::kVisibilityLit) << "at " << q.x << ", " << q.z;
      ++outside;
    }
  }
}

TEST(ExactVisibility, PointLightAboveTheBoxCastsItsProjectedOutline) {
  for (const glm::dvec3 offset : {glm::dvec3(0.0), glm::dvec3(1e4, 0.0, 0.0)}) {
    const ExactVisibility ev(floorBoxWall(glm::vec3(offset)));
    const SurfacePoints p = floorGrid(offset);
    // From (0, 4, 0) the box's top face (y = 2) projects onto the floor scaled by 4 / 2, its
    // bottom (y = 1) by 4 / 3: the shadow is the top's projection, |x|, |z| < 2.
    const SceneLight light = SceneLight::point(offset + glm::dvec3(0.0, 4.0, 0.0), {1, 1, 1}, 100);
    int inside = 0, outside = 0;
    expectSquareShadow(p, ev.visibility(p, light), offset, {-2, -2}, {2, 2}, inside, outside);
    EXPECT_GT(inside, 100) << "offset " << offset.x;
    EXPECT_GT(outside, 1000) << "offset " << offset.x;
  }
}

TEST(ExactVisibility, DirectionalLightCastsTheOrthographicProjection) {
  for (const glm::dvec3 offset : {glm::dvec3(0.0), glm::dvec3(1e4, 0.0, 0.0)}) {
    const ExactVisibility ev(floorBoxWall(glm::vec3(offset)));
    const SurfacePoints p = floorGrid(offset);
    int inside = 0, outside = 0;
    // Straight down: the box's footprint.
    const SceneLight down = SceneLight::directional({0.0f, -1.0f, 0.0f}, {1, 1, 1});
    expectSquareShadow(p, ev.visibility(p, down), offset, {-1, -1}, {1, 1}, inside, outside);
    // Travelling along (1, -1, 0): (x, y, z) lands at (x + y, 0, z), so x in [0, 3].
    const SceneLight slanted =
        SceneLight::directional(glm::normalize(glm::vec3(1.0f, -1.0f, 0.0f)), {1, 1, 1});
    expectSquareShadow(p, ev.visibility(p, slanted), offset, {0, -1}, {3, 1}, inside, outside);
    EXPECT_GT(inside, 100);
    EXPECT_GT(outside, 1000);
  }
}

// alphaMode MASK: a leaf at y = 1.5 over [-2, 2] in x and z whose texture is cut out where x < 0
// (test_scenes.h) lets a sun straight down through that half only; opaque, it blocks both.
TEST(ExactVisibility, AnAlphaMaskedLeafShadowsUnderItsCoveredHalfOnly) {
  for (const ts::AlphaMode mode : {ts::AlphaMode::Mask, ts::AlphaMode::Opaque}) {
    Scene s;
    ts::MeshBuilder b(s);
    ts::test::addFloor(b, kFloor, b.addMaterial(ts::Material{}));
    ts::Material leaf;
    leaf.alphaMode = mode;
    leaf.diffuseTexture = leaf.baseColorTexture = 0;
    s.textures.push_back(ts::test::halfCutOutTexture());
    const uint32_t m = b.addMaterial(leaf);
    b.quad({-2.0f, 1.5f, 2.0f}, {2.0f, 1.5f, 2.0f}, {2.0f, 1.5f, -2.0f}, {-2.0f, 1.5f, -2.0f}, m);
    const ExactVisibility ev(s);  // s may go: the filter keeps what it samples
    s = Scene{};
    const SurfacePoints p = floorGrid();
    const std::vector<uint8_t> v =
        ev.visibility(p, SceneLight::directional({0.0f, -1.0f, 0.0f}, {1, 1, 1}));
    int inside = 0, outside = 0;
    if (mode == ts::AlphaMode::Mask)
      expectSquareShadow(p, v, glm::dvec3(0.0), {0, -2}, {2, 2}, inside, outside);
    else expectSquareShadow(p, v, glm::dvec3(0.0), {-2, -2}, {2, 2}, inside, outside);
    EXPECT_GT(inside, 100);
    EXPECT_GT(outside, 1000);
  }
}

TEST(ExactVisibility, AWallHidesTheFarSide) {
  const ExactVisibility ev(floorBoxWall());
  SurfacePoints p;
  p.width = 2;
  p.height = 1;
  p.position = {{3.0, 0.0, 4.0}, {9.0, 0.0, 4.0}};  // behind the wall from the light, beside it
  p.normal = {{0, 1, 0}, {0, 1, 0}};
  p.geometry = {1, 1};
  const SceneLight light = SceneLight::point({8.0, 1.0, 4.0}, {1, 1, 1}, 100);
  const std::vector<uint8_t> v = ev.visibility(p, light);
  EXPECT_EQ(v[0], ts::kVisibilityOccluded);
  EXPECT_EQ(v[1], ts::kVisibilityLit);
}

TEST(ExactVisibility, RaysThroughSharedEdgesDoNotLeak) {
  // Straight down through the diagonals of the box's top and bottom faces (two triangles each)
  // and along its edges: watertight (RTC_SCENE_FLAG_ROBUST), so no ray slips between triangles.
  const ExactVisibility ev(floorBoxWall());
  SurfacePoints p;
  for (int k = 0; k <= 40; ++k) {
    const double t = -0.95 + 1.9 * k / 40.0;
    for (const glm::dvec3 q : {glm::dvec3(t, 0.0, t), glm::dvec3(t, 0.0, -t)}) {
      p.position.push_back(q);
      p.normal.push_back({0, 1, 0});
      p.geometry.push_back(1);
    }
  }
  p.width = int(p.size());
  p.height = 1;
  const SceneLight down = SceneLight::directional({0.0f, -1.0f, 0.0f}, {1, 1, 1});
  for (uint8_t v : ev.visibility(p, down)) EXPECT_EQ(v, ts::kVisibilityOccluded);
}

TEST(ExactVisibility, GrazingAnEdgeIsDeterministic) {
  // From (0, 4, 0) to (2, 0, z) the segment touches the box's top edge at (1, 2, z/2): either
  // answer is right, but the same one every time and for any thread count.
  const ExactVisibility ev(floorBoxWall());
  SurfacePoints p;
  for (int k = 0; k <= 20; ++k) {
    p.position.push_back({2.0, 0.0, -1.5 + 3.0 * k / 20.0});
    p.normal.push_back({0, 1, 0});
    p.geometry.push_back(1);
  }
  p.width = 1;
  p.height = int(p.size());
  const SceneLight light = SceneLight::point({0.0, 4.0, 0.0}, {1, 1, 1}, 100);
  const std::vector<uint8_t> first = ev.visibility(p, light, 1);
  for (uint8_t v : first) EXPECT_NE(v, ts::kVisibilityNotApplicable);
  for (int run = 0; run < 5; ++run) EXPECT_EQ(ev.visibility(p, light, 1 + run % 2), first);
}

TEST(ExactVisibility, TheSameForOneAndTwoThreads) {
  const ExactVisibility ev(floorBoxWall());
  const SurfacePoints p = floorGrid();
  for (const SceneLight& light :
       {SceneLight::point({0.5, 3.0, -0.3}, {1, 1, 1}, 100),
        SceneLight::directional(glm::normalize(glm::vec3(0.3f, -1.0f, 0.2f)), {1, 1, 1})}) {
    const std::vector<uint8_t> one = ev.visibility(p, light, 1);
    EXPECT_EQ(ev.visibility(p, light, 2), one);
    EXPECT_EQ(ev.visibility(p, light, 7), one);
    EXPECT_TRUE(std::count(one.begin(), one.end(), ts::kVisibilityOccluded) > 0);
    EXPECT_TRUE(std::count(one.begin(), one.end(), ts::kVisibilityLit) > 0);
  }
}

TEST(ExactVisibility, BackgroundRangeAndConeAreNotApplicable) {
  const ExactVisibility ev(floorBoxWall());
  SurfacePoints p;
  p.width = 4;
  p.height = 1;
  p.position = {{0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}, {2.5, 0.0, 0.0}, {0.5, 0.0, 0.0}};
  p.normal = {{0, 0, 0}, {0, 1, 0}, {0, 1, 0}, {0, 1, 0}};
  p.geometry = {0, 1, 1, 1};
  // Range 4.5: (2.5, 0, 0) is 4.7 from the light, (0, 0, 0) and (0.5, 0, 0) within.
  const std::vector<uint8_t> point =
      ev.visibility(p, SceneLight::point({0, 4, 0}, {1, 1, 1}, 4.5f));
  EXPECT_EQ(point, (std::vector<uint8_t>{2, 0, 2, 0}));
  // A spot down with a 0.1 rad cone: (0.5, 0, 0) lies 0.124 rad off its axis.
  const SceneLight spot = SceneLight::spot({0, 4, 0}, {0, -1, 0}, {1, 1, 1}, 100, 0.0f, 0.1f);
  EXPECT_EQ(ev.visibility(p, spot), (std::vector<uint8_t>{2, 0, 2, 2}));
  // A directional light reaches everything but the background.
  EXPECT_EQ(ev.visibility(p, SceneLight::directional({0, -1, 0}, {1, 1, 1})),
            (std::vector<uint8_t>{2, 0, 1, 0}));
}

TEST(ExactVisibility, LitSurfacesAreNotSelfOccludedFarFromTheOrigin) {
  // Points on the box's top face and the floor, stored as floats and moved a few float ulps
  // behind their surfaces (what fp32 G-buffer planes do), at the origin and at x = 1e4.
  for (const double x0 : {0.0, 1e4}) {
    const glm::dvec3 offset(x0, 0.0, 0.0);
    const ExactVisibility ev(floorBoxWall(glm::vec3(offset)));
    SurfacePoints p;
    for (int k = 0; k < 50; ++k) {
      const double t = -0.9 + 1.8 * k / 49.0;
      const double ulp = std::ldexp(1.0, std::ilogb(std::max(1.0, x0 + 4.0)) - 23);
      for (const glm::dvec3 q : {glm::dvec3(t, 2.0, -t), glm::dvec3(t + 3.0, 0.0, t * 4.0)}) {
        p.position.push_back(glm::dvec3(glm::vec3(offset + q)) - glm::dvec3(0.0, 4.0 * ulp, 0.0));
        p.normal.push_back({0, 1, 0});
        p.geometry.push_back(1);
      }
    }
    p.width = int(p.size());
    p.height = 1;
    for (const SceneLight& light :
         {SceneLight::point(offset + glm::dvec3(0, 30, 0), {1, 1, 1}, 100),
          SceneLight::directional({0, -1, 0}, {1, 1, 1})})
      for (uint8_t v : ev.visibility(p, light)) EXPECT_EQ(v, ts::kVisibilityLit) << "x0 " << x0;
  }
}

TEST(ExactVisibility, SurfacePointsFromAGBuffer) {
  // A camera at (0, 0, 5) looking down -z: a pixel's world point is its view point + (0, 0, 5).
  ts::GBuffer g;
  g.resize(2, 2);
  g.depth = {0.0f, 5.0f, 5.0f, 2.0f};
  for (auto& n : g.normal) n = {0.0f, 0.0f, 1.0f, 0.0f};
  const ts::SceneCamera camera =
      ts::SceneCamera::lookAt({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 1.0f, 0.1f, 100.0f);
  const SurfacePoints p = ts::surfacePoints(g, camera);
  EXPECT_EQ(p.geometry, (std::vector<uint8_t>{0, 1, 1, 1}));
  const double t = std::tan(0.5);  // tan(yfov / 2), the aspect 1 (the camera keeps it as float)
  EXPECT_NEAR(p.position[1].x, 0.5 * t * 5.0, 1e-6);
  EXPECT_NEAR(p.position[1].y, 0.5 * t * 5.0, 1e-6);
  EXPECT_NEAR(p.position[1].z, 0.0, 1e-9);
  EXPECT_NEAR(p.position[3].z, 3.0, 1e-9);
  EXPECT_NEAR(p.normal[3].z, 1.0, 1e-6);
}

TEST(ExactVisibility, NoTrianglesIsAnError) { EXPECT_THROW(ExactVisibility{Scene{}}, ts::Error); }

}  // namespace
