// Shadows in the forward techniques (issues #17, #18): the fragment shader samples the frame's
// shadow atlas with kernels/shadows.h compiled as GLSL, the file the kernels and the double
// reference use. Every forward technique with a shadow-casting point, spot and directional light
// over a floor with a box against the reference that samples the same maps (<= 1e-4 of the peak,
// 0 missed); the shadows there (pixels darker than unshadowed, none brighter); a light enclosed
// by a box adds exactly nothing. Skips, saying why, where no OpenGL context can be made.
#include <gtest/gtest.h>

#include <algorithm>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "cl/cl_context.h"
#include "gl_frame.h"
#include "raster/gl_program.h"
#include "raster/shadow_atlas.h"
#include "raster/shadow_maps.h"
#include "reference_check.h"
#include "require_gl.h"
#include "scene/scene_loader.h"
#include "test_scenes.h"
#include "util/file_read.h"

namespace ts {
namespace {

using test::GlFrame;

// Issue #17's bound for forward images (argued in gl_tiled_forward_test.cpp): the interpolated
// float position against the one rebuilt from depth, plus the fp32 sums.
constexpr double kForwardBound = 1e-4;

const char* const kForwardTechniques[] = {"forward", "forward-single", "tiled-forward",
                                          "tiled-forward-prez"};

using test::casting;

// The floor and box of tests/support/test_scenes.h with no ambient: a pixel is the sum of its
// lights.
Scene floorAndBox() { return test::floorAndBox(glm::vec3(0.0f)); }

// The maps of the scene's shadow-casting lights drawn for g's frame and attached to its lights,
// as `render` does (FrameShadows), with `taps` a side.
void attachMaps(GlFrame& g, const Scene& scene, int taps) {
  PreparedFrame& f = g.prepared;
  ASSERT_TRUE(f.features.shadows);
  const ShadowAtlasLayout layout =
      planShadowAtlas(scene.lights, scene.bounds(), f.camera, ShadowAtlasOptions{},
                      viewGeometryBounds(f.gbuffer, f.camera));
  const auto atlas = std::make_shared<ShadowAtlas>(drawShadowAtlas(scene, layout, 1));
  ShadowSampling sampling;
  sampling.taps = taps;
  attachShadowMaps(atlas, scene.lights, f.camera.viewFromWorld, sampling, f.lights);
  ASSERT_TRUE(f.lights.hasShadows());
}

// The same lights without any shadow map (the shader variant without shadows.h).
ViewLights withoutShadows(ViewLights lights) {
  std::fill(lights.shadow.begin(), lights.shadow.end(), -1);
  std::fill(lights.directionalShadow.begin(), lights.directionalShadow.end(), -1);
  lights.shadowFaces.clear();
  lights.shadowAtlas.reset();
  lights.shadowAtlasWidth = 0;
  return lights;
}

bool hasRow(const FrameResult& r, const std::string& name) {
  return std::any_of(r.kernels.begin(), r.kernels.end(),
                     [&](const KernelTime& k) { return k.name == name; });
}

// The GLSL build of the forward shader holds the kernels' kernels/shadows.h verbatim, and no
// second definition of its sampling before it.
TEST(ForwardShadows, FragmentSourceIsTheKernelsShadowsHeader) {
  const std::string header = readTextFile(kernelDir() + "/shadows.h", "shadows header");
  const std::string source = gl::shaderSource("tiled_forward.frag");
  const size_t at = source.find(header);
  ASSERT_NE(at, std::string::npos)
      << "tiled_forward.frag does not contain " << kernelDir() << "/shadows.h verbatim";
  EXPECT_EQ(source.find("ts_shadow_face("), at + header.find("ts_shadow_face("))
      << "a second definition of the shadow sampling before the header";
  EXPECT_NE(source.find("#if TS_HAS_SHADOWS"), std::string::npos);
}

// One shadow-casting light of each type (with a filter each) and a point light that casts none.
struct Case {
  const char* what;
  SceneLight light;
  int taps;
};

TEST(ForwardShadows, EveryForwardTechniqueMatchesTheReferenceWithEachLightType) {
  REQUIRE_GL();
  const Case cases[] = {
      {"point", SceneLight::point({1.5, 4.0, 0.5}, glm::vec3(8.0f), 20.0f), 3},
      {"spot",
       SceneLight::spot({-3.0, 5.0, 2.0}, {0.5f, -1.0f, -0.3f}, glm::vec3(10.0f), 20.0f, 0.3f,
                        0.7f),
       1},
      {"directional", SceneLight::directional({-0.3f, -1.0f, -0.4f}, glm::vec3(0.5f)), 2},
  };
  for (const Case& c : cases) {
    Scene scene = floorAndBox();
    scene.lights.push_back(casting(c.light));
    scene.lights.push_back(SceneLight::point({4.0, 1.0, 4.0}, glm::vec3(2.0f), 8.0f));
    GlFrame g(scene, 0, 96, 54);
    attachMaps(g, scene, c.taps);
    const ViewLights open = withoutShadows(g.prepared.lights);
    for (const char* technique : kForwardTechniques) {
      SCOPED_TRACE(std::string(technique) + ", shadow-casting " + c.what + " light");
      const FrameResult shadowed = g.render(technique);
      const ErrorStats e = test::expectMatchesReference(g, shadowed, kForwardBound);
      EXPECT_TRUE(hasRow(shadowed, "shadow_upload"));
      const FrameResult unshadowed = g.render(technique, open);
      EXPECT_FALSE(hasRow(unshadowed, "shadow_upload"));
      // A factor in [0, 1] times each term, the sums in the same order: no pixel gains light,
      // and the box's shadow takes it from some.
      size_t darker = 0, brighter = 0;
      for (size_t i = 0; i < shadowed.image.size(); ++i)
        for (int ch = 0; ch < 3; ++ch) {
          brighter += shadowed.image[i][ch] > unshadowed.image[i][ch];
          darker += shadowed.image[i][ch] < unshadowed.image[i][ch] - 1e-3f;
        }
      EXPECT_EQ(brighter, 0u);
      EXPECT_GT(darker, 30u);
      std::cout << "[ forward shadows ] " << technique << ", " << c.what << ": max error "
                << e.maxRelPeak << " of the peak, " << darker / 3 << "+ darker pixel channels\n";
    }
  }
}

// A point light inside the closed box lights nothing the camera sees: its terms are exactly 0,
// so the image is the one with the light's colour 0 (x + 0 = x), bit for bit; unshadowed, it
// lights the floor.
TEST(ForwardShadows, AFullyOccludedLightContributesNothing) {
  REQUIRE_GL();
  Scene scene = floorAndBox();
  scene.lights.push_back(casting(SceneLight::point({4.0, 5.0, 3.0}, glm::vec3(8.0f), 30.0f)));
  scene.lights.push_back(casting(SceneLight::point({0.2, 1.5, -0.1}, glm::vec3(8.0f), 30.0f)));
  GlFrame g(scene, 0, 96, 54);
  attachMaps(g, scene, 1);
  ViewLights dark = g.prepared.lights;
  ASSERT_EQ(dark.size(), 2u);
  dark.color[1] = glm::vec4(0.0f, 0.0f, 0.0f, dark.color[1].w);
  ViewLights open = g.prepared.lights;
  open.shadow[1] = -1;  // the enclosed light unshadowed
  for (const char* technique : kForwardTechniques) {
    SCOPED_TRACE(technique);
    const FrameResult enclosed = g.render(technique);
    const FrameResult none = g.render(technique, dark);
    ASSERT_EQ(enclosed.image.size(), none.image.size());
    EXPECT_TRUE(std::equal(enclosed.image.begin(), enclosed.image.end(), none.image.begin()));
    EXPECT_GT(test::relativeDifference(g.render(technique, open).image, none.image), 1e-3)
        << "unshadowed, the enclosed light reaches the floor";
    test::expectMatchesReference(g, enclosed, kForwardBound);
  }
}

// Issue #18's accuracy failure: the atrium at 640x360 with thesis-big-shadows (16 casters, 8 of
// them reduced to 256^2 by the 64 MB budget) was 5.4e-3 of the peak off in every forward
// technique. The cause: one pixel, (565, 69), whose receiver lies 2.3e-5 texel from a texel edge
// of light 13's map (u = 205.99998), a float ulp of its position; the fragment's interpolated
// position fell on the lit side, the one rebuilt from depth on the shadowed. The comparison now
// allows either answer within the fragment's rounding box (reference.h, ReceiverRounding); the
// frame must have such a pair (else it tests nothing) and pass the forward bound. No smaller
// frame of the atrium meets one (96x54, 160x90, frames 0-8 at 320x180 were tried).
TEST(ForwardShadows, AShadowTestWithinRoundingOfATexelEdgeIsNotAnError) {
  REQUIRE_GL();
  Scene scene = makeBuiltinScene("atrium", "thesis-big-shadows", 1);
  GlFrame g(scene, 0, 640, 360);
  attachMaps(g, scene, 1);
  const FrameResult r = g.render("forward-single");
  const ErrorStats e = test::expectMatchesReference(g, r, kForwardBound);
  EXPECT_GT(e.ambiguousShadowPairs, 0u);
  const PreparedFrame& f = g.prepared;
  const ErrorStats strict = compareToReference(
      r.image, shadeReference(f.encoded, f.intrinsics, f.lights, f.ambient, 0), 0.0);
  std::cout << "[ forward shadows ] atrium 640x360: " << e.ambiguousShadowPairs
            << " ambiguous pair(s), error " << e.maxRelPeak << " of the peak beyond their slack, "
            << strict.maxRelPeak << " without it\n";
}

}  // namespace
}  // namespace ts
