// G-buffer files (src/gbuffer/gbuffer_files.h): `render --dump` read back by `--gbuffer-in`
// exactly (same stored bits, same lights, same images from every technique, in every layout),
// a G-buffer from another renderer through a descriptor (hardware depth, unorm normals, bottom
// row first), and one-line errors for bad files.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>

#include <nlohmann/json.hpp>

#include "raster/raster_backend.h"
#include "reference_check.h"
#include "render/gbuffer_dump.h"
#include "render/imported_frame.h"
#include "gbuffer/image_io.h"
#include "scene/scene_features.h"
#include "util/error.h"
#include "util/pi.h"
#include "random_draws.h"

namespace ts {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

fs::path freshDir(const std::string& name) { return ts::test::freshDir("gbuffer_import", name); }

// Dumps `f` as `render --dump` does (through the dump kernel) into a fresh folder.
fs::path dump(const PreparedFrame& f, const std::string& name) {
  fs::path dir = freshDir(name);
  DeviceFrame frame = f.upload(test::context());
  writeGBufferDump(test::context(), frame, f, "test", toString(f.raster), dir.string());
  return dir;
}

template <typename T>
bool sameBits(const std::vector<T>& a, const std::vector<T>& b) {
  // (memcmp must not see the null data() of an empty vector, even for 0 bytes)
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

void expectSameFrame(const PreparedFrame& a, const PreparedFrame& b, const std::string& what) {
  EXPECT_EQ(a.encoded.format, b.encoded.format) << what;
  EXPECT_EQ(a.encoded.width, b.encoded.width) << what;
  EXPECT_EQ(a.encoded.height, b.encoded.height) << what;
  EXPECT_TRUE(sameBits(a.encoded.depth, b.encoded.depth)) << what << ": depth";
  EXPECT_TRUE(sameBits(a.encoded.normal, b.encoded.normal)) << what << ": normal codes";
  EXPECT_TRUE(sameBits(a.encoded.diffuse, b.encoded.diffuse)) << what << ": diffuse codes";
  EXPECT_TRUE(sameBits(a.encoded.specular, b.encoded.specular)) << what << ": specular codes";
  EXPECT_TRUE(sameBits(a.encoded.emissive, b.encoded.emissive)) << what << ": emissive codes";
  EXPECT_TRUE(sameBits(a.lights.positionRange, b.lights.positionRange)) << what;
  EXPECT_TRUE(sameBits(a.lights.color, b.lights.color)) << what;
  EXPECT_TRUE(sameBits(a.lights.spot, b.lights.spot)) << what;
  EXPECT_TRUE(sameBits(a.lights.directionalDir, b.lights.directionalDir)) << what;
  EXPECT_TRUE(sameBits(a.lights.directionalColor, b.lights.directionalColor)) << what;
  EXPECT_EQ(a.ambient, b.ambient) << what;
  EXPECT_EQ(a.intrinsics.tanHalfFovX, b.intrinsics.tanHalfFovX) << what;
  EXPECT_EQ(a.intrinsics.tanHalfFovY, b.intrinsics.tanHalfFovY) << what;
  EXPECT_EQ(a.intrinsics.znear, b.intrinsics.znear) << what;
  EXPECT_EQ(a.intrinsics.zfar, b.intrinsics.zfar) << what;
  EXPECT_EQ(a.gbuffer.model, b.gbuffer.model) << what;
}

// The street with spot lights and a sun (every light type in lights.json), 120x72.
const Scene& mixedLightStreet() {
  static const Scene scene = [] {
    Scene s = makeBuiltinScene("street", "many", 1);
    applyVariants(s, "spot,sun", 1);
    return s;
  }();
  return scene;
}

TEST(GBufferImport, DumpRoundTripsExactlyInEveryLayoutForEveryTechnique) {
  const Scene& scene = mixedLightStreet();
  for (GBufferFormat format : {GBufferFormat::FP32, GBufferFormat::FP16, GBufferFormat::PACKED}) {
    const std::string layout = toString(format);
    PreparedFrame original = prepareFrame(scene, 3, 120, 72, format);
    ImportedFrame imported = importGBuffer(dump(original, layout).string());
    expectSameFrame(original, imported.frame, layout);
    // Re-encoding the imported values in their layout gave back the stored codes (above), so
    // every technique shades the same inputs and gives the same image bit for bit (renders are
    // repeatable: tests/techniques/repeatability_test.cpp).
    for (int lanes : {1, 16}) {
      TechniqueConfig config;
      config.format = format;
      config.lanes = lanes;
      for (const auto& name : gbufferTechniqueNames()) {
        Technique& t = test::cachedTechnique(name, config);
        const FrameResult a = test::renderOnly(original, t, false);
        const FrameResult b = test::renderOnly(imported.frame, t, false);
        EXPECT_TRUE(sameBits(a.image, b.image)) << name << " " << layout << " lanes " << lanes;
      }
    }
  }
}

TEST(GBufferImport, MetallicRoughnessPlanesRoundTrip) {
  Scene scene = makeBuiltinScene("atrium", "small", 1);
  applyVariants(scene, "metallic-roughness", 1);
  SceneFeatures features = analyzeScene(scene, ShadingModel::MetallicRoughness);
  for (GBufferFormat format : {GBufferFormat::FP32, GBufferFormat::FP16, GBufferFormat::PACKED}) {
    SceneRasterizer software(scene, RasterBackend::Software);
    PreparedFrame original = prepareFrame(software, 0, 80, 48, format, features);
    ImportedFrame imported = importGBuffer(dump(original, "mr_" + toString(format)).string());
    EXPECT_EQ(imported.descriptor.model, ShadingModel::MetallicRoughness);
    expectSameFrame(original, imported.frame, "metallic-roughness " + toString(format));
  }
}

TEST(GBufferImport, OpenGLGBufferDumpedAndImported) {
  const Scene& scene = test::builtinScene("atrium", "mixed");
  std::optional<SceneRasterizer> gl;
  try {
    gl.emplace(scene, RasterBackend::Gl);
  } catch (const Error& e) {
    GTEST_SKIP() << e.what();
  }
  for (GBufferFormat format : {GBufferFormat::FP32, GBufferFormat::PACKED}) {
    PreparedFrame original =
        prepareFrame(*gl, 2, 101, 67, format, analyzeScene(scene, ShadingModel::BlinnPhong));
    ASSERT_EQ(original.raster, RasterBackend::Gl);
    ImportedFrame imported = importGBuffer(dump(original, "gl_" + toString(format)).string());
    expectSameFrame(original, imported.frame, "OpenGL " + toString(format));
    TechniqueConfig config;
    config.format = format;
    // Equal input gives equal bits (any technique: renders are repeatable).
    Technique& t = test::cachedTechnique("tiled-single", config);
    EXPECT_TRUE(sameBits(test::renderOnly(original, t, false).image,
                         test::renderOnly(imported.frame, t, false).image));
  }
}

// Another renderer's G-buffer: an OpenGL-style depth buffer (glm::perspective's [-1, 1] NDC
// mapped to [0, 1]), normals as 0.5 n + 0.5, rows bottom first, the field of view in degrees.
TEST(GBufferImport, ForeignDescriptorWithHardwareDepth) {
  const Scene& scene = test::builtinScene("street", "few");
  PreparedFrame original = prepareFrame(scene, 5, 96, 60, GBufferFormat::FP32);
  const GBuffer& g = original.gbuffer;
  const double n = original.intrinsics.znear, f = original.intrinsics.zfar;
  std::vector<float> data;
  for (int row = 0; row < g.height; ++row)
    for (int x = 0; x < g.width; ++x) {
      const size_t i = size_t(g.height - 1 - row) * size_t(g.width) + size_t(x);  // bottom first
      const double depth = g.depth[i];
      // Window depth of glm::perspective (NDC z in [-1, 1]); 1 = cleared (background).
      const double ndc = depth > 0.0 ? (f + n) / (f - n) - 2.0 * f * n / ((f - n) * depth) : 1.0;
      data.push_back(float(0.5 * ndc + 0.5));
      for (int c = 0; c < 3; ++c) data.push_back(0.5f * g.normal[i][c] + 0.5f);
      for (int c = 0; c < 3; ++c) data.push_back(g.diffuse[i][c]);
      for (int c = 0; c < 4; ++c) data.push_back(g.specular[i][c]);
    }
  fs::path dir = freshDir("foreign");
  writeExr((dir / "frame.exr").string(), g.width, g.height,
           {"Z", "nx", "ny", "nz", "albedo.R", "albedo.G", "albedo.B", "spec.R", "spec.G", "spec.B",
            "spec.A"},
           data);
  std::ofstream(dir / "lights.json") << lightsJson(original.lights, original.ambient).dump();
  const double yfovDegrees = double(scene.camera(5).yfov) * 180.0 / ts::kPiDouble;
  json d = {{"tileshade_gbuffer", 1},
            {"image", "frame.exr"},
            {"origin", "bottom"},
            {"camera", {{"yfov_degrees", yfovDegrees}}},
            {"depth",
             {{"channel", "Z"},
              {"encoding", "hardware"},
              {"near", n},
              {"far", f},
              {"range", "minus_one_to_one"}}},
            {"normal", {"nx", "ny", "nz"}},
            {"normal_encoding", "unorm"},
            {"diffuse", {"albedo.R", "albedo.G", "albedo.B"}},
            {"specular", {"spec.R", "spec.G", "spec.B"}},
            {"shininess", "spec.A"}};
  std::ofstream(dir / "my-renderer.json") << d.dump(2);
  ImportedFrame imported = importGBuffer((dir / "my-renderer.json").string());
  const GBuffer& h = imported.frame.gbuffer;
  ASSERT_EQ(h.width, g.width);
  // The window depth is a float: near the far plane its 2^-24 steps are worth
  // d^2 (f - n) / (f n) 2^-23 of depth (relative d (f - n) / (f n) 2^-23 <= 2.7e-5 at d = f = 450).
  double maxDepthRel = 0.0, maxNormal = 0.0;
  for (size_t i = 0; i < g.pixelCount(); ++i) {
    ASSERT_EQ(g.depth[i] > 0.0f, h.depth[i] > 0.0f) << "coverage at " << i;
    if (g.depth[i] <= 0.0f) continue;
    const double rel = std::abs(double(h.depth[i]) - g.depth[i]) / g.depth[i];
    const double bound = g.depth[i] * (f - n) / (f * n) * std::ldexp(1.0, -23) + 1e-6;
    EXPECT_LE(rel, bound) << "depth at pixel " << i;
    maxDepthRel = std::max(maxDepthRel, rel);
    for (int c = 0; c < 3; ++c) {
      maxNormal = std::max(maxNormal, double(std::abs(h.normal[i][c] - g.normal[i][c])));
      EXPECT_EQ(h.diffuse[i][c], g.diffuse[i][c]);
    }
  }
  EXPECT_LE(maxNormal, 2.0 * std::ldexp(1.0, -24) + 1e-7);  // 0.5 n + 0.5 and back: 2 roundings
  EXPECT_EQ(imported.frame.intrinsics.tanHalfFovY, original.intrinsics.tanHalfFovY);
  EXPECT_NEAR(imported.frame.intrinsics.tanHalfFovX, original.intrinsics.tanHalfFovX, 1e-6);
  RecordProperty("max_depth_rel", std::to_string(maxDepthRel));
  // Shaded from it, the image stays within the reference checks.
  TechniqueConfig config;
  test::Checked c = test::renderAndCheck(imported.frame, test::cachedTechnique("tiled", config));
  EXPECT_EQ(c.missed, 0u);
  EXPECT_LE(c.error.maxRelPeak, test::kFp32RelativeTolerance);
}

// ---- Bad files: one line naming the file and the channel or field ---------------------------

struct BadCase {
  std::string name;
  std::function<void(json& descriptor, json& lights, std::vector<std::string>& channels,
                     std::vector<float>& data, int& width)>
      spoil;
  std::vector<std::string> mentions;  // the message names these
};

TEST(GBufferImport, BadFilesGiveOneLineNamingFileAndField) {
  const PreparedFrame good = prepareFrame(mixedLightStreet(), 0, 24, 16, GBufferFormat::FP32);
  const fs::path base = dump(good, "bad_base");
  const FloatImage image = readImage((base / "gbuffer.exr").string());
  json descriptor, lights;
  std::ifstream(base / "gbuffer.json") >> descriptor;
  std::ifstream(base / "lights.json") >> lights;
  auto firstGeometry = [&](const std::vector<std::string>& channels, const std::vector<float>& d) {
    const size_t stride = channels.size(),
                 mask =
                     size_t(std::find(channels.begin(), channels.end(), "mask") - channels.begin());
    for (size_t i = 0; i < d.size() / stride; ++i)
      if (d[i * stride + mask] > 0.5f) return i * stride;
    return size_t(0);
  };
  auto channelIndex = [](const std::vector<std::string>& c, const std::string& n) {
    return size_t(std::find(c.begin(), c.end(), n) - c.begin());
  };
  const std::vector<BadCase> cases = {
      {"missing channel",
       [](json& d, json&, auto&, auto&, int&) {
         d["normal"] = {"Nraw.x", "Nraw.q", "Nraw.z"};
       },
       {"gbuffer.exr", "Nraw.q", "normal"}},
      {"wrong size",
       [](json& d, json&, auto&, auto&, int&) { d["width"] = 25; },
       {"gbuffer.exr", "24x16", "25x16"}},
      {"NaN depth",
       [&](json&, json&, auto& c, auto& data, int&) {
         data[firstGeometry(c, data) + channelIndex(c, "P.z")] = std::nanf("");
       },
       {"gbuffer.exr", "P.z", "NaN", "pixel"}},
      {"NaN colour",
       [&](json&, json&, auto& c, auto& data, int&) {
         data[firstGeometry(c, data) + channelIndex(c, "kd.G")] =
             std::numeric_limits<float>::infinity();
       },
       {"gbuffer.exr", "kd.G", "diffuse", "infinite"}},
      {"light without a range",
       [](json&, json& l, auto&, auto&, int&) { l["lights"][0].erase("range"); },
       {"lights.json", "light 0", "range"}},
      {"negative range",
       [](json&, json& l, auto&, auto&, int&) { l["lights"][1]["range"] = -2; },
       {"lights.json", "light 1", "range"}},
      {"spot without a cone",
       [](json&, json& l, auto&, auto&, int&) {
         for (auto& x : l["lights"])
           if (x["type"] == "spot") {
             x.erase("cos_outer");
             x.erase("cone_scale");
             break;
           }
       },
       {"lights.json", "spot", "outer_cone_angle"}},
      {"directional without direction",
       [](json&, json& l, auto&, auto&, int&) {
         for (auto& x : l["lights"])
           if (x["type"] == "directional") x.erase("direction");
       },
       {"lights.json", "directional", "direction"}},
      {"unknown light type",
       [](json&, json& l, auto&, auto&, int&) { l["lights"][2]["type"] = "area"; },
       {"lights.json", "light 2", "type", "area"}},
      {"no field of view",
       [](json& d, json&, auto&, auto&, int&) { d["camera"].erase("tan_half_fov"); },
       {"gbuffer.json", "yfov"}},
      {"unknown field",
       [](json& d, json&, auto&, auto&, int&) { d["albedo"] = "kd.R"; },
       {"gbuffer.json", "albedo"}},
      {"hardware depth without far",
       [](json& d, json&, auto&, auto&, int&) {
         d["depth"] = {
             {"channel", "P.z"}, {"encoding", "hardware"}, {"near", 0.1}, {"range", "zero_to_one"}};
       },
       {"gbuffer.json", "depth", "far"}},
      {"field of the other model",
       [](json& d, json&, auto&, auto&, int&) { d["metallic"] = "kd.R"; },
       {"gbuffer.json", "metallic", "blinn-phong"}},
  };
  for (const BadCase& bad : cases) {
    json d = descriptor, l = lights;
    std::vector<std::string> channels = image.channels;
    std::vector<float> data = image.data;
    int width = image.width;
    bad.spoil(d, l, channels, data, width);
    const fs::path dir = freshDir("bad");
    writeExr((dir / "gbuffer.exr").string(), width, image.height, channels, data);
    std::ofstream(dir / "gbuffer.json") << d.dump(2);
    std::ofstream(dir / "lights.json") << l.dump(2);
    try {
      importGBuffer(dir.string());
      ADD_FAILURE() << bad.name << ": no error";
    } catch (const Error& e) {
      const std::string msg = e.what();
      EXPECT_EQ(msg.find('\n'), std::string::npos) << bad.name << ": " << msg;
      for (const auto& m : bad.mentions)
        EXPECT_NE(msg.find(m), std::string::npos) << bad.name << ": '" << m << "' not in: " << msg;
    }
  }
  // A folder without a descriptor.
  try {
    importGBuffer(freshDir("empty").string());
    ADD_FAILURE() << "no error for a folder without gbuffer.json";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("gbuffer.json"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace ts
