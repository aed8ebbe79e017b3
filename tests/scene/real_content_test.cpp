// Real third-party glTF content (../shared/scenes, Debian's assimp-testmodels) end to end: loads,
// rasterizes, and shades with tiled within tolerance of the double-precision reference.
#include <gtest/gtest.h>

#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "render/frame_setup.h"
#include "scene/scene_loader.h"
#include "techniques/technique.h"
#include "reference_check.h"
#include "test_support.h"
#include "random_draws.h"
#include "tiled_technique.h"

namespace ts {
namespace {

using test::Checked;
using test::kFp32RelativeTolerance;
using test::renderAndCheck;
using test::tiledTechnique;

// Third-party glTF content: loads, rasterizes, shades within tolerance of the reference.
void checkRealScene(const std::string& path, const std::vector<SceneLight>& extraLights) {
  Scene scene = loadGltf(path);
  ASSERT_GT(scene.triangleCount(), 1000u);
  for (const auto& l : extraLights) scene.lights.push_back(l);
  ASSERT_FALSE(scene.lights.empty());
  PreparedFrame f = prepareFrame(scene, 0, 160, 90, GBufferFormat::FP16);
  ASSERT_GT(f.gbuffer.geometryPixels(), 0u);
  Checked c = renderAndCheck(f, tiledTechnique(GBufferFormat::FP16, 16));
  EXPECT_EQ(c.missed, 0u);
  EXPECT_LE(c.error.maxRelPeak, kFp32RelativeTolerance);
  EXPECT_GT(c.error.peak, 0.0);
}

// Lights scattered through a scene's bounds, sized to it (Sponza and the engine have none).
std::vector<SceneLight> scatteredLights(const Scene& scene, int n) {
  Bounds b = scene.bounds();
  float size = glm::length(b.extent());
  std::mt19937 rng(2);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<SceneLight> lights;
  auto draw = [&] { return u(rng); };
  for (int i = 0; i < n; ++i) {
    const auto c = test::drawnLastFirst<3>(draw);  // the colour first, as g++ drew the arguments
    const auto p = test::drawnLastFirst<3>(draw);
    lights.push_back(SceneLight::point(b.min + glm::vec3(p[0], p[1], p[2]) * b.extent(),
                                       glm::vec3(c[0], c[1], c[2]) * size * size * 0.01f,
                                       0.25f * size));
  }
  return lights;
}

TEST(RealContent, CrytekSponza) {
  std::string path = test::sharedScene("sponza-crytek/sponza.gltf");
  if (path.empty()) path = test::sharedScene("sponza-crytek/sponza.glb");
  if (path.empty()) GTEST_SKIP() << "../shared/scenes/sponza-crytek absent";
  checkRealScene(path, scatteredLights(loadGltf(path), 64));
}

TEST(RealContent, DungeonWithItsOwnLights) {
  std::string dir = test::sharedScene("dungeon");
  if (dir.empty()) GTEST_SKIP() << "../shared/scenes/dungeon absent";
  std::string path;
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir))
    if (e.path().extension() == ".gltf" || e.path().extension() == ".glb") path = e.path().string();
  ASSERT_FALSE(path.empty()) << "no glTF file under " << dir;
  checkRealScene(path, {});
}

TEST(RealContent, CylinderEngineFromAssimpTestModels) {
  std::string path =
      "/usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "assimp-testmodels not installed";
  checkRealScene(path, scatteredLights(loadGltf(path), 32));
}

}  // namespace
}  // namespace ts
