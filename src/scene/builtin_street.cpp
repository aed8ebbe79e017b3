// builtin:street — modelled on the BART "Robots" setting of Olsson & Assarsson's tiled-shading
// paper: a 29.1-unit-wide main street between city blocks, 11 robots standing on paths down the
// street and point lights spread along those paths. Layout, light rules and camera path are
// documented in scenes/README.md; the tests assert the numbers below.
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "scene/builtin_scenes.h"
#include "scene/mesh_builder.h"
#include "util/error.h"
#include "util/pi.h"
#include "util/short_text.h"

namespace ts {

namespace {

// Street layout (units ≈ metres). The main street runs along Z; facades at x = ±kHalfWidth.
constexpr float kHalfWidth = 14.55f;  // 29.1 wide, facade to facade
constexpr float kSidewalk = 3.0f;     // sidewalk width in front of the facades
constexpr float kStreetZ0 = -160.0f;  // blocks from kStreetZ0 to kStreetZ1
constexpr float kStreetZ1 = 160.0f;
constexpr float kPathZ0 = -150.0f;  // the robots' paths (and the lights on them)
constexpr float kPathZ1 = 150.0f;
constexpr int kRobots = 11;
constexpr float kStorey = 3.3f;

// The `many` set: 924 lights = 84 per robot path, range 12.5; `few`: one per robot, range 40.
constexpr int kManyLights = 924;
constexpr float kManyRange = 12.5f;
constexpr float kManyIntensity = 2.5f;  // peak channel of each light's colour
constexpr float kFewRange = 40.0f;
constexpr float kFewIntensity = 35.0f;

struct RobotPath {
  float lane = 0.0f, amplitude = 0.0f, wavelength = 20.0f, phase = 0.0f;
  float x(float z) const { return lane + amplitude * std::sin(z / wavelength + phase); }
};

struct Robot {
  glm::vec3 position{0.0f};
  float height = 2.0f, yaw = 0.0f;
  int paint = 0, kind = 0;
};

struct Materials {
  uint32_t asphalt, sidewalk, marking, glass, litWindow, cornice, lampPost, lampHead, metal, joint,
      eye, antennaTip;
  uint32_t facade[5];
  uint32_t paint[4];
};

Materials addMaterials(MeshBuilder& mb) {
  auto mat = [&](const char* name, glm::vec3 kd, glm::vec3 ks, float s, glm::vec3 ke = {}) {
    Material m;
    m.name = name;
    m.diffuse = kd;
    m.specular = ks;
    m.shininess = s;
    m.emissive = ke;
    return mb.addMaterial(m);
  };
  Materials M{};
  M.asphalt = mat("asphalt", {0.16f, 0.16f, 0.17f}, glm::vec3(0.04f), 8.0f);
  M.sidewalk = mat("sidewalk", {0.45f, 0.44f, 0.42f}, glm::vec3(0.05f), 16.0f);
  M.marking = mat("road_marking", {0.8f, 0.78f, 0.7f}, glm::vec3(0.1f), 16.0f);
  M.facade[0] = mat("brick", {0.50f, 0.23f, 0.16f}, glm::vec3(0.04f), 12.0f);
  M.facade[1] = mat("sandstone", {0.62f, 0.55f, 0.42f}, glm::vec3(0.05f), 16.0f);
  M.facade[2] = mat("concrete", {0.48f, 0.48f, 0.47f}, glm::vec3(0.06f), 20.0f);
  M.facade[3] = mat("slate_blue", {0.32f, 0.37f, 0.45f}, glm::vec3(0.10f), 32.0f);
  M.facade[4] = mat("ochre_render", {0.65f, 0.45f, 0.20f}, glm::vec3(0.04f), 10.0f);
  M.glass = mat("window_glass", {0.04f, 0.05f, 0.06f}, glm::vec3(0.7f), 256.0f);
  M.litWindow =
      mat("lit_window", {0.05f, 0.05f, 0.05f}, glm::vec3(0.5f), 128.0f, {0.55f, 0.42f, 0.22f});
  M.cornice = mat("cornice", {0.70f, 0.68f, 0.64f}, glm::vec3(0.08f), 24.0f);
  M.lampPost = mat("lamp_post", {0.10f, 0.11f, 0.12f}, glm::vec3(0.5f), 64.0f);
  M.lampHead = mat("lamp_head", {0.9f, 0.9f, 0.8f}, glm::vec3(0.2f), 32.0f, {1.6f, 1.4f, 1.0f});
  M.metal = mat("robot_metal", {0.45f, 0.46f, 0.48f}, glm::vec3(0.8f), 96.0f);
  M.joint = mat("robot_joint", {0.12f, 0.12f, 0.13f}, glm::vec3(0.3f), 32.0f);
  M.eye = mat("robot_eye", {0.1f, 0.1f, 0.1f}, glm::vec3(0.5f), 64.0f, {2.0f, 0.35f, 0.1f});
  M.antennaTip =
      mat("robot_beacon", {0.1f, 0.1f, 0.1f}, glm::vec3(0.5f), 64.0f, {0.2f, 1.2f, 2.0f});
  M.paint[0] = mat("robot_paint_orange", {0.85f, 0.35f, 0.05f}, glm::vec3(0.45f), 48.0f);
  M.paint[1] = mat("robot_paint_teal", {0.05f, 0.55f, 0.55f}, glm::vec3(0.45f), 48.0f);
  M.paint[2] = mat("robot_paint_yellow", {0.85f, 0.72f, 0.08f}, glm::vec3(0.45f), 48.0f);
  M.paint[3] = mat("robot_paint_white", {0.80f, 0.80f, 0.78f}, glm::vec3(0.45f), 48.0f);
  return M;
}

// One building: a box with storey window bands and a cornice, optionally a set-back upper part.
// The facade towards the main street is the plane x = side * kHalfWidth.
void building(MeshBuilder& mb, const Materials& M, SceneRandom& rnd, int side, float z0, float z1,
              float depth, bool sideStreetBefore, bool sideStreetAfter) {
  uint32_t facade = M.facade[rnd.index(5)];
  int storeys = 3 + rnd.index(10);  // 3..12
  int lower = storeys;
  float setback = 0.0f;
  if (storeys >= 6 && rnd.chance(0.5f)) {  // a set-back upper part
    lower = storeys - 2 - rnd.index(storeys / 3);
    setback = rnd.uniform(2.0f, 4.5f);
  }
  float xf = float(side) * kHalfWidth;            // facade plane
  float xb = float(side) * (kHalfWidth + depth);  // back
  auto part = [&](float inset, int fromStorey, int toStorey) {
    float xFront = xf + float(side) * inset;
    float y0 = float(fromStorey) * kStorey, y1 = float(toStorey) * kStorey;
    mb.box({std::min(xFront, xb), y0, z0}, {std::max(xFront, xb), y1, z1}, facade, false);
    // Cornice at the top of the part, protruding 0.3.
    float xc = xFront - float(side) * 0.3f;
    mb.box({std::min(xc, xFront + float(side) * 0.6f), y1 - 0.35f, z0 - 0.3f},
           {std::max(xc, xFront + float(side) * 0.6f), y1, z1 + 0.3f}, M.cornice, true);
    // Window bands: one per storey on the street facade, and on the ends facing side streets.
    for (int s = fromStorey; s < toStorey; ++s) {
      float wy0 = float(s) * kStorey + 0.9f, wy1 = wy0 + 1.5f;
      uint32_t w = rnd.chance(0.12f) ? M.litWindow : M.glass;
      float x = xFront - float(side) * 0.02f;
      glm::vec3 a{x, wy0, z0 + 0.8f}, b{x, wy0, z1 - 0.8f}, c{x, wy1, z1 - 0.8f},
          d{x, wy1, z0 + 0.8f};
      if (side > 0) mb.quad(a, b, c, d, w);
      else mb.quad(a, d, c, b, w);  // facing the street
      float xIn = std::min(xFront, xb) + 0.8f, xOut = std::max(xFront, xb) - 0.8f;
      if (sideStreetBefore && xOut - xIn > 2.0f) {
        float z = z0 - 0.02f;
        mb.quad({xIn, wy0, z}, {xIn, wy1, z}, {xOut, wy1, z}, {xOut, wy0, z},
                rnd.chance(0.12f) ? M.litWindow : M.glass);
      }
      if (sideStreetAfter && xOut - xIn > 2.0f) {
        float z = z1 + 0.02f;
        mb.quad({xIn, wy0, z}, {xOut, wy0, z}, {xOut, wy1, z}, {xIn, wy1, z},
                rnd.chance(0.12f) ? M.litWindow : M.glass);
      }
    }
  };
  part(0.0f, 0, lower);
  if (lower < storeys) part(setback, lower, storeys);
}

void streetLamp(MeshBuilder& mb, const Materials& M, int side, float z) {
  float x = float(side) * (kHalfWidth - kSidewalk + 0.5f);
  mb.cylinder({x, 0.15f, z}, 0.09f, 5.2f, 8, M.lampPost);
  float armEnd = x - float(side) * 1.4f;
  mb.box({std::min(x, armEnd), 5.2f, z - 0.06f}, {std::max(x, armEnd), 5.32f, z + 0.06f},
         M.lampPost);
  mb.sphere({armEnd, 5.1f, z}, glm::vec3(0.28f, 0.18f, 0.28f), 10, 6, M.lampHead);
}

// A robot ≈ 2.2 * scale tall, built from boxes, cylinders and spheres; faces local -Z.
void robot(MeshBuilder& mb, const Materials& M, const Robot& r) {
  float s = r.height / 2.2f;
  glm::mat4 base = glm::translate(glm::mat4(1.0f), r.position) *
                   glm::rotate(glm::mat4(1.0f), r.yaw, glm::vec3(0, 1, 0)) *
                   glm::scale(glm::mat4(1.0f), glm::vec3(s));
  auto at = [&](glm::vec3 p) { return glm::vec3(base * glm::vec4(p, 1.0f)); };
  auto part = [&](glm::vec3 center, glm::vec3 size, uint32_t m) {
    mb.box(base * glm::translate(glm::mat4(1.0f), center) * glm::scale(glm::mat4(1.0f), size), m);
  };
  uint32_t paint = M.paint[r.paint];
  // Legs and feet.
  for (int lr = -1; lr <= 1; lr += 2) {
    part({0.2f * float(lr), 0.5f, 0.0f}, {0.24f, 0.8f, 0.28f}, M.metal);
    part({0.2f * float(lr), 0.06f, -0.06f}, {0.3f, 0.12f, 0.44f}, M.joint);
  }
  // Torso: a box (kind 0) or a barrel (kind 1).
  if (r.kind == 0) {
    part({0.0f, 1.3f, 0.0f}, {0.82f, 0.8f, 0.5f}, paint);
    part({0.0f, 1.35f, -0.26f}, {0.4f, 0.25f, 0.04f}, M.joint);  // chest panel
  } else {
    mb.cylinder(at({0.0f, 0.9f, 0.0f}), 0.42f * s, 0.8f * s, 14, paint);
  }
  part({0.0f, 0.92f, 0.0f}, {0.6f, 0.1f, 0.36f}, M.joint);  // hips
  // Arms: shoulder spheres, cylinders hanging down, hands.
  for (int lr = -1; lr <= 1; lr += 2) {
    glm::vec3 shoulder{0.52f * float(lr), 1.62f, 0.0f};
    mb.sphere(at(shoulder), 0.12f * s, 8, 6, M.joint);
    mb.cylinder(at(shoulder - glm::vec3(0.0f, 0.72f, 0.0f)), 0.08f * s, 0.72f * s, 8, M.metal);
    mb.sphere(at(shoulder - glm::vec3(0.0f, 0.8f, 0.0f)), 0.11f * s, 8, 6, paint);
  }
  // Neck, head, eyes, antenna with a glowing beacon.
  mb.cylinder(at({0.0f, 1.7f, 0.0f}), 0.08f * s, 0.14f * s, 8, M.joint);
  if (r.kind == 0) {
    mb.sphere(at({0.0f, 1.98f, 0.0f}), 0.26f * s, 16, 10, M.metal);
  } else {
    part({0.0f, 1.98f, 0.0f}, {0.46f, 0.4f, 0.4f}, M.metal);
  }
  float eyeZ = r.kind == 0 ? -0.23f : -0.21f;
  for (int lr = -1; lr <= 1; lr += 2)
    mb.sphere(at({0.1f * float(lr), 2.02f, eyeZ}), 0.05f * s, 8, 6, M.eye);
  mb.cylinder(at({0.0f, 2.18f, 0.0f}), 0.015f * s, 0.25f * s, 6, M.joint);
  mb.sphere(at({0.0f, 2.45f, 0.0f}), 0.05f * s, 8, 6, M.antennaTip);
}

struct Layout {
  RobotPath paths[kRobots];
  Robot robots[kRobots];
};

Layout makeLayout(SceneRandom& rnd) {
  Layout L;
  for (int i = 0; i < kRobots; ++i) {
    RobotPath& p = L.paths[i];
    // Lanes spread across the roadway (|x| <= 9.5 incl. the wiggle), each wiggling gently.
    p.lane = -8.0f + 16.0f * (float(i) + 0.5f) / float(kRobots) + rnd.uniform(-0.5f, 0.5f);
    p.amplitude = rnd.uniform(0.5f, 1.5f);
    p.wavelength = rnd.uniform(12.0f, 30.0f);
    p.phase = rnd.uniform(0.0f, 2.0f * kPi);
    Robot& r = L.robots[i];
    float z = kPathZ0 + 12.0f + (kPathZ1 - kPathZ0 - 24.0f) * (float(i) + 0.5f) / float(kRobots) +
              rnd.uniform(-8.0f, 8.0f);
    r.position = {p.x(z), 0.0f, z};
    r.height = rnd.uniform(1.2f, 3.0f);
    // Face along the path (+Z or -Z), turned a little.
    const bool backwards = !rnd.chance(0.5f);
    const float turn = rnd.uniform(-0.5f, 0.5f);
    r.yaw = (backwards ? kPi : 0.0f) + turn;
    r.paint = rnd.index(4);
    r.kind = rnd.index(2);
  }
  return L;
}

std::vector<SceneLight> manyLights(const Layout& L, uint32_t seed, int count) {
  // Light k lies on path k % 11, at the (k / 11)-th of that path's evenly spaced slots, with a
  // random sideways offset (±3) and height (1..6) and a random saturated colour.
  SceneRandom rnd(seed * 747796405u + 2891336453u);
  std::vector<SceneLight> lights;
  lights.reserve(size_t(count));
  for (int k = 0; k < count; ++k) {
    int path = k % kRobots, slot = k / kRobots;
    int onPath = count / kRobots + (path < count % kRobots ? 1 : 0);
    float t = (float(slot) + 0.5f) / float(onPath);
    float z = kPathZ0 + (kPathZ1 - kPathZ0) * t;
    SceneLight l;
    float offset = rnd.uniform(-3.0f, 3.0f);
    l.position = {L.paths[path].x(z) + offset, rnd.uniform(1.0f, 6.0f), z};
    const float saturation = rnd.uniform(0.3f, 0.9f);  // first: g++'s old order (SceneRandom)
    const float hue = rnd.uniform();
    l.color = kManyIntensity * hueColor(hue, saturation);
    l.range = kManyRange;
    lights.push_back(l);
  }
  return lights;
}

std::vector<SceneLight> fewLights(const Layout& L, uint32_t seed, int count) {
  // Light k hangs above robot k % 11, 2.5 above its head (2 more per extra round), slightly to one
  // side; warm-to-cool whites.
  SceneRandom rnd(seed * 747796405u + 1013904223u);
  std::vector<SceneLight> lights;
  lights.reserve(size_t(count));
  for (int k = 0; k < count; ++k) {
    const Robot& r = L.robots[k % kRobots];
    float a = rnd.uniform(0.0f, 2.0f * kPi);
    SceneLight l;
    l.position =
        r.position + glm::vec3(1.2f * std::cos(a), r.height + 2.5f + 2.0f * float(k / kRobots),
                               1.2f * std::sin(a));
    const float saturation = rnd.uniform(0.1f, 0.35f);  // first: g++'s old order (SceneRandom)
    const float hue = rnd.uniform();
    l.color = kFewIntensity * hueColor(hue, saturation);
    l.range = kFewRange;
    lights.push_back(l);
  }
  return lights;
}

std::vector<SceneCamera> cameraPath() {
  // 240 frames flying down the street (+Z to -Z), weaving sideways, from pedestrian height
  // (1.7) up to rooftop-ish views (~14) and back twice; always looking down the street.
  std::vector<SceneCamera> path;
  const int frames = 240;
  const float yfov = 60.0f * kPi / 180.0f;
  for (int k = 0; k < frames; ++k) {
    float t = float(k) / float(frames);
    float z = 140.0f - 280.0f * t;
    float x = 6.0f * std::sin(2.0f * kPi * 1.5f * t);
    float y = 1.7f + 12.3f * (0.5f - 0.5f * std::cos(2.0f * kPi * 2.0f * t));
    glm::vec3 eye{x, y, z};
    glm::vec3 target{0.4f * x + 3.0f * std::sin(2.0f * kPi * t), 0.35f * y + 0.6f, z - 35.0f};
    path.push_back(SceneCamera::lookAt(eye, target, {0.0f, 1.0f, 0.0f}, yfov, 0.2f, 450.0f));
  }
  return path;
}

}  // namespace

std::vector<std::string> streetLightSets() { return {"many", "few"}; }

Scene makeStreetScene(const std::string& lightSet, uint32_t seed, int lightCount) {
  std::string set = lightSet.empty() ? "many" : lightSet;
  if (set != "many" && set != "few")
    throw Error("unknown light set '" + shortText(lightSet) +
                "' for builtin:street (valid: many, few)");
  Scene scene;
  scene.name = "street";
  scene.ambient = glm::vec3(0.03f);
  MeshBuilder mb(scene);
  Materials M = addMaterials(mb);
  SceneRandom rnd(seed * 2654435761u + 12345u);

  // Ground: one asphalt plane under everything (main street, side streets, back lots).
  const float groundX = 75.0f, groundZ0 = kStreetZ0 - 30.0f, groundZ1 = kStreetZ1 + 30.0f;
  mb.quad({-groundX, 0.0f, groundZ1}, {groundX, 0.0f, groundZ1}, {groundX, 0.0f, groundZ0},
          {-groundX, 0.0f, groundZ0}, M.asphalt, glm::vec2(2.0f * groundX, groundZ1 - groundZ0));
  // Centre line, dashed.
  for (float z = kStreetZ0; z < kStreetZ1; z += 8.0f)
    mb.quad({-0.1f, 0.01f, z + 4.0f}, {0.1f, 0.01f, z + 4.0f}, {0.1f, 0.01f, z}, {-0.1f, 0.01f, z},
            M.marking);

  // Blocks on both sides, cut by side streets; a back row of buildings behind them; end blocks
  // closing the street at both ends.
  for (int side = -1; side <= 1; side += 2) {
    float z = kStreetZ0;
    while (z < kStreetZ1 - 10.0f) {
      float blockLen = std::min(rnd.uniform(30.0f, 60.0f), kStreetZ1 - z);
      float blockEnd = z + blockLen;
      bool streetBefore = z > kStreetZ0, streetAfter = blockEnd < kStreetZ1 - 1.0f;
      // Sidewalk along the block.
      float xs0 = float(side) * (kHalfWidth - kSidewalk), xs1 = float(side) * kHalfWidth;
      mb.box({std::min(xs0, xs1), 0.0f, z}, {std::max(xs0, xs1), 0.15f, blockEnd}, M.sidewalk,
             false);
      for (float lz = z + 6.0f; lz < blockEnd - 3.0f; lz += 24.0f) streetLamp(mb, M, side, lz);
      // Buildings of 8..20 frontage filling the block.
      float bz = z;
      while (bz < blockEnd - 0.5f) {
        float w = rnd.uniform(8.0f, 20.0f);
        if (blockEnd - (bz + w) < 8.0f) w = blockEnd - bz;
        float depth = rnd.uniform(14.0f, 24.0f);
        building(mb, M, rnd, side, bz, bz + w, depth, streetBefore && bz == z,
                 streetAfter && bz + w >= blockEnd - 0.01f);
        bz += w;
      }
      z = blockEnd + rnd.uniform(10.0f, 14.0f);  // side street
    }
    // Back row, seen through the side streets.
    for (float bz = kStreetZ0; bz < kStreetZ1;) {
      float w = std::min(rnd.uniform(20.0f, 40.0f), kStreetZ1 - bz);
      float x0 = float(side) * (kHalfWidth + 36.0f),
            x1 = float(side) * (kHalfWidth + 36.0f + 18.0f);
      float h = kStorey * float(4 + rnd.index(12));
      mb.box({std::min(x0, x1), 0.0f, bz}, {std::max(x0, x1), h, bz + w}, M.facade[rnd.index(5)],
             false);
      bz += w;
    }
  }
  for (int end = 0; end < 2; ++end) {
    float z0 = end ? kStreetZ1 + 8.0f : kStreetZ0 - 26.0f;
    mb.box({-kHalfWidth - 30.0f, 0.0f, z0}, {kHalfWidth + 30.0f, kStorey * 9.0f, z0 + 18.0f},
           M.facade[2], false);
  }

  Layout layout = makeLayout(rnd);
  for (const Robot& r : layout.robots) robot(mb, M, r);

  if (set == "many")
    scene.lights = manyLights(layout, seed, lightCount < 0 ? kManyLights : lightCount);
  else scene.lights = fewLights(layout, seed, lightCount < 0 ? kRobots : lightCount);
  scene.cameraPath = cameraPath();
  return scene;
}

}  // namespace ts
