// Pinned values of every built-in scene and light set (seed 1): a compiler or standard library
// that draws the scene's random numbers in another order, or maps them differently, builds another
// scene and fails here (scenes/README.md promises the same scene on any of them). The values are
// what g++/libstdc++ built before the draws became named locals (SceneRandom, mesh_builder.h).
#include <vector>

#include <gtest/gtest.h>

#include "scene/scene_loader.h"

namespace {

struct Vec {
  float x, y, z;
};

struct LightPin {
  size_t index;
  Vec position, color;
  float range;
};

struct VertexPin {
  size_t index;
  Vec position;
};

// Exact comparison, through double so that it holds whether the scene stores float or double.
template <typename V>
void expectExactly(const Vec& pinned, const V& actual, const char* what) {
  SCOPED_TRACE(what);
  EXPECT_EQ(double(actual.x), double(pinned.x));
  EXPECT_EQ(double(actual.y), double(pinned.y));
  EXPECT_EQ(double(actual.z), double(pinned.z));
}

void expectLights(const std::string& scene, const std::string& set, size_t count,
                  const std::vector<LightPin>& pins) {
  SCOPED_TRACE(scene + "/" + set);
  const ts::Scene s = ts::makeBuiltinScene(scene, set, 1);
  ASSERT_EQ(s.lights.size(), count);
  for (const LightPin& p : pins) {
    SCOPED_TRACE("light " + std::to_string(p.index));
    expectExactly(p.position, s.lights[p.index].position, "position");
    expectExactly(p.color, s.lights[p.index].color, "colour");
    EXPECT_EQ(double(s.lights[p.index].range), double(p.range));
  }
}

// Vertices that depend on the random numbers (they move with the seed): buildings and robots of
// the street, curtains and planters of the atrium.
void expectVertices(const std::string& scene, size_t count, const std::vector<VertexPin>& pins) {
  SCOPED_TRACE(scene);
  const ts::Scene s = ts::makeBuiltinScene(scene, "", 1);
  const ts::Scene other = ts::makeBuiltinScene(scene, "", 8);
  ASSERT_EQ(s.vertices.size(), count);
  for (const VertexPin& p : pins) {
    SCOPED_TRACE("vertex " + std::to_string(p.index));
    expectExactly(p.position, s.vertices[p.index].position, "position");
    ASSERT_LT(p.index, other.vertices.size());
    EXPECT_NE(s.vertices[p.index].position, other.vertices[p.index].position)
        << "the pin should be a vertex the random numbers place";
  }
}

TEST(BuiltinScenePins, StreetGeometry) {
  expectVertices("street", 17602,
                 {{165, {-14.5500002f, 0.0f, -115.786591f}},
                  {8571, {-7.02063894f, 2.38035297f, -118.098076f}},
                  {16978, {8.17981529f, 0.60006839f, 121.342422f}}});
}

TEST(BuiltinScenePins, StreetLights) {
  expectLights(
      "street", "many", 924,
      {{0, {-7.91891098f, 1.72359824f, -148.214279f}, {2.07802725f, 2.5f, 0.363058299f}, 12.5f},
       {1, {-7.33159733f, 2.44498348f, -148.214279f}, {1.89754939f, 1.09720469f, 2.5f}, 12.5f},
       {463, {-3.62511873f, 4.40969276f, 1.78570557f}, {2.5f, 2.39851856f, 0.821306407f}, 12.5f},
       {923, {6.13430691f, 3.80809593f, 148.214294f}, {1.22894406f, 2.01803255f, 2.5f}, 12.5f}});
  expectLights(
      "street", "few", 11,
      {{0, {-6.04989719f, 4.90219116f, -118.780418f}, {35.0f, 28.6709557f, 34.9184608f}, 40.0f},
       {6, {2.52939868f, 4.88870096f, 21.8137093f}, {35.0f, 28.2192211f, 31.5549736f}, 40.0f},
       {10, {6.76678085f, 4.32155752f, 122.124596f}, {32.2592964f, 30.0575638f, 35.0f}, 40.0f}});
}

TEST(BuiltinScenePins, AtriumGeometry) {
  expectVertices("atrium", 21913,
                 {{18177, {-10.875f, 3.31381798f, -5.9000001f}},
                  {19268, {3.93963218f, 1.47258162f, -5.10867786f}},
                  {20359, {11.25f, 0.498511672f, 5.19999981f}}});
}

TEST(BuiltinScenePins, AtriumLights) {
  expectLights("atrium", "small", 128,
               {{0,
                 {11.8895798f, 1.13822603f, -4.68269205f},
                 {0.384169519f, 0.199937806f, 0.522847831f},
                 0.933495045f},
                {65,
                 {6.75475311f, 11.9882698f, -10.3498955f},
                 {1.83031428f, 0.473529428f, 2.18577814f},
                 1.90865493f},
                {127,
                 {-13.5806808f, 1.59337378f, 7.92935467f},
                 {0.91118747f, 0.140725568f, 0.435237467f},
                 1.23233342f}});
  expectLights("atrium", "big", 16,
               {{0,
                 {-0.437870026f, 2.73011708f, 7.64330101f},
                 {1.95023441f, 2.16109204f, 1.87381232f},
                 10.3949318f},
                {9,
                 {-9.02016354f, 4.22140026f, -4.48528004f},
                 {5.57904387f, 5.24279261f, 5.93012714f},
                 17.2193604f},
                {15,
                 {6.83826256f, 9.67129898f, -7.37618637f},
                 {2.71472979f, 3.41693616f, 2.32459879f},
                 13.070838f}});
  expectLights("atrium", "mixed", 128,
               {{0,
                 {-0.437870026f, 2.73011708f, 7.64330101f},
                 {1.95023441f, 2.16109204f, 1.87381232f},
                 10.3949318f},
                {1,
                 {11.5286484f, 1.19362283f, -5.96884346f},
                 {0.310769975f, 0.564548433f, 1.38121653f},
                 1.51724339f},
                {127,
                 {9.58399391f, 1.82848763f, -7.8122263f},
                 {0.127687737f, 0.152601674f, 0.288191199f},
                 0.693050265f}});
}

}  // namespace
