// The frame's shadow maps one light at a time (src/raster/per_light_shadows.cpp, --shadow-storage
// per-light): the passes (the directional lights together, then one per point or spot light), each
// a strip of its light's faces; every texel of every pass equals the atlas's texel at the same
// place of the same face, and the face table points each face into its strip.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "raster/per_light_shadows.h"
#include "scene/view_space_lights.h"
#include "shading/shading_cpu.h"
#include "shading/view_lights.h"
#include "test_scenes.h"
#include "util/error.h"

namespace ts {
namespace {

Scene litFloorAndBox() {
  using test::casting;
  Scene s = test::floorAndBox();
  s.lights.push_back(casting(SceneLight::point({1.5, 4.0, 0.5}, glm::vec3(8.0f), 20.0f)));
  s.lights.push_back(SceneLight::point({4.0, 1.0, 4.0}, glm::vec3(2.0f), 8.0f));  // casts none
  s.lights.push_back(casting(SceneLight::spot({-3.0, 5.0, 2.0}, {0.5f, -1.0f, -0.3f},
                                              glm::vec3(10.0f), 20.0f, 0.3f, 0.7f)));
  s.lights.push_back(casting(SceneLight::directional({-0.3f, -1.0f, -0.4f}, glm::vec3(0.5f))));
  s.lights.push_back(casting(SceneLight::directional({0.2f, -1.0f, 0.1f}, glm::vec3(0.5f))));
  return s;
}

ShadowAtlasLayout smallLayout(const Scene& s) {
  ShadowAtlasOptions o;
  o.mapSize = 32;  // directional faces 128
  return planShadowAtlas(s.lights, s.bounds(), s.cameraPath[0], o);
}

TEST(PerLightShadowMaps, EachPassHoldsTheAtlasTexelsOfItsLightsFaces) {
  const Scene scene = litFloorAndBox();
  const ShadowAtlasLayout layout = smallLayout(scene);
  const ShadowAtlas atlas = drawShadowAtlas(scene, layout, 2);
  const PerLightShadowMaps maps(scene, layout);
  // The point light (6 faces), the spot light (1), the two directional ones together.
  const ShadowPass& point = maps.passOf(0);
  const ShadowPass& spot = maps.passOf(6);
  ASSERT_NE(maps.directionalPass(), nullptr);
  const ShadowPass& directional = *maps.directionalPass();
  EXPECT_EQ(point.faces, (std::vector<size_t>{0, 1, 2, 3, 4, 5}));
  EXPECT_EQ(spot.faces, (std::vector<size_t>{6}));
  EXPECT_EQ(directional.faces, (std::vector<size_t>{7, 8}));
  // Exactly its faces' texels: a strip as wide as the faces together.
  EXPECT_EQ(point.layout.width, 6 * 32);
  EXPECT_EQ(point.layout.height, 32);
  EXPECT_EQ(directional.layout.width, 2 * 128);
  EXPECT_EQ(maps.residentBytes(), uint64_t(2 * 128 * 128 * 4));  // the directional pass
  EXPECT_LT(maps.residentBytes(), layout.bytes());
  size_t faces = 0;
  for (const ShadowPass* pass : {&point, &spot, &directional}) {
    const ShadowAtlas strip = maps.draw(*pass, 1);
    ASSERT_EQ(strip.depth.size(), size_t(pass->layout.width) * size_t(pass->layout.height));
    size_t drawn = 0;  // texels nearer than far over the pass (a cube's +Y face sees nothing)
    for (size_t k = 0; k < pass->faces.size(); ++k) {
      const ShadowFace& in = layout.faces[pass->faces[k]];
      const ShadowFace& own = pass->layout.faces[k];
      ASSERT_EQ(in.size, own.size);
      EXPECT_EQ(in.light, own.light);
      EXPECT_EQ(in.face, own.face);
      size_t differing = 0;
      for (int y = 0; y < in.size; ++y)
        for (int x = 0; x < in.size; ++x) {
          const float a = atlas.at(in.x + x, in.y + y), b = strip.at(own.x + x, own.y + y);
          differing += a != b;
          drawn += a < float(in.view.zfar);
        }
      EXPECT_EQ(differing, 0u) << "face " << pass->faces[k];
      EXPECT_EQ(strip.faceTriangles[k], atlas.faceTriangles[pass->faces[k]]);
      ++faces;
    }
    EXPECT_GT(drawn, 0u) << "a pass that sees nothing: a weak test";
  }
  EXPECT_EQ(faces, layout.faces.size());
}

TEST(PerLightShadowMaps, TheFaceTablePointsIntoEachPassesStrip) {
  const Scene scene = litFloorAndBox();
  const ShadowAtlasLayout layout = smallLayout(scene);
  auto atlas = std::make_shared<const ShadowAtlas>(drawShadowAtlas(scene, layout, 1));
  ViewLights lights = toViewSpace(scene.lights, scene.cameraPath[0].viewFromWorld);
  attachShadowMaps(atlas, scene.lights, scene.cameraPath[0].viewFromWorld, ShadowSampling{},
                   lights);
  const PerLightShadowMaps maps(scene, layout);
  const std::vector<glm::vec4> table = maps.passFaceTable(lights.shadowFaces);
  ASSERT_EQ(table.size(), lights.shadowFaces.size());
  for (size_t f = 0; f < layout.faces.size(); ++f)
    for (int r = 0; r < TS_SHADOW_FACE_RECORDS; ++r) {
      const size_t i = f * TS_SHADOW_FACE_RECORDS + size_t(r);
      if (r != 4) {
        EXPECT_EQ(table[i], lights.shadowFaces[i]) << "face " << f << " record " << r;
        continue;
      }
      // The rectangle: the face's place in its pass, the pass's width as the stride.
      const bool isDirectional =
          scene.lights[layout.faces[f].light].type == SceneLightType::Directional;
      // A light's faces are consecutive: its first is f less the cube face's index.
      const ShadowPass& pass =
          isDirectional ? *maps.directionalPass() : maps.passOf(int(f) - layout.faces[f].face);
      const auto k =
          size_t(std::find(pass.faces.begin(), pass.faces.end(), f) - pass.faces.begin());
      ASSERT_LT(k, pass.faces.size());
      EXPECT_EQ(table[i], glm::vec4(float(pass.layout.faces[k].x), 0.0f,
                                    float(layout.faces[f].size), float(pass.layout.width)));
    }
  // A face that starts no point or spot light's pass.
  EXPECT_THROW(maps.passOf(1), Error);   // the cube's second face
  EXPECT_THROW(maps.passOf(7), Error);   // a directional face
  EXPECT_THROW(maps.passOf(-1), Error);  // casts none
}

}  // namespace
}  // namespace ts
