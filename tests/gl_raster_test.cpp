// The OpenGL rasterizer (src/raster/gl_rasterizer.cpp) against the software one.
#include <gtest/gtest.h>

#include <iostream>

#include "raster/egl_context.h"
#include "raster/gbuffer_compare.h"
#include "raster/gl_rasterizer.h"
#include "reference_check.h"
#include "util/error.h"

namespace {

using namespace ts;

// Skips the calling test, saying why, when no OpenGL context can be made here.
#define REQUIRE_GL()                                                   \
  do {                                                                 \
    try {                                                              \
      EglContext::shared();                                            \
    } catch (const Error& e) {                                         \
      GTEST_SKIP() << "no OpenGL context: " << e.what();               \
    }                                                                  \
  } while (0)

TEST(GlRaster, Explore) {
  REQUIRE_GL();
  std::cout << EglContext::shared().renderer() << " " << EglContext::shared().version() << "\n";
  for (const char* name : {"street", "atrium"}) {
    const Scene& scene = test::builtinScene(name, name == std::string("street") ? "many" : "small");
    GlRasterizer gl(scene);
    std::cout << name << " setup " << gl.setupMs() << " ms\n";
    for (int frame : {0, 37, 120}) {
      RasterOptions o;
      o.triangleIds = true;
      auto t0 = std::chrono::steady_clock::now();
      GBuffer g = gl.rasterize(scene.camera(frame), 640, 360, o);
      auto t1 = std::chrono::steady_clock::now();
      GBuffer s = rasterize(scene, scene.camera(frame), 640, 360, o);
      auto t2 = std::chrono::steady_clock::now();
      std::cout << name << " frame " << frame << " gl "
                << std::chrono::duration<double, std::milli>(t1 - t0).count() << " ms, sw "
                << std::chrono::duration<double, std::milli>(t2 - t1).count() << " ms\n  "
                << compareGBuffers(s, g).summary() << "\n";
    }
  }
}

}  // namespace
namespace {
TEST(GlRaster, Debug) {
  REQUIRE_GL();
  const Scene& scene = test::builtinScene("street", "many");
  GlRasterizer gl(scene);
  RasterOptions o;
  o.triangleIds = true;
  GBuffer g = gl.rasterize(scene.camera(0), 640, 360, o);
  GBuffer s = rasterize(scene, scene.camera(0), 640, 360, o);
  for (int y = 168; y <= 172; ++y)
    for (int x = 335; x <= 339; ++x) {
      size_t i = size_t(y) * 640 + x;
      std::cout << x << "," << y << " tri " << s.triangleId[i] << "/" << g.triangleId[i] << " d "
                << s.depth[i] << "/" << g.depth[i] << " n " << s.normal[i].x << " " << s.normal[i].y
                << " " << s.normal[i].z << " / " << g.normal[i].x << " " << g.normal[i].y << " "
                << g.normal[i].z << "\n";
    }
  int t = s.triangleId[170 * 640 + 337];
  for (int k = 0; k < 3; ++k) {
    const Vertex& v = scene.vertices[scene.indices[3 * t + k]];
    glm::vec4 p = scene.camera(0).viewFromWorld * glm::vec4(v.position, 1);
    std::cout << "v" << k << " view " << p.x << " " << p.y << " " << p.z << " n " << v.normal.x << " "
              << v.normal.y << " " << v.normal.z << "\n";
  }
}
}  // namespace
