// The shadow maps drawn (src/raster/shadow_maps.cpp, rasterizeDepth): a floor at y = 0 with a box
// on it, seen from lights above. Every texel is checked against a ray cast from the face's eye
// through the texel's centre: the map holds the hit's linear depth along the face's axis within
// kTolerance of it (relative), except on silhouettes (texels whose ray, moved by 1/50 texel,
// hits something else: the rasterizer snaps to 1/256 pixel).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include "test_scenes.h"
#include "raster/shadow_maps.h"
#include "scene/mesh_builder.h"
#include "scene/view_space_lights.h"
#include "util/error.h"

namespace {

using ts::Scene;
using ts::SceneLight;
using ts::ShadowAtlas;
using ts::ShadowFace;

constexpr double kTolerance = 1e-5;  // relative: float storage and the double ray-plane solve
constexpr float kFloor = 10.0f;      // the floor spans [-kFloor, kFloor] in x and z
const glm::vec3 kBoxLo(-1.0f, 0.0f, -1.0f), kBoxHi(1.0f, 1.0f, 1.0f);

Scene floorAndBox() {
  Scene s;
  s.name = "floor-and-box";
  ts::MeshBuilder b(s);
  const uint32_t m = b.addMaterial(ts::Material{});
  ts::test::addFloor(b, kFloor, m);
  b.box(kBoxLo, kBoxHi, m, false);
  s.cameraPath.push_back(ts::SceneCamera::lookAt({0.0, 3.0, 12.0}, {0.0, 0.0, 0.0}, {0.0, 1.0, 0.0},
                                                 1.0f, 0.1f, 100.0f));
  return s;
}

enum class Hit { None, Floor, Box };

// The nearest hit of the ray o + t d (t > 0) with the floor and the box.
Hit cast(const glm::dvec3& o, const glm::dvec3& d, double& t) {
  t = std::numeric_limits<double>::infinity();
  Hit hit = Hit::None;
  if (d.y < 0.0) {
    const double tf = -o.y / d.y;
    const glm::dvec3 p = o + tf * d;
    if (tf > 0.0 && std::abs(p.x) <= kFloor && std::abs(p.z) <= kFloor) {
      t = tf;
      hit = Hit::Floor;
    }
  }
  double t0 = -std::numeric_limits<double>::infinity(), t1 = -t0;
  for (int k = 0; k < 3; ++k) {
    if (d[k] == 0.0) {
      if (o[k] < kBoxLo[k] || o[k] > kBoxHi[k]) return hit;
      continue;
    }
    double a = (kBoxLo[k] - o[k]) / d[k], b = (kBoxHi[k] - o[k]) / d[k];
    if (a > b) std::swap(a, b);
    t0 = std::max(t0, a);
    t1 = std::min(t1, b);
  }
  if (t0 <= t1 && t0 > 0.0 && t0 < t) {
    t = t0;
    hit = Hit::Box;
  }
  return hit;
}

// The ray through face texel (u, v) in [0, size)^2 as fractions: origin and direction with a view
// z of -1 (so t is the linear depth).
void texelRay(const ShadowFace& f, double u, double v, glm::dvec3& o, glm::dvec3& d) {
  const double nx = 2.0 * u / f.size - 1.0, ny = 1.0 - 2.0 * v / f.size;
  const glm::dmat4 worldFromView = glm::inverse(f.view.viewFromWorld);
  if (f.view.orthographic) {
    o = glm::dvec3(worldFromView * glm::dvec4(nx * f.view.halfX, ny * f.view.halfY, 0.0, 1.0));
    d = glm::dvec3(worldFromView * glm::dvec4(0.0, 0.0, -1.0, 0.0));
  } else {
    o = glm::dvec3(worldFromView * glm::dvec4(0.0, 0.0, 0.0, 1.0));
    d = glm::dvec3(worldFromView * glm::dvec4(nx * f.view.halfX, ny * f.view.halfY, -1.0, 0.0));
  }
}

struct FaceCheck {
  size_t floor = 0, box = 0, empty = 0, silhouette = 0, wrong = 0;
  size_t boxNearer = 0;  // box texels nearer than the floor's plane along the same ray
  double floorDepth = 0.0, boxDepth = 0.0;  // the last seen
};

FaceCheck checkFace(const ShadowAtlas& atlas, const ShadowFace& f) {
  FaceCheck c;
  for (int y = 0; y < f.size; ++y)
    for (int x = 0; x < f.size; ++x) {
      glm::dvec3 o, d;
      double t = 0.0, ts = 0.0;
      texelRay(f, x + 0.5, y + 0.5, o, d);
      const Hit hit = cast(o, d, t);
      bool edge = false;
      for (int k = 0; k < 4 && !edge; ++k) {
        glm::dvec3 oe, de;
        texelRay(f,
                 x + 0.5 +
                     (k == 0   ? 0.02
                      : k == 1 ? -0.02
                               : 0.0),
                 y + 0.5 +
                     (k == 2   ? 0.02
                      : k == 3 ? -0.02
                               : 0.0),
                 oe, de);
        edge = cast(oe, de, ts) != hit;
      }
      if (hit != Hit::None && (t < f.view.znear || t > f.view.zfar)) edge = true;
      if (edge) {
        ++c.silhouette;
        continue;
      }
      const float stored = atlas.at(f.x + x, f.y + y);
      const double expected = hit == Hit::None ? f.view.zfar : t;
      if (!(std::abs(stored - expected) <= kTolerance * expected)) {
        if (c.wrong < 5)
          ADD_FAILURE() << "face " << f.face << " texel " << x << "," << y << ": " << stored
                        << ", expected " << expected;
        ++c.wrong;
      }
      if (hit == Hit::Floor) {
        ++c.floor;
        c.floorDepth = stored;
      } else if (hit == Hit::Box) {
        ++c.box;
        c.boxDepth = stored;
        if (d.y < 0.0 && stored < -o.y / d.y) ++c.boxNearer;
      } else {
        ++c.empty;
      }
    }
  return c;
}

ShadowAtlas drawFor(const Scene& scene, std::vector<SceneLight> lights, int threads = 2,
                    int mapSize = 128) {
  for (SceneLight& l : lights) l.castsShadow = true;
  ts::ShadowAtlasOptions o;
  o.mapSize = mapSize;
  const ts::ShadowAtlasLayout layout = planShadowAtlas(lights, scene.bounds(), scene.camera(0), o);
  return drawShadowAtlas(scene, layout, threads);
}

ShadowAtlas drawFor(const Scene& scene, const SceneLight& light) {
  return drawFor(scene, std::vector<SceneLight>{light});
}

TEST(ShadowMaps, PointLightCubeFacesHoldAnalyticDepths) {
  const Scene scene = floorAndBox();
  const ShadowAtlas atlas = drawFor(scene, SceneLight::point({0.0, 4.0, 0.0}, glm::vec3(1), 20));
  ASSERT_EQ(atlas.layout.faces.size(), 6u);
  for (const ShadowFace& f : atlas.layout.faces) {
    const FaceCheck c = checkFace(atlas, f);
    EXPECT_EQ(c.wrong, 0u) << "face " << f.face;
    if (f.face == 3) {  // -Y: the floor at depth 4, the box's top at 3
      EXPECT_GT(c.floor, 0u);
      EXPECT_GT(c.box, 0u);
      EXPECT_NEAR(c.floorDepth, 4.0, 4.0 * kTolerance);
      EXPECT_NEAR(c.boxDepth, 3.0, 3.0 * kTolerance);
      EXPECT_EQ(c.boxNearer, c.box);
      EXPECT_EQ(c.empty, 0u);
    }
    if (f.face == 2) {  // +Y: nothing above the light, nothing drawn: all at the far value
      EXPECT_EQ(c.empty, size_t(f.size) * size_t(f.size));
      EXPECT_EQ(atlas.faceTriangles[2], 0u);
    }
  }
  // The side faces see the floor's far part below their horizon.
  EXPECT_GT(checkFace(atlas, atlas.layout.faces[0]).floor, 0u);
}

TEST(ShadowMaps, SpotLightLookingDownHoldsTheSameDepths) {
  const Scene scene = floorAndBox();
  const ShadowAtlas atlas = drawFor(
      scene, SceneLight::spot({0.0, 4.0, 0.0}, {0.0f, -1.0f, 0.0f}, glm::vec3(1), 20, 0.3f, 0.6f));
  ASSERT_EQ(atlas.layout.faces.size(), 1u);
  const FaceCheck c = checkFace(atlas, atlas.layout.faces[0]);
  EXPECT_EQ(c.wrong, 0u);
  EXPECT_GT(c.floor, 0u);
  EXPECT_GT(c.box, 0u);
  EXPECT_NEAR(c.floorDepth, 4.0, 4.0 * kTolerance);
  EXPECT_NEAR(c.boxDepth, 3.0, 3.0 * kTolerance);
}

TEST(ShadowMaps, DirectionalMapCoversTheScene) {
  const Scene scene = floorAndBox();
  for (glm::vec3 dir :
       {glm::vec3(0.0f, -1.0f, 0.0f), glm::normalize(glm::vec3(0.4f, -1.0f, 0.3f))}) {
    const ShadowAtlas atlas = drawFor(scene, SceneLight::directional(dir, glm::vec3(1)));
    ASSERT_EQ(atlas.layout.faces.size(), 1u);
    const ShadowFace& f = atlas.layout.faces[0];
    EXPECT_TRUE(f.view.orthographic);
    const FaceCheck c = checkFace(atlas, f);
    EXPECT_EQ(c.wrong, 0u);
    EXPECT_GT(c.box, 0u);
    // Looking straight down the fit is the floor itself: every texel sees it or the box; slanted,
    // the square fit around the scene's box holds the floor's parallelogram and some empty rim.
    if (dir.y == -1.0f) {
      EXPECT_EQ(c.empty, 0u);
    }
    EXPECT_GT(c.floor, size_t(f.size) * size_t(f.size) / 4);
    EXPECT_EQ(c.boxNearer, c.box);
    EXPECT_EQ(atlas.trianglesDrawn(), scene.triangleCount());
  }
}

// The view's geometry from a G-buffer: inside the scene, around what the camera sees.
TEST(ShadowMaps, ViewGeometryBoundsHoldWhatTheCameraSees) {
  const Scene scene = floorAndBox();
  // Looking down at the box from close by: the floor's far parts are out of view.
  const ts::SceneCamera close = ts::SceneCamera::lookAt({0.0, 4.0, 0.5}, {0.0, 0.0, 0.0},
                                                        {0.0, 0.0, -1.0}, 0.6f, 0.1f, 50.0f);
  ts::RasterOptions o;
  o.threads = 2;
  const ts::GBuffer g = ts::rasterize(scene, close, 64, 64, o);
  const ts::Bounds b = ts::viewGeometryBounds(g, close);
  const ts::Bounds all = scene.bounds();
  for (int k = 0; k < 3; ++k) {
    EXPECT_GE(b.min[k], all.min[k] - 0.2f) << k;
    EXPECT_LE(b.max[k], all.max[k] + 0.2f) << k;
  }
  EXPECT_LT(b.extent().x, all.extent().x / 2.0f);
  EXPECT_LT(b.extent().z, all.extent().z / 2.0f);
  EXPECT_GE(b.max.y, 1.0f);  // the box's top is in view
  EXPECT_LE(b.min.y, 0.0f);  // and the floor around it
  // A view of nothing: empty.
  const ts::SceneCamera up = ts::SceneCamera::lookAt({0.0, 4.0, 0.0}, {0.0, 8.0, 0.0},
                                                     {0.0, 0.0, -1.0}, 0.6f, 0.1f, 50.0f);
  const ts::Bounds none = ts::viewGeometryBounds(ts::rasterize(scene, up, 16, 16, o), up);
  EXPECT_GT(none.min.x, none.max.x);
}

// A directional map fitted to the receivers holds the same analytic depths, finer.
TEST(ShadowMaps, DirectionalMapFittedToTheReceivers) {
  const Scene scene = floorAndBox();
  SceneLight sun =
      SceneLight::directional(glm::normalize(glm::vec3(0.4f, -1.0f, 0.3f)), glm::vec3(1));
  sun.castsShadow = true;
  ts::Bounds receivers;
  receivers.extend(glm::vec3(-2.0f, 0.0f, -2.0f));
  receivers.extend(glm::vec3(2.0f, 1.0f, 2.0f));
  ts::ShadowAtlasOptions o;
  o.mapSize = 32;  // 128 for the directional map
  const ShadowAtlas atlas = drawShadowAtlas(
      scene, planShadowAtlas({sun}, scene.bounds(), scene.camera(0), o, receivers), 2);
  const FaceCheck c = checkFace(atlas, atlas.layout.faces[0]);
  EXPECT_EQ(c.wrong, 0u);
  EXPECT_EQ(c.empty, 0u);  // the floor extends beyond the receivers on every side
  EXPECT_GT(c.box, size_t(atlas.layout.faces[0].size) * size_t(atlas.layout.faces[0].size) / 8);
  EXPECT_EQ(c.boxNearer, c.box);
}

TEST(ShadowMaps, FacesOutsideTheGeometryStayAtFar) {
  const Scene scene = floorAndBox();
  // A spot light under the floor looking down: the floor's box lies behind it.
  const ShadowAtlas atlas = drawFor(
      scene, SceneLight::spot({0.0, -2.0, 0.0}, {0.0f, -1.0f, 0.0f}, glm::vec3(1), 5, 0.3f, 0.6f));
  const ShadowFace& f = atlas.layout.faces[0];
  EXPECT_EQ(atlas.faceTriangles[0], 0u);
  for (int y = 0; y < f.size; ++y)
    for (int x = 0; x < f.size; ++x) ASSERT_EQ(atlas.at(f.x + x, f.y + y), float(f.view.zfar));
}

// alphaMode MASK (ts_material_covered, as the G-buffer's test): a quad at y = kLeafY over the
// floor, [-2, 2] in x and z, whose texture (2x1, NEAREST) has alpha 0.2 where x < 0 and 1 where
// x > 0. The maps hold the quad's depth over its covered half only, the floor's under the other.
constexpr float kLeafY = 2.0f, kLeaf = 2.0f;
Scene floorAndLeaf(ts::AlphaMode mode) {
  Scene s;
  s.name = "floor-and-leaf";
  ts::MeshBuilder b(s);
  const uint32_t floor = b.addMaterial(ts::Material{});
  ts::Material leaf;
  leaf.alphaMode = mode;
  leaf.diffuseTexture = leaf.baseColorTexture = 0;
  const uint32_t m = b.addMaterial(leaf);
  s.textures.push_back(ts::test::halfCutOutTexture());
  ts::test::addFloor(b, kFloor, floor);
  // u runs along +x: u < 0.5 (alpha 0.2) where x < 0.
  b.quad({-kLeaf, kLeafY, kLeaf}, {kLeaf, kLeafY, kLeaf}, {kLeaf, kLeafY, -kLeaf},
         {-kLeaf, kLeafY, -kLeaf}, m);
  s.cameraPath.push_back(ts::SceneCamera::lookAt({0.0, 3.0, 12.0}, {0.0, 0.0, 0.0}, {0.0, 1.0, 0.0},
                                                 1.0f, 0.1f, 100.0f));
  return s;
}

struct LeafCheck {
  size_t leaf = 0, under = 0, wrong = 0;  // texels showing the leaf, the floor under the cut-out
};

// Every texel whose ray meets the leaf's plane away (by 0.05) from its outline and its x = 0
// split: the leaf's depth over x > 0 (and over x < 0 when `cutOut` is false), else the floor's.
LeafCheck checkLeaf(const ShadowAtlas& atlas, const ShadowFace& f, bool cutOut) {
  constexpr double kMargin = 0.05;
  LeafCheck c;
  for (int y = 0; y < f.size; ++y)
    for (int x = 0; x < f.size; ++x) {
      glm::dvec3 o, d;
      texelRay(f, x + 0.5, y + 0.5, o, d);
      if (!(d.y < 0.0) || o.y <= kLeafY) continue;
      const double tl = (kLeafY - o.y) / d.y, tf = -o.y / d.y;
      const glm::dvec3 p = o + tl * d;
      const double ax = std::abs(p.x), az = std::abs(p.z);
      if (ax > kLeaf - kMargin || az > kLeaf - kMargin || ax < kMargin) continue;
      const bool leaf = p.x > 0.0 || !cutOut;
      const double expected = leaf ? tl : tf;
      const float stored = atlas.at(f.x + x, f.y + y);
      if (!(std::abs(stored - expected) <= kTolerance * expected)) {
        if (c.wrong < 5)
          ADD_FAILURE() << "face " << f.face << " texel " << x << "," << y << ": " << stored
                        << ", expected " << expected;
        ++c.wrong;
      }
      (leaf ? c.leaf : c.under)++;
    }
  return c;
}

TEST(ShadowMaps, MaskLeavesTheCutOutHalfOut) {
  const std::vector<SceneLight> lights = {
      SceneLight::spot({0.3, 5.0, 0.2}, {0.0f, -1.0f, 0.0f}, glm::vec3(1), 20, 0.5f, 0.8f),
      SceneLight::directional(glm::normalize(glm::vec3(0.3f, -1.0f, 0.2f)), glm::vec3(1))};
  for (const SceneLight& light : lights) {
    SCOPED_TRACE(light.type == ts::SceneLightType::Directional ? "directional" : "spot");
    const ShadowAtlas masked = drawFor(floorAndLeaf(ts::AlphaMode::Mask), {light}, 1);
    ASSERT_EQ(masked.layout.faces.size(), 1u);
    const LeafCheck c = checkLeaf(masked, masked.layout.faces[0], true);
    EXPECT_EQ(c.wrong, 0u);
    EXPECT_GT(c.leaf, 100u);
    EXPECT_GT(c.under, 100u);
    // The same for any thread count.
    for (int threads : {2, 3})
      EXPECT_TRUE(drawFor(floorAndLeaf(ts::AlphaMode::Mask), {light}, threads).depth ==
                  masked.depth)
          << threads << " threads";
    // OPAQUE: the whole leaf casts, alpha ignored.
    const ShadowAtlas opaque = drawFor(floorAndLeaf(ts::AlphaMode::Opaque), {light}, 2);
    const LeafCheck o = checkLeaf(opaque, opaque.layout.faces[0], false);
    EXPECT_EQ(o.wrong, 0u);
    EXPECT_EQ(o.under, 0u);
    EXPECT_GT(o.leaf, 200u);
  }
}

// Big faces are drawn one after another with every thread, small ones (one tile) side by side.
TEST(ShadowMaps, SameAtlasForAnyThreadCount) {
  const Scene scene = floorAndBox();
  const std::vector<SceneLight> lights = {
      SceneLight::point({0.5, 3.0, 0.25}, glm::vec3(1), 20),
      SceneLight::point({-3.0, 2.0, 1.0}, glm::vec3(1), 8),
      SceneLight::spot({2.0, 4.0, 0.0}, {0.0f, -1.0f, 0.0f}, glm::vec3(1), 20, 0.3f, 0.6f)};
  for (int size : {128, 32}) {
    const ShadowAtlas one = drawFor(scene, lights, 1, size),
                      three = drawFor(scene, lights, 3, size);
    ASSERT_EQ(one.depth.size(), three.depth.size());
    EXPECT_TRUE(one.depth == three.depth) << size;
    EXPECT_TRUE(one.faceTriangles == three.faceTriangles) << size;
  }
}

}  // namespace

// --shadow-bias receiver,C: the receiver plane with the constant only (no slope), its canonical
// text, and the face table's flag (record 6's z) that kernels/shadows.h branches on.
TEST(ShadowMaps, ReceiverPlaneBiasParsesAndReachesTheFaceTable) {
  ts::ShadowSampling plain, receiver;
  ts::parseShadowBias("0.5,2", plain);
  ts::parseShadowBias("receiver,0.25", receiver);
  EXPECT_FALSE(plain.receiverPlane);
  EXPECT_TRUE(receiver.receiverPlane);
  EXPECT_EQ(receiver.biasConstant, 0.25f);
  EXPECT_EQ(receiver.biasSlope, 0.0f);
  EXPECT_EQ(ts::shadowBiasText(plain), "0.5,2");
  EXPECT_EQ(ts::shadowBiasText(receiver), "receiver,0.25");
  for (const char* bad :
       {"receiver", "receiver,1,2", "receiver,-1", "receiver,nan", "1,receiver"}) {
    ts::ShadowSampling s;
    EXPECT_THROW(ts::parseShadowBias(bad, s), ts::Error) << bad;
  }
  ts::Scene scene = ts::test::floorAndBox();
  ts::SceneLight sun = ts::SceneLight::directional({0.0f, -1.0f, 0.0f}, glm::vec3(1.0f));
  sun.castsShadow = true;
  scene.lights.push_back(sun);
  const ts::SceneCamera camera = scene.camera(0);
  auto atlas = std::make_shared<ts::ShadowAtlas>(ts::drawShadowAtlas(
      scene, ts::planShadowAtlas(scene.lights, scene.bounds(), camera, ts::ShadowAtlasOptions{}),
      1));
  for (const ts::ShadowSampling& s : {plain, receiver}) {
    ts::ViewLights lights = ts::toViewSpace(scene.lights, camera.viewFromWorld);
    ts::attachShadowMaps(atlas, scene.lights, camera.viewFromWorld, s, lights);
    ASSERT_EQ(lights.shadowFaces.size(), 7u);  // one face: TS_SHADOW_FACE_RECORDS
    EXPECT_EQ(lights.shadowFaces[6].z, s.receiverPlane ? 1.0f : 0.0f);
    EXPECT_EQ(lights.shadowFaces[5].w, s.biasSlope);
  }
}
