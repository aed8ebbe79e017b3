// builtin:atrium — modelled on the proportions of the Sponza atrium: a 30 x 13 m courtyard with
// 16 m walls, two storeys of arcades (columns and arches) on the long sides over aisles, a gallery
// floor, hanging curtains and banners, planters, vases and braziers. Light sets after the
// forward-vs-deferred comparison: many small lights, a few big ones, or a mix. See
// scenes/README.md.
#include <cmath>

#include "scene/builtin_scenes.h"
#include "scene/mesh_builder.h"
#include "util/error.h"
#include "util/pi.h"
#include "util/short_text.h"

namespace ts {

namespace {

constexpr float kHalfX = 15.0f;   // courtyard floor: x in [-15, 15]
constexpr float kHalfZ = 6.5f;    //                  z in [-6.5, 6.5] (arcade wall centres)
constexpr float kOuterZ = 11.0f;  // outer aisle walls (inner face)
constexpr float kWallTop = 16.0f;
constexpr int kBays = 8;
constexpr float kBay = 2.0f * kHalfX / float(kBays);  // 3.75 m column spacing

// Light sets: `small` 128 lights of range 0.5..2 m, `big` 16 of range 8..20 m, `mixed` = every
// 32nd light big, the others small (128: 4 big + 124 small); the thesis-* sets are these with
// the big lights casting shadows (makeAtriumScene). Colour peak = k * range^2, so each
// light looks about as bright at the same fraction of its range.
constexpr int kSmallCount = 128;
constexpr float kSmallRange0 = 0.5f, kSmallRange1 = 2.0f, kSmallK = 0.6f;
constexpr int kBigCount = 16;
constexpr float kBigRange0 = 8.0f, kBigRange1 = 20.0f, kBigK = 0.02f;
constexpr int kMixedCount = 128, kMixedBigEvery = 32;

struct Materials {
  uint32_t stone, darkStone, marble, tileA, tileB, plaster, recess, terracotta, plant, bronze, fire;
  uint32_t cloth[3];
};

Materials addMaterials(MeshBuilder& mb) {
  auto mat = [&](const char* name, glm::vec3 kd, glm::vec3 ks, float s, glm::vec3 ke = {},
                 bool doubleSided = false) {
    Material m;
    m.name = name;
    m.diffuse = kd;
    m.specular = ks;
    m.shininess = s;
    m.emissive = ke;
    m.doubleSided = doubleSided;
    return mb.addMaterial(m);
  };
  Materials M{};
  M.stone = mat("sandstone", {0.62f, 0.56f, 0.46f}, glm::vec3(0.05f), 16.0f);
  M.darkStone = mat("dark_stone", {0.40f, 0.36f, 0.30f}, glm::vec3(0.06f), 20.0f);
  M.marble = mat("column_marble", {0.76f, 0.73f, 0.68f}, glm::vec3(0.35f), 80.0f);
  M.tileA = mat("floor_tile_light", {0.58f, 0.53f, 0.44f}, glm::vec3(0.15f), 48.0f);
  M.tileB = mat("floor_tile_dark", {0.33f, 0.28f, 0.24f}, glm::vec3(0.15f), 48.0f);
  M.plaster = mat("aisle_plaster", {0.70f, 0.66f, 0.58f}, glm::vec3(0.03f), 8.0f);
  M.recess = mat("recess", {0.08f, 0.07f, 0.06f}, glm::vec3(0.02f), 8.0f);
  M.terracotta = mat("terracotta", {0.62f, 0.30f, 0.17f}, glm::vec3(0.08f), 24.0f);
  M.plant = mat("plant", {0.14f, 0.36f, 0.08f}, glm::vec3(0.06f), 12.0f);
  M.bronze = mat("bronze", {0.30f, 0.19f, 0.08f}, glm::vec3(0.65f), 96.0f);
  M.fire = mat("brazier_fire", {0.2f, 0.1f, 0.0f}, glm::vec3(0.0f), 1.0f, {3.0f, 1.2f, 0.25f});
  M.cloth[0] = mat("curtain_red", {0.60f, 0.07f, 0.05f}, glm::vec3(0.03f), 6.0f, {}, true);
  M.cloth[1] = mat("curtain_green", {0.08f, 0.42f, 0.12f}, glm::vec3(0.03f), 6.0f, {}, true);
  M.cloth[2] = mat("curtain_blue", {0.07f, 0.14f, 0.52f}, glm::vec3(0.03f), 6.0f, {}, true);
  return M;
}

float bayCenter(int b) { return -kHalfX + kBay * (float(b) + 0.5f); }
float columnX(int i) { return -kHalfX + kBay * float(i); }

// One storey of arcade along the wall plane z = zc: pedestals, columns, capitals, arches,
// stepped spandrels and a wall band up to bandTop.
void arcade(MeshBuilder& mb, const Materials& M, float zc, float yBase, float pedestal, float shaft,
            float radius, float capWidth, float archThickness, float wallDepth, float bandTop) {
  float ys = yBase + pedestal + shaft + 0.3f;  // springing line (top of the capitals)
  float hz = 0.5f * wallDepth;
  for (int i = 1; i < kBays; ++i) {
    float x = columnX(i), c = 0.5f * capWidth;
    mb.box({x - c, yBase, zc - c}, {x + c, yBase + pedestal, zc + c}, M.darkStone, false);
    mb.cylinder({x, yBase + pedestal, zc}, radius, shaft, 16, M.marble, false);
    mb.box({x - c, ys - 0.3f, zc - c}, {x + c, ys, zc + c}, M.stone);
  }
  for (int end = 0; end < 2; ++end) {  // half piers against the end walls
    float x0 = end ? kHalfX - 0.5f * capWidth : -kHalfX, x1 = x0 + 0.5f * capWidth;
    mb.box({x0, yBase, zc - hz}, {x1, ys, zc + hz}, M.stone, false);
  }
  float r = 0.5f * (kBay - capWidth), ro = r + archThickness;
  const float steps[4] = {0.0f, 0.5f * ro, 0.82f * ro, ro};
  for (int b = 0; b < kBays; ++b) {
    float xm = bayCenter(b);
    mb.arch({xm, ys, zc}, {1.0f, 0.0f, 0.0f}, r, archThickness, wallDepth * 1.02f, 12, M.stone);
    for (int k = 0; k < 3; ++k) {
      float h = steps[k + 1];
      float inner = std::sqrt(std::max(ro * ro - h * h, 0.0f));
      for (int lr = -1; lr <= 1; lr += 2) {
        float xa = xm + float(lr) * inner, xb = xm + float(lr) * 0.5f * kBay;
        mb.box({std::min(xa, xb), ys + steps[k], zc - hz}, {std::max(xa, xb), ys + h, zc + hz},
               M.stone);
      }
    }
  }
  mb.box({-kHalfX, ys + ro, zc - hz}, {kHalfX, bandTop, zc + hz}, M.stone);
}

std::vector<SceneLight> makeLights(const std::string& set, uint32_t seed, int count) {
  SceneRandom rnd(seed * 747796405u + 2891336453u);
  std::vector<SceneLight> lights;
  lights.reserve(size_t(count));
  for (int k = 0; k < count; ++k) {
    bool big = set == "big" || (set == "mixed" && k % kMixedBigEvery == 0);
    SceneLight l;
    if (big) {
      // Anywhere in the courtyard or over the aisles, 1.5..10 m up. (A braced list's elements are
      // evaluated in order, unlike a call's arguments.)
      l.position = {rnd.uniform(-13.0f, 13.0f), rnd.uniform(1.5f, 10.0f), rnd.uniform(-9.0f, 9.0f)};
      l.range = rnd.uniform(kBigRange0, kBigRange1);
      const float saturation = rnd.uniform(0.1f, 0.4f);  // first: g++'s old order (SceneRandom)
      const float hue = rnd.uniform();
      l.color = kBigK * l.range * l.range * hueColor(hue, saturation);
    } else {
      // 55% in the courtyard, 25% in the ground-floor aisles, 20% in the gallery; near surfaces.
      float region = rnd.uniform();
      float side = rnd.chance(0.5f) ? 1.0f : -1.0f;
      if (region < 0.55f) {
        l.position = {rnd.uniform(-14.0f, 14.0f), rnd.uniform(0.3f, 4.5f),
                      rnd.uniform(-6.0f, 6.0f)};
      } else if (region < 0.8f) {
        l.position = {rnd.uniform(-14.5f, 14.5f), rnd.uniform(0.3f, 4.0f),
                      side * rnd.uniform(7.2f, 10.6f)};
      } else {
        l.position = {rnd.uniform(-14.5f, 14.5f), rnd.uniform(8.7f, 12.0f),
                      side * rnd.uniform(7.2f, 10.6f)};
      }
      l.range = rnd.uniform(kSmallRange0, kSmallRange1);
      const float saturation = rnd.uniform(0.4f, 0.9f);  // first: g++'s old order (SceneRandom)
      const float hue = rnd.uniform();
      l.color = kSmallK * l.range * l.range * hueColor(hue, saturation);
    }
    lights.push_back(l);
  }
  return lights;
}

std::vector<SceneCamera> cameraPath() {
  // 240 frames walking an ellipse (11 x 4 m) round the courtyard, eye height 1.7..4.5 m, looking
  // across the courtyard ~125° ahead on a smaller ellipse (views along the arcades and to the
  // ends). The path closes: frame 240 would equal frame 0.
  std::vector<SceneCamera> path;
  const int frames = 240;
  const float yfov = 60.0f * kPi / 180.0f;
  for (int k = 0; k < frames; ++k) {
    float a = 2.0f * kPi * float(k) / float(frames);
    glm::vec3 eye{11.0f * std::cos(a), 1.7f + 2.8f * (0.5f - 0.5f * std::cos(2.0f * a)),
                  4.0f * std::sin(a)};
    float b = a + 2.2f;
    glm::vec3 target{9.0f * std::cos(b), 3.0f + 1.5f * std::sin(3.0f * a), 3.0f * std::sin(b)};
    path.push_back(SceneCamera::lookAt(eye, target, {0.0f, 1.0f, 0.0f}, yfov, 0.1f, 80.0f));
  }
  return path;
}

}  // namespace

std::vector<std::string> atriumLightSets() {
  return {"small",       "big", "mixed", "thesis-small", "thesis-big", "thesis-big-shadows",
          "thesis-mixed"};
}

Scene makeAtriumScene(const std::string& lightSet, uint32_t seed, int lightCount) {
  std::string set = lightSet.empty() ? "small" : lightSet;
  // The thesis's four scenarios (issue #18): small, big, big with every light casting a shadow,
  // and mixed with its big lights casting (its "few big shadow-casting ones"); the same lights
  // as small, big and mixed for a seed, only castsShadow differs.
  bool bigLightsCast = false;
  if (set == "thesis-small" || set == "thesis-big" || set == "thesis-mixed") {
    bigLightsCast = set == "thesis-mixed";
    set = set.substr(7);
  } else if (set == "thesis-big-shadows") {
    bigLightsCast = true;
    set = "big";
  }
  if (set != "small" && set != "big" && set != "mixed")
    throw Error("unknown light set '" + shortText(lightSet) +
                "' for builtin:atrium (valid: small, big, mixed, thesis-small, thesis-big, "
                "thesis-big-shadows, thesis-mixed)");
  Scene scene;
  scene.name = "atrium";
  scene.ambient = glm::vec3(0.03f);
  MeshBuilder mb(scene);
  Materials M = addMaterials(mb);
  SceneRandom rnd(seed * 2654435761u + 777u);

  // Courtyard floor: 20 x 10 checker of 1.5 x 1.3 m tiles; aisle floors.
  for (int i = 0; i < 20; ++i)
    for (int j = 0; j < 10; ++j) {
      float x0 = -kHalfX + 1.5f * float(i), z0 = -kHalfZ + 1.3f * float(j);
      mb.quad({x0, 0.0f, z0 + 1.3f}, {x0 + 1.5f, 0.0f, z0 + 1.3f}, {x0 + 1.5f, 0.0f, z0},
              {x0, 0.0f, z0}, (i + j) % 2 ? M.tileA : M.tileB);
    }
  for (int side = -1; side <= 1; side += 2) {
    float z0 = float(side) * kHalfZ, z1 = float(side) * kOuterZ;
    mb.box({-kHalfX, -0.1f, std::min(z0, z1)}, {kHalfX, 0.0f, std::max(z0, z1)}, M.darkStone,
           false);
  }

  // Outer walls, end walls, aisle roofs and the cornice.
  for (int side = -1; side <= 1; side += 2) {
    float s = float(side);
    mb.box({-kHalfX - 0.5f, 0.0f, std::min(s * kOuterZ, s * (kOuterZ + 0.5f))},
           {kHalfX + 0.5f, kWallTop + 0.3f, std::max(s * kOuterZ, s * (kOuterZ + 0.5f))}, M.plaster,
           false);
    mb.box({std::min(s * kHalfX, s * (kHalfX + 0.5f)), 0.0f, -kOuterZ},
           {std::max(s * kHalfX, s * (kHalfX + 0.5f)), kWallTop + 0.3f, kOuterZ}, M.stone, false);
    mb.box({-kHalfX, kWallTop, std::min(s * (kHalfZ - 0.3f), s * kOuterZ)},
           {kHalfX, kWallTop + 0.3f, std::max(s * (kHalfZ - 0.3f), s * kOuterZ)}, M.darkStone);
    // Gallery floor over the aisle.
    mb.box({-kHalfX, 8.0f, std::min(s * (kHalfZ - 0.45f), s * kOuterZ)},
           {kHalfX, 8.4f, std::max(s * (kHalfZ - 0.45f), s * kOuterZ)}, M.darkStone);
    // End-wall relief: a big arch on pilasters framing a dark recess.
    float xw = s * (kHalfX - 0.2f);
    mb.arch({xw, 6.0f, 0.0f}, {0.0f, 0.0f, 1.0f}, 3.0f, 0.5f, 0.4f, 16, M.darkStone);
    for (int lr = -1; lr <= 1; lr += 2)
      mb.box({xw - 0.2f, 0.0f, float(lr) * 3.0f - 0.25f + float(lr) * 0.25f},
             {xw + 0.2f, 6.0f, float(lr) * 3.0f + 0.25f + float(lr) * 0.25f}, M.darkStone, false);
    float xr = s * (kHalfX - 0.01f);
    glm::vec3 a{xr, 0.0f, -3.0f}, b{xr, 0.0f, 3.0f}, c{xr, 6.0f, 3.0f}, d{xr, 6.0f, -3.0f};
    if (side > 0) mb.quad(a, b, c, d, M.recess);
    else mb.quad(a, d, c, b, M.recess);
  }

  // Two storeys of arcades on both long sides, a balustrade on the gallery.
  for (int side = -1; side <= 1; side += 2) {
    float zc = float(side) * kHalfZ;
    arcade(mb, M, zc, 0.0f, 0.4f, 3.8f, 0.4f, 1.0f, 0.4f, 0.9f, 8.0f);
    arcade(mb, M, zc, 8.4f, 0.3f, 3.0f, 0.25f, 0.6f, 0.3f, 0.6f, kWallTop);
    mb.box({-kHalfX, 8.4f, zc - 0.15f}, {kHalfX, 9.4f, zc + 0.15f}, M.darkStone, false);
  }

  // Curtains hanging under the gallery in four ground-floor bays per side; banners above.
  int colour = 0;
  for (int side = -1; side <= 1; side += 2) {
    float s = float(side);
    glm::vec3 along{-s, 0.0f, 0.0f};  // normals towards the courtyard
    for (int b : {1, 3, 4, 6}) {
      const float amp = rnd.uniform(0.08f, 0.18f);
      const float waves = rnd.uniform(2.5f, 4.0f);  // before the height: g++'s old order
      const float height = rnd.uniform(4.2f, 5.4f);
      mb.curtain({bayCenter(b), 7.7f, s * (kHalfZ - 0.6f)}, along, 3.0f, height, amp, waves, 24,
                 M.cloth[colour++ % 3]);
    }
    for (int b : {0, 2, 5, 7})
      mb.curtain({bayCenter(b), 15.6f, s * (kHalfZ - 0.45f)}, along, 1.6f, rnd.uniform(3.0f, 3.8f),
                 0.05f, 1.5f, 12, M.cloth[colour++ % 3]);
  }

  // Planters in front of the columns, vases in the corners, three braziers down the middle.
  for (int side = -1; side <= 1; side += 2)
    for (int i : {1, 3, 5, 7}) {
      glm::vec3 p{columnX(i), 0.0f, float(side) * (kHalfZ - 1.3f)};
      mb.frustum(p, 0.35f, 0.5f, 0.7f, 14, M.terracotta);
      mb.sphere(p + glm::vec3(0.0f, 0.95f, 0.0f),
                glm::vec3(0.55f, rnd.uniform(0.45f, 0.65f), 0.55f), 14, 8, M.plant);
    }
  for (int sx = -1; sx <= 1; sx += 2)
    for (int sz = -1; sz <= 1; sz += 2) {
      glm::vec3 p{float(sx) * (kHalfX - 1.2f), 0.0f, float(sz) * (kHalfZ - 1.2f)};
      mb.box(p - glm::vec3(0.3f, 0.0f, 0.3f), p + glm::vec3(0.3f, 0.8f, 0.3f), M.darkStone, false);
      mb.sphere(p + glm::vec3(0.0f, 1.22f, 0.0f), glm::vec3(0.35f, 0.45f, 0.35f), 14, 10,
                M.terracotta);
      mb.frustum(p + glm::vec3(0.0f, 1.6f, 0.0f), 0.12f, 0.2f, 0.3f, 12, M.terracotta);
    }
  for (float x : {-6.0f, 0.0f, 6.0f}) {
    glm::vec3 p{x, 0.0f, 0.0f};
    mb.cylinder(p, 0.08f, 1.0f, 8, M.bronze);
    mb.frustum(p + glm::vec3(0.0f, 1.0f, 0.0f), 0.15f, 0.42f, 0.25f, 14, M.bronze);
    mb.sphere(p + glm::vec3(0.0f, 1.35f, 0.0f), glm::vec3(0.3f, 0.35f, 0.3f), 10, 8, M.fire);
  }

  int count = lightCount >= 0  ? lightCount
              : set == "small" ? kSmallCount
              : set == "big"   ? kBigCount
                               : kMixedCount;
  scene.lights = makeLights(set, seed, count);
  if (bigLightsCast)
    for (SceneLight& l : scene.lights) l.castsShadow = l.range >= kBigRange0;  // small: <= 2 m
  scene.cameraPath = cameraPath();
  return scene;
}

}  // namespace ts
