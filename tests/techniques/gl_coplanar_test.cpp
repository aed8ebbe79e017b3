// Coplanar faces drawn twice in the forward family: the G-buffer pass (depth GREATER) keeps the
// first face drawn at a pixel, and a depth-EQUAL pass alone would shade both, the later over the
// first (tiled-forward-prez's forward pass) or summed (forward's light passes). Each keeps the
// pre-pass's or base pass's triangle (u_visibleOnly), so its image is the reference's of the
// G-buffer. The built-in street has such faces (tiled-forward-prez on street/few frame 160 at
// 640x360 erred by 1.5e-3 of the peak before). Skips where no OpenGL context can be made.
#include <gtest/gtest.h>

#include <iostream>

#include "gl_frame.h"
#include "reference_check.h"
#include "require_gl.h"

namespace ts {
namespace {

constexpr double kForwardBound = 1e-4;  // as the forward techniques' own tests
constexpr int kW = 96, kH = 54;

// A wall facing the camera at depth 6, drawn twice from the same vertices (bit-identical depths)
// with two materials, grey first and red second, lit by point lights in front.
Scene twiceDrawnWall() {
  Scene s;
  s.name = "twice-drawn wall";
  SceneCamera cam;
  cam.yfov = 1.2f;
  cam.znear = 0.1f;
  cam.zfar = 100.0f;
  s.cameraPath.push_back(cam);
  Material grey, red;
  grey.name = "grey";
  grey.diffuse = {0.5f, 0.5f, 0.5f};
  red.name = "red";
  red.diffuse = {0.9f, 0.1f, 0.1f};
  s.materials = {grey, red};
  for (uint32_t material : {0u, 1u}) {
    const uint32_t base = uint32_t(s.vertices.size());
    for (auto [x, y] : {std::pair{-8.0f, -5.0f}, {-8.0f, 5.0f}, {8.0f, -5.0f}, {8.0f, 5.0f}})
      s.vertices.push_back(Vertex{{x, y, -6.0f}, {0.0f, 0.0f, 1.0f}, {0.0f, 0.0f}});
    s.indices.insert(s.indices.end(), {base, base + 1, base + 2, base + 2, base + 1, base + 3});
    s.triangleMaterial.insert(s.triangleMaterial.end(), {material, material});
  }
  for (int k = 0; k < 4; ++k)
    s.lights.push_back(
        SceneLight::point({-3.0 + 2.0 * k, k % 2 ? 1.0 : -1.0, -4.0}, {0.8f, 0.7f, 0.6f}, 5.0f));
  s.ambient = glm::vec3(0.05f);
  return s;
}

TEST(GlCoplanar, ForwardTechniquesShadeTheFaceTheGBufferKeeps) {
  REQUIRE_GL();
  const Scene scene = twiceDrawnWall();
  test::GlFrame g(scene, 0, kW, kH);
  ASSERT_NE(g.forward, nullptr);
  // The G-buffer keeps the grey face (drawn first) everywhere: else this test could not fail.
  size_t grey = 0;
  for (size_t i = 0; i < g.prepared.gbuffer.depth.size(); ++i)
    grey += g.prepared.gbuffer.diffuse[i].y > 0.4f ? 1 : 0;
  EXPECT_EQ(grey, size_t(kW * kH));
  for (const char* technique :
       {"forward", "forward-single", "tiled-forward", "tiled-forward-prez"}) {
    SCOPED_TRACE(technique);
    const FrameResult r = g.render(technique);
    const ErrorStats e = test::expectMatchesReference(g, r, kForwardBound);
    std::cout << "[ coplanar ] " << technique << ": max error " << e.maxRelPeak << " of the peak, "
              << r.counters.lightingComputations << " lighting computations\n";
  }
}

}  // namespace
}  // namespace ts
