// The hard-case table and the small scenes it is built from (docs/hard-cases.md).
#include "check/hard_cases.h"

#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "scene/mesh_builder.h"

namespace ts {
namespace {

// ---- the room every case starts from -------------------------------------------------------
// A floor, a back wall, a glossy box and sphere, and a single-sided panel turned away from the
// camera (its back is seen, with normals pointing away: back-facing normals). 64x48 pixels.

const glm::dvec3 kEye(0.0, 2.0, 4.0), kTarget(0.0, 1.0, -6.0);

SceneCamera roomCamera(float znear = 0.1f, float zfar = 100.0f) {
  return SceneCamera::lookAt(kEye, kTarget, {0.0, 1.0, 0.0}, 1.0f, znear, zfar);
}

Scene room(const std::string& name) {
  Scene s;
  s.name = name;
  s.ambient = glm::vec3(0.02f);
  MeshBuilder mb(s);
  Material matte;
  matte.name = "matte";
  matte.diffuse = {0.6f, 0.55f, 0.5f};
  matte.specular = glm::vec3(0.1f);
  matte.shininess = 8.0f;
  Material glossy;
  glossy.name = "glossy";
  glossy.diffuse = {0.2f, 0.3f, 0.5f};
  glossy.specular = glm::vec3(0.6f);
  glossy.shininess = 64.0f;
  uint32_t m0 = mb.addMaterial(matte), m1 = mb.addMaterial(glossy);
  mb.quad({-8, 0, 2}, {8, 0, 2}, {8, 0, -20}, {-8, 0, -20}, m0);      // floor, normal +y
  mb.quad({-8, 0, -12}, {8, 0, -12}, {8, 6, -12}, {-8, 6, -12}, m0);  // back wall, +z
  mb.box({-1, 0, -6}, {1, 2, -4}, m1);
  mb.sphere({3, 1, -7}, 1.0f, 24, 12, m1);
  mb.quad({-2, 0, -3}, {-4, 0, -3}, {-4, 3, -3}, {-2, 3, -3}, m1);  // panel, normal -z (away)
  s.cameraPath = {roomCamera()};
  return s;
}

HardCaseFrame frameOf(Scene scene, int width = 64, int height = 48) {
  HardCaseFrame f;
  f.scene = std::move(scene);
  f.width = width;
  f.height = height;
  return f;
}

// A deterministic stream of numbers for light placement (SceneRandom: the same on every library).
// Every draw is its own statement: C++ leaves the order of a call's arguments unspecified (g++ on
// x86-64 evaluates them right to left, clang left to right), so a call that draws twice builds
// another case under each compiler. The cases draw in the order g++ did (a call's last argument
// first: range, colour, position), so its cases are unchanged
// (tests/check/hard_case_pins_test.cpp). Braced lists ({in(), in()}) are evaluated left to right
// and may draw several times.
struct Placer {
  SceneRandom rng;
  explicit Placer(uint32_t seed) : rng(seed) {}
  float in(float lo, float hi) { return rng.uniform(lo, hi); }
  glm::vec3 in(glm::vec3 lo, glm::vec3 hi) {
    return {in(lo.x, hi.x), in(lo.y, hi.y), in(lo.z, hi.z)};
  }
  // log-uniform in [lo, hi]
  float logIn(float lo, float hi) { return std::exp(in(std::log(lo), std::log(hi))); }
  glm::vec3 color() { return {in(0.2f, 1.0f), in(0.2f, 1.0f), in(0.2f, 1.0f)}; }
};

// World position of a point given in the room camera's view space.
glm::vec3 fromView(const SceneCamera& camera, glm::dvec3 view) {
  return glm::vec3(glm::inverse(camera.viewFromWorld) * glm::dvec4(view, 1.0));
}

// The point of the plane (point `o`, normal `n`) that pixel (x, y)'s centre sees, for the room
// camera at width x height; the view-ray parameter through kernels/shading.h's pixel centres.
glm::dvec3 pixelOnPlane(const SceneCamera& camera, int width, int height, double x, double y,
                        glm::dvec3 o, glm::dvec3 n) {
  double tanY = std::tan(0.5 * double(camera.yfov)), tanX = tanY * double(width) / double(height);
  glm::dvec3 dirView((2.0 * (x + 0.5) / width - 1.0) * tanX,
                     (1.0 - 2.0 * (y + 0.5) / height) * tanY, -1.0);
  glm::dmat4 worldFromView = glm::inverse(camera.viewFromWorld);
  glm::dvec3 eye(worldFromView[3]), dir = glm::dmat3(worldFromView) * dirView;
  double t = glm::dot(o - eye, n) / glm::dot(dir, n);
  return eye + t * dir;
}

// ---- cases ---------------------------------------------------------------------------------

HardCaseFrame lightsBehindCamera() {
  Scene s = room("lights-behind-camera");
  Placer p(11);
  for (int i = 0; i < 40; ++i) {  // behind the eye (z > 4), most reaching into the room
    const float range = i % 4 ? p.in(6.0f, 25.0f) : p.in(0.5f, 3.0f);
    const glm::vec3 color = p.color();
    const glm::vec3 at = p.in({-6, 0.5f, 4.2f}, {6, 4, 12});
    s.lights.push_back(SceneLight::point(at, color, range));
  }
  return frameOf(std::move(s));
}

HardCaseFrame lightsStraddlingNearPlane() {
  Scene s = room("lights-straddling-near-plane");
  SceneCamera c = roomCamera();
  Placer p(12);
  // View-space depths around the near plane (w = 0.1): on it, on the eye, just either side.
  const double depths[] = {0.1, 0.0, 0.0999, 0.1001, -0.05, 0.05, 0.3, -0.3};
  for (int i = 0; i < 48; ++i) {
    double w = depths[i % 8];
    const float y = p.in(-0.3f, 0.3f);
    const float x = p.in(-0.4f, 0.4f);
    const float range = p.logIn(0.05f, 12.0f);
    const glm::vec3 color = p.color();
    s.lights.push_back(SceneLight::point(fromView(c, glm::dvec3(x, y, -w)), color, range));
  }
  return frameOf(std::move(s));
}

HardCaseFrame lightsAroundCamera() {
  Scene s = room("lights-around-camera");
  Placer p(13);
  for (int i = 0; i < 32; ++i) {
    glm::vec3 dir = glm::normalize(p.in(glm::vec3(-1.0f), glm::vec3(1.0f)) + glm::vec3(1e-3f));
    const float range = p.in(1.0f, 9.0f);
    const glm::vec3 color = p.color();
    const float distance = p.in(0.3f, 3.0f);
    s.lights.push_back(SceneLight::point(glm::vec3(kEye) + distance * dir, color, range));
  }
  return frameOf(std::move(s));
}

// Lights on the floor at pixel centres' surface points (a light reaches about one pixel) and a
// hair above them, with ranges from 1e-6 to 1e-2.
HardCaseFrame rangesTiny() {
  Scene s = room("ranges-tiny");
  SceneCamera c = roomCamera();
  Placer p(14);
  for (int i = 0; i < 200; ++i) {
    double x = std::floor(p.in(0.0f, 64.0f)), y = std::floor(p.in(30.0f, 48.0f));
    glm::dvec3 at = pixelOnPlane(c, 64, 48, x, y, {0, 0, 0}, {0, 1, 0});
    at.y += i % 2 ? 0.0 : 1e-6 * double(i % 7);
    const float range = p.logIn(1e-6f, 1e-2f);
    const glm::vec3 color = p.color();
    s.lights.push_back(SceneLight::point(glm::vec3(at), color, range));
  }
  return frameOf(std::move(s));
}

HardCaseFrame rangesHuge() {
  Scene s = room("ranges-huge");
  Placer p(15);
  for (int i = 0; i < 24; ++i) {
    const float range = p.logIn(1e3f, 1e6f);
    const glm::vec3 color = 0.05f * p.color();
    const glm::vec3 at = p.in({-30, -5, -60}, {30, 20, 30});
    s.lights.push_back(SceneLight::point(at, color, range));
  }
  return frameOf(std::move(s));
}

HardCaseFrame rangesMixed() {
  Scene s = room("ranges-1e-6-to-1e6");
  Placer p(16);
  for (int i = 0; i < 120; ++i) {
    const float range = p.logIn(1e-6f, 1e6f);
    const glm::vec3 color = 0.1f * p.color();
    const glm::vec3 at = p.in({-8, 0, -14}, {8, 5, 6});
    s.lights.push_back(SceneLight::point(at, color, range));
  }
  return frameOf(std::move(s));
}

HardCaseFrame lightsOnSurfaces() {
  Scene s = room("lights-on-surfaces");
  Placer p(17);
  for (int i = 0; i < 60; ++i) {
    glm::vec3 at;
    switch (i % 4) {
      case 0: at = {p.in(-8.0f, 8.0f), 0.0f, p.in(-20.0f, 2.0f)}; break;  // floor
      case 1: at = {p.in(-8.0f, 8.0f), p.in(0.0f, 6.0f), -12.0f}; break;  // back wall
      case 2: at = {p.in(-1.0f, 1.0f), 2.0f, p.in(-6.0f, -4.0f)}; break;  // box top
      default: at = {p.in(-1.0f, 1.0f), p.in(0.0f, 2.0f), -4.0f}; break;  // box front
    }
    const float range = p.in(1.0f, 6.0f);
    const glm::vec3 color = p.color();
    s.lights.push_back(SceneLight::point(at, color, range));
  }
  return frameOf(std::move(s));
}

HardCaseFrame lightsAtVertices() {
  Scene s = room("lights-at-vertices");
  Placer p(18);
  for (size_t i = 0; i < s.vertices.size(); i += 7) {
    const float range = p.in(0.5f, 5.0f);
    const glm::vec3 color = p.color();
    s.lights.push_back(SceneLight::point(s.vertices[i].position, color, range));
  }
  return frameOf(std::move(s));
}

// Issue #12 item 4: lights in the floor's and the back wall's planes (N.l ~ 0, rounding to
// either sign), inside and beyond the surfaces' extent.
HardCaseFrame lightsInSurfacePlanes() {
  Scene s = room("lights-in-surface-planes");
  Placer p(19);
  for (int i = 0; i < 60; ++i) {
    float tiny = i % 3 == 0 ? 0.0f : (i % 3 == 1 ? 1e-6f : -1e-6f);
    glm::vec3 at;
    if (i % 2) {  // the floor's plane
      const float z = p.in(-24.0f, 6.0f);
      const float x = p.in(-12.0f, 12.0f);
      at = {x, tiny, z};
    } else {  // the back wall's
      const float y = p.in(0.0f, 8.0f);
      const float x = p.in(-12.0f, 12.0f);
      at = {x, y, -12.0f + tiny};
    }
    const float range = p.in(3.0f, 12.0f);
    const glm::vec3 color = p.color();
    s.lights.push_back(SceneLight::point(at, color, range));
  }
  return frameOf(std::move(s));
}

// The eye a hair above a long floor, looking along it: every floor pixel is seen at a grazing
// angle (N.V ~ 1e-3).
HardCaseFrame grazingView() {
  Scene s = room("grazing-view");
  s.cameraPath = {
      SceneCamera::lookAt({0.0, 0.01, 1.9}, {0.0, 0.01, -100.0}, {0, 1, 0}, 1.0f, 0.005f, 100.0f)};
  Placer p(20);
  for (int i = 0; i < 40; ++i) {
    const float range = p.in(1.0f, 10.0f);
    const glm::vec3 color = p.color();
    const glm::vec3 at = p.in({-8, 0.01f, -20}, {8, 2, 2});
    s.lights.push_back(SceneLight::point(at, color, range));
  }
  return frameOf(std::move(s));
}

// The panel's back (normals away from the eye) lit from behind it and from in front.
HardCaseFrame backFacingNormals() {
  Scene s = room("back-facing-normals");
  Placer p(21);
  for (int i = 0; i < 30; ++i) {
    float z = i % 2 ? p.in(-6.0f, -3.001f) : p.in(-2.999f, 2.0f);
    const float range = p.in(1.0f, 8.0f);
    const glm::vec3 color = p.color();
    const glm::vec3 at = {p.in(-5.0f, -1.0f), p.in(0.2f, 3.0f), z};
    s.lights.push_back(SceneLight::point(at, color, range));
  }
  return frameOf(std::move(s));
}

// Lights straight behind surface points on their pixel's view ray (l = -V): the half vector
// l + V is zero there. Behind the panel the normal faces the light (N.l > 0), so the degenerate
// half vector is shaded; behind the floor and wall N.l < 0.
HardCaseFrame lightOppositeView() {
  Scene s = room("light-opposite-view");
  SceneCamera c = roomCamera();
  Placer p(22);
  for (int i = 0; i < 40; ++i) {
    double x = std::floor(p.in(0.0f, 64.0f)), y = std::floor(p.in(0.0f, 48.0f));
    bool panel = i % 2 == 0;
    if (panel) x = std::floor(p.in(14.0f, 22.0f)), y = std::floor(p.in(14.0f, 28.0f));
    glm::dvec3 at = panel ? pixelOnPlane(c, 64, 48, x, y, {0, 0, -3}, {0, 0, 1})
                          : pixelOnPlane(c, 64, 48, x, y, {0, 0, 0}, {0, 1, 0});
    glm::dvec3 away = glm::normalize(at - kEye);
    const float range = p.in(2.0f, 8.0f);
    const glm::vec3 color = p.color();
    const float behind = p.in(0.01f, 2.0f);
    s.lights.push_back(SceneLight::point(glm::vec3(at + double(behind) * away), color, range));
  }
  return frameOf(std::move(s));
}

// The same room `offset` away from the origin: positions are first rounded to 1/16 (the float
// spacing at 1e6, and a multiple of it at 1e5), so both copies hold exactly the same geometry and
// lights in float; only the camera-relative arithmetic can tell them apart.
HardCaseFrame farFromOrigin(const std::string& name, double offset) {
  auto snap = [](glm::vec3 v) { return glm::round(v * 16.0f) / 16.0f; };
  Scene atOrigin = room(name);
  Placer p(23);
  for (int i = 0; i < 40; ++i) {
    const float range = p.in(2.0f, 10.0f);
    const glm::vec3 color = p.color();
    const glm::vec3 at = p.in({-8, 0.2f, -14}, {8, 5, 4});
    atOrigin.lights.push_back(SceneLight::point(at, color, range));
  }
  for (auto& v : atOrigin.vertices) v.position = snap(v.position);
  for (auto& l : atOrigin.lights) l.position = snap(l.position);
  Scene moved = atOrigin;
  const glm::dvec3 shift(offset, offset, -offset);
  for (auto& v : moved.vertices) v.position = glm::vec3(glm::dvec3(v.position) + shift);
  for (auto& l : moved.lights) l.position = glm::vec3(glm::dvec3(l.position) + shift);
  moved.cameraPath = {
      SceneCamera::lookAt(kEye + shift, kTarget + shift, {0, 1, 0}, 1.0f, 0.1f, 100.0f)};
  HardCaseFrame f = frameOf(std::move(moved));
  f.referenceScene = std::move(atOrigin);
  return f;
}

HardCaseFrame nearFar(const std::string& name, float znear, float zfar) {
  Scene s = room(name);
  s.cameraPath = {roomCamera(znear, zfar)};
  Placer p(24);
  for (int i = 0; i < 40; ++i) {
    const float range = p.in(1.0f, 10.0f);
    const glm::vec3 color = p.color();
    const glm::vec3 at = p.in({-8, 0.2f, -14}, {8, 5, 4});
    s.lights.push_back(SceneLight::point(at, color, range));
  }
  return frameOf(std::move(s));
}

HardCaseFrame litRoom(const std::string& name, int width, int height) {
  Scene s = room(name);
  Placer p(25);
  for (int i = 0; i < 40; ++i) {
    const float range = p.in(1.0f, 10.0f);
    const glm::vec3 color = p.color();
    const glm::vec3 at = p.in({-8, 0.2f, -14}, {8, 5, 4});
    s.lights.push_back(SceneLight::point(at, color, range));
  }
  return frameOf(std::move(s), width, height);
}

HardCaseFrame noLights() { return frameOf(room("no-lights")); }

// 1e5 small lights through the room's volume: long lists, most lights culled.
HardCaseFrame hundredThousandLights() {
  Scene s = room("lights-1e5");
  Placer p(26);
  for (int i = 0; i < 100000; ++i) {
    const float range = p.logIn(0.02f, 0.5f);
    const glm::vec3 color = 0.05f * p.color();
    const glm::vec3 at = p.in({-8, 0, -14}, {8, 5, 4});
    s.lights.push_back(SceneLight::point(at, color, range));
  }
  return frameOf(std::move(s), 48, 32);
}

// One 16x16 tile lit by 1e4 lights that all reach it: beyond tiled-single's local list (40
// chunks) and any presized list (the lists start small and grow), in every lanes width.
HardCaseFrame tenThousandLightsInOneTile() {
  Scene s = room("lights-1e4-one-tile");
  Placer p(27);
  for (int i = 0; i < 10000; ++i) {
    const glm::vec3 color = 1e-3f * p.color();
    const glm::vec3 at = p.in({-8, 0.2f, -14}, {8, 5, 4});
    s.lights.push_back(SceneLight::point(at, color, 1000.0f));
  }
  HardCaseFrame f = frameOf(std::move(s), 16, 16);
  f.config.presizeLists = false;
  f.lanes = {1, 2, 4, 8, 16};
  return f;
}

// Values beyond half's range and below its normal range in the G-buffer: emission 1e5 (half's
// largest is 65504), shininess 1e5, diffuse and specular 1e-6 and 3e-8 (half denormals, and below
// them). fp16 storage clamps to +-65504 (docs/accuracy.md); the reference shades the stored values.
HardCaseFrame fp16Extremes() {
  Scene s = room("fp16-overflow-denormals");
  s.materials[0].emissive = glm::vec3(1e5f, 7e4f, 65504.0f);
  s.materials[0].shininess = 1e5f;
  s.materials[1].diffuse = glm::vec3(1e-6f, 3e-8f, 6e-5f);
  s.materials[1].specular = glm::vec3(3e-8f, 1e-6f, 1e-5f);
  s.materials[1].emissive = glm::vec3(1e-7f);
  Placer p(28);
  for (int i = 0; i < 30; ++i) {
    const float range = p.in(1.0f, 10.0f);
    const glm::vec3 color = p.color();
    const glm::vec3 at = p.in({-8, 0.2f, -14}, {8, 5, 4});
    s.lights.push_back(SceneLight::point(at, color, range));
  }
  return frameOf(std::move(s));
}

// Light colours and materials near the top of fp32's range (the scene's shading bound 7e36, just
// under what prepareFrame accepts: src/scene/shading_range.h) and near the bottom (products
// ~1e-36, still normal floats).
HardCaseFrame extremeValues(const std::string& name, float color, float material) {
  Scene s = room(name);
  for (auto& m : s.materials) {
    m.diffuse *= material;
    m.specular *= material;
  }
  Placer p(29);
  for (int i = 0; i < 30; ++i) {
    const float range = p.in(1.0f, 10.0f);
    const glm::vec3 lightColor = color * p.color();
    const glm::vec3 at = p.in({-8, 0.2f, -14}, {8, 5, 4});
    s.lights.push_back(SceneLight::point(at, lightColor, range));
  }
  return frameOf(std::move(s));
}

// Spot lights against the camera: the eye inside cones, cones behind it and with their apex on
// the near plane, cones seen edge-on, from 1 degree to 89 degrees wide, and cones lying in the
// floor's plane (the cone's edge grazing the floor).
HardCaseFrame spotLights() {
  Scene s = room("spot-lights");
  SceneCamera c = roomCamera();
  Placer p(30);
  const glm::vec3 eye(kEye), ahead = glm::normalize(glm::vec3(kTarget - kEye));
  const glm::vec3 side = glm::normalize(glm::cross(ahead, glm::vec3(0, 1, 0)));
  constexpr float kDeg = 0.01745329252f;
  auto spot = [&](glm::vec3 at, glm::vec3 axis, float outerDeg, float range) {
    float outer = outerDeg * kDeg;
    s.lights.push_back(
        SceneLight::spot(at, glm::normalize(axis), p.color(), range, 0.7f * outer, outer));
  };
  spot(eye + glm::vec3(0, 1, 0), -ahead - glm::vec3(0, 0.5f, 0), 40, 12);  // the eye inside
  spot(eye - 3.0f * ahead, ahead, 20, 20);                                 // behind, past the eye
  spot(glm::vec3(fromView(c, {0.05, -0.02, -0.1})), ahead, 60, 15);        // apex on the near plane
  spot(eye + 4.0f * ahead, side, 10, 10);                                  // edge-on, narrow
  spot(eye + 6.0f * ahead - 3.0f * side, side, 89, 10);                    // edge-on, almost flat
  spot({0, 1e-6f, -2}, {0, 0, -1}, 30, 12);                                // its axis in the floor
  for (int i = 0; i < 40; ++i) {                                           // anywhere, any width
    const float range = p.in(2.0f, 15.0f);
    const float outerDeg = p.logIn(1.0f, 89.0f);
    const glm::vec3 axis = p.in(glm::vec3(-1.0f), glm::vec3(1.0f)) + 1e-3f;
    const glm::vec3 at = p.in({-8, 0.1f, -14}, {8, 5, 4});
    spot(at, axis, outerDeg, range);  // its colour drawn last, in spot()
  }
  return frameOf(std::move(s));
}

// Directional lights: a sun from above, suns grazing the floor (in its plane, 1e-6 above and
// below it), one from below, and point lights among them.
HardCaseFrame directionalLights() {
  Scene s = room("directional-lights");
  Placer p(31);
  s.lights.push_back(
      SceneLight::directional(glm::normalize(glm::vec3(0.3f, -1.0f, 0.2f)), p.color()));
  for (float lift : {0.0f, 1e-6f, -1e-6f})
    s.lights.push_back(
        SceneLight::directional(glm::normalize(glm::vec3(1.0f, lift, -0.5f)), p.color()));
  s.lights.push_back(SceneLight::directional({0.0f, 1.0f, 0.0f}, p.color()));
  for (int i = 0; i < 20; ++i) {
    const float range = p.in(1.0f, 10.0f);
    const glm::vec3 color = p.color();
    const glm::vec3 at = p.in({-8, 0.2f, -14}, {8, 5, 4});
    s.lights.push_back(SceneLight::point(at, color, range));
  }
  return frameOf(std::move(s));
}

// glTF's metallic-roughness model at its ends: roughness 0 (clamped to 0.045) and 1, metallic 0
// and 1, lights at the floor's mirror directions (the GGX peak), grazing the floor, in its plane
// and on it.
HardCaseFrame metallicRoughness() {
  Scene s = room("metallic-roughness");
  const float roughness[] = {0.0f, 1.0f, 0.0f, 1.0f};
  const float metallic[] = {0.0f, 0.0f, 1.0f, 1.0f};
  std::vector<Material> ends;
  for (int k = 0; k < 4; ++k) {
    Material m;
    m.name = "mr" + std::to_string(k);
    m.model = ShadingModel::MetallicRoughness;
    m.baseColor = {0.9f, 0.6f, 0.3f};
    m.roughness = roughness[k];
    m.metallic = metallic[k];
    ends.push_back(m);
  }
  s.materials = ends;  // the floor and wall get ends 0, the box and sphere 1-3 by triangle
  for (size_t t = 0; t < s.triangleMaterial.size(); ++t)
    s.triangleMaterial[t] = uint32_t(t < 4 ? 0 : 1 + t % 3);
  SceneCamera c = roomCamera();
  Placer p(32);
  for (int i = 0; i < 48; ++i) {
    double x = std::floor(p.in(0.0f, 64.0f)), y = std::floor(p.in(30.0f, 48.0f));
    glm::dvec3 at = pixelOnPlane(c, 64, 48, x, y, {0, 0, 0}, {0, 1, 0});
    glm::dvec3 toEye = glm::normalize(kEye - at);
    glm::dvec3 mirror(-toEye.x, toEye.y, -toEye.z);  // the eye's direction mirrored in the floor
    glm::dvec3 where = at;                           // on it
    if (i % 4 == 0) {
      where = at + 2.0 * mirror;  // GGX peak
    } else if (i % 4 == 1) {
      where = at + glm::dvec3(2.0, 1e-6 * (i % 3), 0.5);  // grazing
    } else if (i % 4 == 3) {
      const float up = p.in(0.2f, 3.0f);
      const float aside = p.in(-2.0f, 2.0f);
      where = at + glm::dvec3(aside, up, 1.0);
    }
    const float range = p.in(3.0f, 10.0f);
    const glm::vec3 color = p.color();
    s.lights.push_back(SceneLight::point(glm::vec3(where), color, range));
  }
  return frameOf(std::move(s));
}

}  // namespace

const std::vector<HardCase>& hardCases() {
  static const std::vector<HardCase> cases = {
      {"lights-behind-camera", "40 lights behind the eye, most reaching into the view",
       lightsBehindCamera},
      {"lights-straddling-near-plane",
       "48 lights centred on, just before and behind the near plane and on the eye",
       lightsStraddlingNearPlane},
      {"lights-around-camera", "32 lights 0.3-3 units around the eye: the eye inside their volumes",
       lightsAroundCamera},
      {"ranges-tiny", "200 lights of range 1e-6..1e-2 on (or 1e-6 above) pixels' floor points",
       rangesTiny},
      {"ranges-huge", "24 lights of range 1e3..1e6", rangesHuge},
      {"ranges-1e-6-to-1e6", "120 lights, ranges log-uniform in 1e-6..1e6", rangesMixed},
      {"lights-on-surfaces", "60 lights lying on the floor, the wall and the box",
       lightsOnSurfaces},
      {"lights-at-vertices", "lights at every 7th mesh vertex", lightsAtVertices},
      {"lights-in-surface-planes",
       "60 lights in the floor's and the wall's planes (0, +-1e-6 off), inside and beyond them",
       lightsInSurfacePlanes},
      {"grazing-view", "the eye 0.01 above a long floor, looking along it", grazingView},
      {"back-facing-normals", "a single-sided panel seen from behind, lit from both sides",
       backFacingNormals},
      {"light-opposite-view",
       "lights on pixels' view rays behind the surface (l = -V: zero half vector)",
       lightOppositeView},
      {"far-from-origin-1e5", "the room 1e5 from the origin against the room at the origin",
       [] { return farFromOrigin("far-from-origin-1e5", 1e5); }},
      {"far-from-origin-1e6", "the room 1e6 from the origin against the room at the origin",
       [] { return farFromOrigin("far-from-origin-1e6", 1e6); }},
      {"near-far-1e6", "near plane 1e-4, far plane 100 (ratio 1e6)",
       [] { return nearFar("near-far-1e6", 1e-4f, 100.0f); }},
      {"near-far-1e9", "near plane 1e-7, far plane 100 (ratio 1e9)",
       [] { return nearFar("near-far-1e9", 1e-7f, 100.0f); }},
      {"resolution-1x1", "one pixel", [] { return litRoom("resolution-1x1", 1, 1); }},
      {"resolution-1x37", "one column", [] { return litRoom("resolution-1x37", 1, 37); }},
      {"resolution-53x1", "one row", [] { return litRoom("resolution-53x1", 53, 1); }},
      {"resolution-61x35", "no multiple of the 16x16 tile",
       [] { return litRoom("resolution-61x35", 61, 35); }},
      {"tiles-7x5", "61x35 in 7x5 tiles (35 work-items, no whole vector of 16)",
       [] {
         HardCaseFrame f = litRoom("tiles-7x5", 61, 35);
         f.config.tileWidth = 7;
         f.config.tileHeight = 5;
         return f;
       }},
      {"no-lights", "no light at all", noLights},
      {"lights-1e5", "1e5 lights of range 0.02..0.5 through the room, 48x32",
       hundredThousandLights},
      {"lights-1e4-one-tile",
       "1e4 lights reaching one 16x16 tile: lists grown, 40 local chunks, every lanes width",
       tenThousandLightsInOneTile},
      {"fp16-overflow-denormals", "emission and shininess beyond half's range, half denormals",
       fp16Extremes},
      {"values-near-fp32-max", "light colours 2e28, materials x1e5 (shading bound 7e36)",
       [] { return extremeValues("values-near-fp32-max", 2e28f, 1e5f); }},
      {"values-near-fp32-min", "light colours 1e-25, materials x1e-10 (products ~1e-36)",
       [] { return extremeValues("values-near-fp32-min", 1e-25f, 1e-10f); }},
      {"spot-lights",
       "46 spot lights, 1-89 degrees: the eye inside cones, cones behind it, on the near plane, "
       "edge-on, in the floor's plane",
       spotLights},
      {"directional-lights",
       "suns from above, from below and grazing the floor (in its plane, 1e-6 off), with 20 "
       "point lights",
       directionalLights},
      {"metallic-roughness",
       "glTF's model at roughness 0 and 1, metallic 0 and 1: lights at the floor's mirror "
       "directions, grazing it, on it",
       metallicRoughness},
#ifndef TILESHADE_NO_OIIO  // the files are an EXR
      {"import-reversed-z",
       "lights-straddling-near-plane through another renderer's files: reversed-Z depth with an "
       "infinite far plane, unorm normals, rows bottom first (--gbuffer-in's reader)",
       [] {
         HardCaseFrame f = lightsStraddlingNearPlane();
         f.throughImport = true;
         return f;
       }},
#endif
  };
  return cases;
}

}  // namespace ts
