// End to end: scene -> software G-buffer -> multi-kernel tiled deferred on PoCL -> compared with
// the double-precision reference; culling conservativeness on random cameras; the --dump decode;
// real third-party content; the command line's handling of bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <memory>
#include <random>

#include <nlohmann/json.hpp>

#include "reference/error_metrics.h"
#include "reference/reference.h"
#include "render/frame_setup.h"
#include "render/gbuffer_dump.h"
#include "scene/scene_loader.h"
#include "techniques/technique.h"
#include "reference_check.h"
#include "test_support.h"
#include "random_draws.h"

namespace ts {
namespace {

using test::builtinScene;
using test::Checked;
using test::kFp32RelativeTolerance;
using test::renderAndCheck;
using test::renderOnly;

Technique& tiledTechnique(GBufferFormat format, int tile) {
  TechniqueConfig config;
  config.format = format;
  config.tileWidth = config.tileHeight = tile;
  return test::cachedTechnique("tiled", config);
}

struct Case {
  std::string scene, lights;
  int frame, tile, width, height;
  GBufferFormat format;
};

// Keeps CTest's names readable (GoogleTest would print the parameter's bytes).
void PrintTo(const Case& k, std::ostream* os) {
  *os << k.scene << "/" << k.lights << " frame " << k.frame << " tile " << k.tile << " "
      << k.width << "x" << k.height << " " << toString(k.format);
}

class TiledMatchesReference : public ::testing::TestWithParam<Case> {};

TEST_P(TiledMatchesReference, WithinFp32RoundingAndNoMissedLight) {
  const Case& k = GetParam();
  PreparedFrame f = prepareFrame(builtinScene(k.scene, k.lights), k.frame, k.width, k.height, k.format);
  ASSERT_GT(f.gbuffer.geometryPixels(), f.gbuffer.pixelCount() / 4) << "camera sees little";
  Checked c = renderAndCheck(f, tiledTechnique(k.format, k.tile));
  EXPECT_EQ(c.missed, 0u);
  EXPECT_LE(c.error.maxRelPeak, kFp32RelativeTolerance)
      << "max abs " << c.error.maxAbs << " peak " << c.error.peak;
  EXPECT_GT(c.result.counters.evaluations, 0u);
}

INSTANTIATE_TEST_SUITE_P(
    Builtins, TiledMatchesReference,
    ::testing::Values(Case{"street", "many", 0, 16, 200, 120, GBufferFormat::FP32},
                      Case{"street", "many", 60, 8, 200, 120, GBufferFormat::FP16},
                      Case{"street", "few", 30, 32, 203, 117, GBufferFormat::FP32},
                      Case{"atrium", "small", 0, 16, 200, 120, GBufferFormat::FP16},
                      Case{"atrium", "big", 45, 32, 203, 117, GBufferFormat::FP32},
                      Case{"atrium", "mixed", 90, 64, 200, 120, GBufferFormat::FP32}),
    [](const auto& info) {
      const Case& k = info.param;
      return k.scene + "_" + k.lights + "_f" + std::to_string(k.frame) + "_t" +
             std::to_string(k.tile) + "_" + toString(k.format);
    });

// Random cameras inside the scene (looking anywhere, lights behind and around the camera, near
// plane through light volumes): the tile lists must hold every contributing light.
TEST(TiledCulling, ConservativeOnRandomCameras) {
  for (const auto& [label, f] : test::randomCameraFrames(11)) {
    Checked c = renderAndCheck(f, tiledTechnique(GBufferFormat::FP32, 16));
    EXPECT_EQ(c.missed, 0u) << label;
    EXPECT_LE(c.error.maxRelPeak, kFp32RelativeTolerance) << label;
  }
}

// --depth-split only drops lights that no pixel of a tile can see: on random cameras and on the
// atrium's lights between its columns and the far wall, no missed light, the same error bound,
// and never more lighting computations than one range per tile.
TEST(TiledCulling, DepthSplitIsConservativeAndNeverCullsLess) {
  auto frames = test::randomCameraFrames(5);
  frames.push_back(test::LabelledFrame{
      "atrium/small frame 0",
      prepareFrame(builtinScene("atrium", "small"), 0, 200, 120, GBufferFormat::FP32)});
  uint64_t plain = 0, split = 0;
  for (const auto& [label, f] : frames) {
    TechniqueConfig config;
    config.depthSplit = true;
    auto tiled = createTechnique("tiled", test::context(), config);
    Checked c = renderAndCheck(f, *tiled);
    EXPECT_EQ(c.missed, 0u) << label;
    EXPECT_LE(c.error.maxRelPeak, kFp32RelativeTolerance) << label;
    Checked d = renderAndCheck(f, tiledTechnique(GBufferFormat::FP32, 16));
    EXPECT_LE(c.result.counters.lightingComputations, d.result.counters.lightingComputations)
        << label;
    split += c.result.counters.lightingComputations;
    plain += d.result.counters.lightingComputations;
  }
  EXPECT_LT(split, plain) << "the split culled nothing anywhere";
}

// Far more list entries than the initial buffer holds: the list grows and the frame re-runs,
// nothing is dropped, and the run says so.
TEST(TiledCulling, OverflowingListGrowsInsteadOfDropping) {
  // 300 huge lights: every tile lists all of them.
  PreparedFrame f = test::hugeLightsFrame(300);
  TechniqueConfig config;
  config.tileWidth = config.tileHeight = 8;
  config.presizeLists = false;  // start from the small default buffer so it has to grow
  auto tiled = createTechnique("tiled", test::context(), config);
  Checked c = renderAndCheck(f, *tiled);
  EXPECT_EQ(c.missed, 0u);
  EXPECT_LE(c.error.maxRelPeak, kFp32RelativeTolerance);
  EXPECT_EQ(c.result.counters.listMax, 300u);
  ASSERT_FALSE(c.result.counters.notes.empty());
  EXPECT_NE(c.result.counters.notes[0].find("grown"), std::string::npos);

  // Presized from the host's rectangle bound (the default), the same frame needs no re-run.
  config.presizeLists = true;
  Checked p = renderAndCheck(f, *createTechnique("tiled", test::context(), config));
  EXPECT_TRUE(p.result.counters.notes.empty());
  EXPECT_EQ(p.missed, 0u);
  EXPECT_EQ(p.result.counters.lightingComputations, c.result.counters.lightingComputations);
}

// Decoding: the dump kernel's values equal the host decoder's (which feeds the reference).
TEST(GBufferDecode, KernelMatchesHostDecoder) {
  for (GBufferFormat format : {GBufferFormat::FP32, GBufferFormat::FP16, GBufferFormat::PACKED}) {
    PreparedFrame f = prepareFrame(builtinScene("street", "few"), 10, 120, 72, format);
    DeviceFrame frame = f.upload(test::context());
    const std::vector<float> d =
        decodeOnDevice(test::context(), frame, format, TechniqueConfig().features);
    size_t geometry = 0;
    for (int y = 0; y < 72; ++y)
      for (int x = 0; x < 120; ++x) {
        const float* o = &d[(size_t(y) * 120 + x) * 17];
        SurfaceD s;
        bool valid = decodeSurface(f.encoded, f.intrinsics, x, y, s);
        ASSERT_EQ(o[16], valid ? 1.0f : 0.0f);
        if (!valid) continue;
        ++geometry;
        for (int c = 0; c < 3; ++c) {
          EXPECT_NEAR(o[0 + c], s.P[c], 1e-6 * std::abs(s.P.z) + 1e-7);
          EXPECT_NEAR(o[3 + c], s.N[c], 1e-6);
          EXPECT_EQ(o[6 + c], float(s.kd[c]));  // colours decode exactly
          EXPECT_EQ(o[9 + c], float(s.ks[c]));
          EXPECT_EQ(o[13 + c], float(s.ke[c]));
        }
        // Packed shininess is decoded with exp2, which OpenCL allows 3 ulp; the other layouts
        // store it and must match exactly.
        if (format == GBufferFormat::PACKED)
          EXPECT_NEAR(o[12], s.gloss, 3 * std::ldexp(1.0, std::ilogb(s.gloss) - 23));
        else
          EXPECT_EQ(o[12], float(s.gloss));
      }
    EXPECT_GT(geometry, 0u);
  }
}

// Third-party glTF content: loads, rasterizes, shades within tolerance of the reference.
void checkRealScene(const std::string& path, const std::vector<Light>& extraLights) {
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
std::vector<Light> scatteredLights(const Scene& scene, int n) {
  Bounds b = scene.bounds();
  float size = glm::length(b.extent());
  std::mt19937 rng(2);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<Light> lights;
  auto draw = [&] { return u(rng); };
  for (int i = 0; i < n; ++i) {
    const auto c = test::drawnLastFirst<3>(draw);  // the colour first, as g++ drew the arguments
    const auto p = test::drawnLastFirst<3>(draw);
    lights.push_back(Light::point(b.min + glm::vec3(p[0], p[1], p[2]) * b.extent(),
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

// The command line: bad input gives one line on stderr and a non-zero exit.
using test::CliRun;
using test::runTileshade;

TEST(CommandLine, BadInputFailsWithOneLine) {
  if (!std::filesystem::exists(TILESHADE_BINARY)) GTEST_SKIP() << "tileshade binary not built";
  auto tmp = std::filesystem::temp_directory_path() / "tileshade_cli_test";
  std::string out = " --out " + tmp.string() + " --width 64 --height 36";
  for (const char* args :
       {"render --scene builtin:nowhere", "render --technique nonsense",
        "render --scene /nonexistent/file.gltf", "render --tile 0", "render --gbuffer fp8",
        "render --device no-such-device", "render --lights nonsense", "render --width",
        "render --frobnicate"}) {
    std::string a = args;
    CliRun r = runTileshade(a + out + (a.find("--device") == std::string::npos ? " --device cpu" : ""));
    EXPECT_NE(r.status, 0) << args;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << args << ": " << r.output;
    EXPECT_NE(r.output.find("error"), std::string::npos) << args << ": " << r.output;
  }
}

TEST(CommandLine, RenderWritesImagesStatsAndDump) {
  if (!std::filesystem::exists(TILESHADE_BINARY)) GTEST_SKIP() << "tileshade binary not built";
  auto tmp = std::filesystem::temp_directory_path() / "tileshade_cli_render";
  std::filesystem::remove_all(tmp);
  CliRun r = runTileshade("render --scene builtin:street --lights few --width 96 --height 54 "
                       "--device cpu --check --dump --out " + tmp.string());
  ASSERT_EQ(r.status, 0) << r.output;
  for (const char* f : {"image.exr", "image.png", "stats.json", "gbuffer.exr", "lights.json"})
    EXPECT_TRUE(std::filesystem::exists(tmp / f)) << f;
  EXPECT_NE(r.output.find("tiled"), std::string::npos);
  EXPECT_NE(r.output.find("shading err"), std::string::npos) << r.output;
  // Both windowed errors: from depth in double, and from the kernels' float positions.
  const nlohmann::json stats = nlohmann::json::parse(std::ifstream(tmp / "stats.json"));
  const nlohmann::json& t = stats["techniques"][0];
  for (const char* key : {"error", "error_shading", "error_vs_physical"}) {
    ASSERT_TRUE(t.contains(key)) << key;
    EXPECT_LE(t[key]["max_rel_peak"].get<double>(), std::string(key) == "error_vs_physical" ? 1.0
                                                                                          : 2e-5)
        << key;
  }
  EXPECT_NE(t["error"]["max_rel_peak"], t["error_shading"]["max_rel_peak"]);
}

}  // namespace
}  // namespace ts
