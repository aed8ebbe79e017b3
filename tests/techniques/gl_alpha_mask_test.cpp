// alphaMode MASK in the forward family (issue #17): every forward technique leaves out the
// fragments that the G-buffer pass leaves out (the one alpha test of shaders/material_planes.h,
// a discard in tiled_forward.frag and depth_only.frag), so its image matches the double reference
// shaded from the OpenGL G-buffer of the same masked scene. Skips where no OpenGL context can be
// made.
#include <gtest/gtest.h>

#include <iostream>

#include "gl_frame.h"
#include "raster/rasterizer.h"
#include "reference_check.h"
#include "require_gl.h"

namespace ts {
namespace {

// As the forward techniques' own tests (gl_forward_test.cpp, gl_tiled_forward_test.cpp).
constexpr double kForwardBound = 1e-4;

constexpr int kW = 96, kH = 54;

// A wall at depth 6 behind a masked quad at depth 3 (triangles 2, 3) whose diffuse texture is a
// 4x4 checker of alpha 0 and 1 (NEAREST: texel edges 16 and 8 pixels apart, half a pixel from
// any pixel centre, so both rasterizations take the same side), lit by point lights between them
// and in front. Hand-made rather than a built-in with masks: masking a built-in's facades reveals
// coplanar surfaces behind them, which depth-EQUAL passes shade where the G-buffer keeps one.
Scene maskedQuad() {
  Scene s;
  s.name = "masked quad";
  SceneCamera cam;
  cam.yfov = 1.2f;
  cam.znear = 0.1f;
  cam.zfar = 100.0f;
  s.cameraPath.push_back(cam);
  const CameraIntrinsics in = CameraIntrinsics::from(cam, kW, kH);
  auto at = [&](double x, double y, double d) {
    const double ndcX = 2.0 * x / kW - 1.0, ndcY = 1.0 - 2.0 * y / kH;
    return glm::vec3(glm::dvec3(ndcX * in.tanHalfFovX * d, ndcY * in.tanHalfFovY * d, -d));
  };
  Material wall, leaf;
  wall.name = "wall";
  wall.diffuse = {0.5f, 0.6f, 0.7f};
  leaf.name = "leaf";
  leaf.diffuse = {0.9f, 0.7f, 0.3f};
  leaf.alphaMode = AlphaMode::Mask;
  leaf.diffuseTexture = 0;
  s.materials = {wall, leaf};
  Texture checker;
  checker.width = checker.height = 4;
  for (int i = 0; i < 16; ++i)
    checker.texels.push_back(glm::vec4(1.0f, 1.0f, 1.0f, ((i % 4) + (i / 4)) % 2 ? 1.0f : 0.0f));
  checker.nearest = true;
  checker.wrapS = checker.wrapT = TextureWrap::ClampToEdge;
  s.textures.push_back(checker);
  auto quad = [&](double x0, double y0, double x1, double y1, double d, uint32_t material) {
    const uint32_t base = uint32_t(s.vertices.size());
    for (auto [x, y] : {std::pair{x0, y0}, {x0, y1}, {x1, y0}, {x1, y1}})
      s.vertices.push_back(
          Vertex{at(x, y, d), glm::vec3(0.0f, 0.0f, 1.0f),
                 glm::vec2(float((x - x0) / (x1 - x0)), float((y - y0) / (y1 - y0)))});
    s.indices.insert(s.indices.end(), {base, base + 1, base + 2, base + 2, base + 1, base + 3});
    s.triangleMaterial.insert(s.triangleMaterial.end(), {material, material});
  };
  quad(0, 0, kW, kH, 6.0, 0);
  quad(16, 11, 80, 43, 3.0, 1);
  for (int k = 0; k < 6; ++k) {
    const double x = -1.5 + 0.6 * k, y = k % 2 ? 0.6 : -0.5;
    s.lights.push_back(
        SceneLight::point({x, y, k < 3 ? -4.5 : -1.0}, {0.6f, 0.5f + 0.1f * float(k), 0.4f}, 4.0f));
  }
  s.ambient = glm::vec3(0.05f);
  return s;
}

TEST(GlAlphaMask, ForwardTechniquesLeaveOutWhatTheGBufferPassLeavesOut) {
  REQUIRE_GL();
  const Scene scene = maskedQuad();
  // Half of the quad's pixels show the wall (else this test could not fail), in the software
  // G-buffer and the OpenGL one the forward images are checked against.
  RasterOptions o;
  o.triangleIds = true;
  const GBuffer soft = rasterize(scene, scene.camera(0), kW, kH, o);
  size_t quad = 0;
  for (int32_t t : soft.triangleId) quad += t >= 2 ? 1 : 0;
  EXPECT_EQ(quad, size_t(64 * 32 / 2));

  test::GlFrame g(scene, 0, kW, kH);
  ASSERT_NE(g.forward, nullptr);
  size_t wallPixels = 0;
  for (float d : g.prepared.gbuffer.depth) wallPixels += d > 4.5f ? 1 : 0;
  EXPECT_EQ(wallPixels, size_t(kW * kH) - quad);
  for (const char* technique :
       {"forward", "forward-single", "tiled-forward", "tiled-forward-prez"}) {
    SCOPED_TRACE(technique);
    const FrameResult r = g.render(technique);
    const ErrorStats e = test::expectMatchesReference(g, r, kForwardBound);
    std::cout << "[ mask ] " << technique << ": max error " << e.maxRelPeak << " of the peak\n";
  }
}

}  // namespace
}  // namespace ts
