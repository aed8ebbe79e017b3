// Hostile glTF input (issue #12): size and offset arithmetic that would wrap, numbers beyond
// float's range, values of the wrong type or shape, degenerate cameras and transforms, absurd
// allocations, texture failures. Each must give one clear ts::Error (or a documented clamp with one
// warning), never a crash, a silent wrong read or NaN/inf in the scene. The fuzzers' findings are
// regression tests here too (files under tests/data/fuzz/).
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "gltf_builder.h"
#include "scene/scene_loader.h"
#include "test_support.h"
#include "util/error.h"

namespace {

using json = nlohmann::json;
using ts::test::base64;
using ts::test::triangle;

struct Loaded {
  bool ok = false;
  std::string error;
  std::vector<std::string> warnings;
  ts::Scene scene;
};

Loaded load(const std::string& bytes) {
  Loaded r;
  try {
    r.scene = ts::loadGltfFromMemory(reinterpret_cast<const unsigned char*>(bytes.data()),
                                     bytes.size(), "/nonexistent", "hostile.gltf", &r.warnings);
    r.ok = true;
  } catch (const ts::Error& e) {
    r.error = e.what();
  }
  return r;
}

Loaded load(const json& doc) { return load(doc.dump()); }

// Loading fails with one line naming the file and containing `fragment`.
void expectError(const json& doc, const std::string& fragment) {
  Loaded r = load(doc);
  ASSERT_FALSE(r.ok) << "loaded without an error; expected one containing '" << fragment << "'";
  EXPECT_NE(r.error.find("hostile.gltf"), std::string::npos) << r.error;
  EXPECT_NE(r.error.find(fragment), std::string::npos) << r.error;
  EXPECT_EQ(r.error.find('\n'), std::string::npos) << r.error;
}

bool allFinite(const ts::Scene& s) {
  auto finite = [](glm::vec3 v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
  };
  for (const auto& v : s.vertices)
    if (!finite(v.position) || !finite(v.normal) || !std::isfinite(v.uv.x) ||
        !std::isfinite(v.uv.y))
      return false;
  for (const auto& l : s.lights)
    if (!finite(l.position) || !finite(l.color) || !finite(l.direction) || !std::isfinite(l.range))
      return false;
  for (const auto& m : s.materials)
    if (!finite(m.diffuse) || !finite(m.specular) || !finite(m.emissive) || !finite(m.baseColor) ||
        !std::isfinite(m.metallic) || !std::isfinite(m.roughness) || !std::isfinite(m.shininess))
      return false;
  for (const auto& c : s.cameraPath)
    for (int i = 0; i < 4; ++i)
      if (!std::isfinite(c.viewFromWorld[i].x + c.viewFromWorld[i].y + c.viewFromWorld[i].z +
                         c.viewFromWorld[i].w) ||
          !std::isfinite(c.zfar) || !(c.znear > 0.0f) || !(c.zfar > c.znear))
        return false;
  return true;
}

TEST(HostileGltf, TheBaseFileLoads) {
  Loaded r = load(triangle());
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(r.scene.triangleCount(), 1u);
  EXPECT_EQ(r.scene.lights.size(), 1u);
  EXPECT_TRUE(r.warnings.empty());
  EXPECT_TRUE(allFinite(r.scene));
}

// ---- item 2: size and offset arithmetic -------------------------------------------------------

TEST(HostileGltf, AccessorCountThatWrapsTimesThreeIsAnError) {
  // (2^64 / 3 + 1) * 3 wraps to 3 in size_t: a 3-element buffer, then a read of 2^64/3 elements.
  json doc = triangle();
  doc["accessors"][0]["count"] = std::numeric_limits<uint64_t>::max() / 3 + 1;
  expectError(doc, "runs past bufferView 0");
  doc["accessors"][0]["count"] = std::numeric_limits<uint64_t>::max();
  expectError(doc, "runs past bufferView 0");
  doc = triangle();
  doc["accessors"][1]["count"] = std::numeric_limits<uint64_t>::max() / 2 + 1;  // uint16 indices
  expectError(doc, "runs past bufferView 1");
}

TEST(HostileGltf, OffsetsNear2To64AreErrorsNotReadsBeforeTheBuffer) {
  json doc = triangle();
  doc["accessors"][0]["byteOffset"] = std::numeric_limits<uint64_t>::max() - 35;  // + 36 wraps to 0
  expectError(doc, "runs past bufferView 0");
  doc = triangle();
  doc["bufferViews"][0]["byteOffset"] = std::numeric_limits<uint64_t>::max() - 7;
  expectError(doc, "runs past buffer 0");
  doc = triangle();
  doc["bufferViews"][0]["byteLength"] = std::numeric_limits<uint64_t>::max();
  expectError(doc, "runs past buffer 0");
}

// tinygltf 2.7 passes an image's bufferView to the image decoder without checking it against the
// buffer (found by gltf_fuzzer): the JSON check refuses such a bufferView before tinygltf runs.
TEST(HostileGltf, BufferViewsMustLieInsideTheirBuffer) {
  json doc = triangle();
  doc["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", 40}, {"byteLength", 5}});  // 45 > 44
  doc["images"] = {{{"bufferView", 2}, {"mimeType", "image/png"}}};
  expectError(doc, "bufferViews[2]: byteOffset + byteLength (45) runs past buffer 0's 44 bytes");
  doc["bufferViews"][2]["byteOffset"] = std::numeric_limits<uint64_t>::max();
  expectError(doc, "more than 2^64");
}

TEST(HostileGltf, SparseAccessorsAreBoundsChecked) {
  json doc = triangle();
  // Two sparse values for the 3 positions: indices (uint16) and values read from bufferView 1/0.
  doc["accessors"][0]["sparse"] = {{"count", 2},
                                   {"indices", {{"bufferView", 1}, {"componentType", 5123}}},
                                   {"values", {{"bufferView", 0}}}};
  EXPECT_TRUE(load(doc).ok) << load(doc).error;
  doc["accessors"][0]["sparse"]["count"] = 4;  // more than the accessor's 3 elements
  expectError(doc, "4 sparse values for 3 elements");
  doc["accessors"][0]["sparse"]["count"] = 2;
  doc["accessors"][0]["sparse"]["indices"]["byteOffset"] = 2147483647;
  expectError(doc, "runs past bufferView 1");
  doc["accessors"][0]["sparse"]["indices"]["byteOffset"] = 4294967296;  // tinygltf keeps an int
  expectError(doc, "sparse.indices.byteOffset");
  doc["accessors"][0]["sparse"]["indices"]["byteOffset"] = 0;
  doc["accessors"][0]["sparse"]["indices"]["componentType"] = 5126;  // float indices
  expectError(doc, "sparse.indices.componentType");
}

TEST(HostileGltf, CountsWithoutDataAreCappedBeforeAllocating) {
  json doc = triangle();
  doc["accessors"][0].erase("bufferView");  // all zeros: nothing bounds the count but the cap
  doc["accessors"][0]["count"] = uint64_t(1) << 40;
  expectError(doc, "without a bufferView");
  doc["accessors"][0]["count"] = 3;
  EXPECT_TRUE(load(doc).ok);  // three zero positions: a legal, degenerate triangle
}

TEST(HostileGltf, IndicesMustBeUnsignedIntegers) {
  json doc = triangle();
  doc["accessors"][1]["componentType"] = 5126;  // float indices: 1e30 would not fit a uint32
  doc["bufferViews"][1]["byteLength"] = 8;
  doc["accessors"][1]["count"] = 2;
  expectError(doc, "must be unsigned byte, short or int");
  doc = triangle();
  doc["accessors"][1]["componentType"] = 5122;  // signed short
  expectError(doc, "must be unsigned byte, short or int");
}

TEST(HostileGltf, IntegersBeyondIntAreNotTruncated) {
  json doc = triangle();
  doc["accessors"][0]["bufferView"] = 4294967296;  // tinygltf would truncate this to 0
  expectError(doc, "accessors[0].bufferView");
  doc = triangle();
  doc["nodes"][0]["mesh"] = -1;
  expectError(doc, "nodes[0].mesh");
}

// ---- item 3: numbers beyond float's range ----------------------------------------------------

TEST(HostileGltf, NumbersBeyondFloatAreErrors) {
  auto with = [](auto edit) {
    json doc = triangle();
    edit(doc);
    return doc;
  };
  const json::json_pointer lights("/extensions/KHR_lights_punctual/lights/0");
  expectError(with([&](json& d) { d[lights]["intensity"] = 1e39; }), "intensity");
  expectError(with([&](json& d) { d[lights]["color"] = {1e39, 1, 1}; }), "color");
  expectError(with([&](json& d) { d[lights]["range"] = 1e39; }), "range");
  expectError(with([&](json& d) { d[lights]["range"] = 0; }), "range");
  expectError(with([&](json& d) { d[lights]["intensity"] = -1; }), "intensity");
  expectError(with([&](json& d) { d["nodes"][1]["translation"] = {1e39, 0, 0}; }), "translation");
  expectError(with([&](json& d) { d["nodes"][0]["scale"] = {1, -1e300, 1}; }), "scale");
  expectError(with([&](json& d) { d["cameras"][0]["perspective"]["znear"] = 1e39; }), "znear");
  expectError(
      with([&](json& d) {
        d["materials"] = {{{"pbrMetallicRoughness", {{"baseColorFactor", {1e39, 1, 1, 1}}}}}};
        d["meshes"][0]["primitives"][0]["material"] = 0;
      }),
      "baseColorFactor");
  expectError(with([&](json& d) {
                d["materials"] = {{{"emissiveFactor", {1, 1, 1e39}}}};
              }),
              "emissiveFactor");
}

TEST(HostileGltf, ProductsBeyondFloatAreErrors) {
  json doc = triangle();
  auto& light = doc["extensions"]["KHR_lights_punctual"]["lights"][0];
  light["color"] = {1e20, 1, 1};
  light["intensity"] = 1e20;  // each a float, the product 1e40 is not
  expectError(doc, "light colour x intensity");
  light["color"] = {1, 1, 1};
  light["intensity"] = 3e38;  // the largest light is fine: its range comes from double
  Loaded r = load(doc);
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_TRUE(allFinite(r.scene));
  EXPECT_GT(r.scene.lights[0].range, 1e19f);

  // Factors are clamped to [0, 1], so a strength or colour factor within float's range keeps
  // their products within it too.
  doc = triangle();
  doc["materials"] = {{{"emissiveFactor", {1, 1, 1}},
                       {"extensions",
                        {{"KHR_materials_emissive_strength", {{"emissiveStrength", 3.4e38}}},
                         {"KHR_materials_specular",
                          {{"specularFactor", 1}, {"specularColorFactor", {3e38, 1, 1}}}}}}}};
  doc["meshes"][0]["primitives"][0]["material"] = 0;
  r = load(doc);
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_TRUE(allFinite(r.scene));
  EXPECT_FLOAT_EQ(r.scene.materials[0].emissive.x, 3.4e38f);
}

TEST(HostileGltf, FactorsOutsideZeroToOneAreClampedWithOneWarning) {
  json doc = triangle();
  doc["materials"] = {
      {{"pbrMetallicRoughness", {{"baseColorFactor", {2, 0.5, -1, 1}}, {"metallicFactor", 1.5}}},
       {"emissiveFactor", {3, 0, 0}}}};
  doc["meshes"][0]["primitives"][0]["material"] = 0;
  Loaded r = load(doc);
  ASSERT_TRUE(r.ok) << r.error;
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_NE(r.warnings[0].find("clamped 4 material factor(s)"), std::string::npos) << r.warnings[0];
  EXPECT_NE(r.warnings[0].find("materials[0].baseColorFactor 2"), std::string::npos)
      << r.warnings[0];
  const ts::Material& m = r.scene.materials[0];
  EXPECT_EQ(m.baseColor, glm::vec3(1.0f, 0.5f, 0.0f));
  EXPECT_EQ(m.metallic, 1.0f);
  EXPECT_EQ(m.emissive, glm::vec3(1.0f, 0.0f, 0.0f));
}

TEST(HostileGltf, VertexDataMustBeFinite) {
  float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  expectError(triangle({0, 0, 0, 1, nan, 0, 0, 1, 0}), "POSITION: element 1 holds nan");
  expectError(triangle({0, 0, 0, 1, 0, 0, 0, -inf, 0}), "POSITION: element 2 holds -inf");
  // Finite vertices that a finite node transform takes beyond float's range.
  json doc = triangle({0, 0, 0, 3e38f, 0, 0, 0, 1, 0});
  doc["nodes"][0]["scale"] = {10, 1, 1};
  expectError(doc, "beyond float's range once its node transforms are applied");
  // And a hierarchy whose product overflows.
  doc = triangle();
  doc["nodes"].push_back({{"translation", {3e38, 0, 0}}, {"children", {4}}});
  doc["nodes"].push_back({{"translation", {3e38, 0, 0}}, {"mesh", 0}});
  doc["scenes"][0]["nodes"] = {0, 1, 2, 3};
  expectError(doc, "world transform overflows float");
}

// ---- item 7: invalid values reported instead of repaired ----------------------------------------

TEST(HostileGltf, WrongTypesAndShapesAreErrors) {
  json doc = triangle();
  doc["nodes"][1]["translation"] = "1,2,3";  // tinygltf would drop it silently
  expectError(doc, "nodes[1].translation: expected an array of 3 numbers");
  doc["nodes"][1]["translation"] = {1, 2};
  expectError(doc, "nodes[1].translation: expected an array of 3 numbers");
  doc = triangle();
  doc["nodes"][1]["rotation"] = {0, 0, 0, 0};  // nothing to normalise
  expectError(doc, "rotation quaternion of zero length");
  doc = triangle();
  doc["nodes"][0]["matrix"] = {1, 0, 0, 0, 0, 1, 0, 0};
  expectError(doc, "nodes[0].matrix");
  doc = triangle();
  doc["extensions"]["KHR_lights_punctual"]["lights"][0]["intensity"] = "bright";
  expectError(doc, "intensity");
  doc = triangle();
  doc["accessors"][0]["normalized"] = 1;
  expectError(doc, "normalized: expected true or false");
}

// alphaMode is one of glTF's three names (another would be drawn opaque without a word) and
// alphaCutoff a number in [0, 1]; the valid ones load as written.
TEST(HostileGltf, AlphaModesAndCutoffsAreCheckedNotDefaulted) {
  json doc = triangle();
  doc["meshes"][0]["primitives"][0]["material"] = 0;
  doc["materials"] = json::parse(R"([{"alphaMode": "MASK", "alphaCutoff": 0.75,
      "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 0.4]}}])");
  Loaded r = load(doc);
  ASSERT_TRUE(r.ok) << r.error;
  ASSERT_EQ(r.scene.materials.size(), 1u);
  EXPECT_EQ(r.scene.materials[0].alphaMode, ts::AlphaMode::Mask);
  EXPECT_FLOAT_EQ(r.scene.materials[0].alphaCutoff, 0.75f);
  EXPECT_FLOAT_EQ(r.scene.materials[0].opacity, 0.4f);
  for (const char* bad : {"CLIP", "blend", ""}) {
    doc["materials"][0]["alphaMode"] = bad;
    expectError(doc, "materials[0].alphaMode: expected one of OPAQUE, MASK, BLEND");
  }
  doc["materials"][0]["alphaMode"] = "BLEND";
  EXPECT_EQ(load(doc).scene.materials[0].alphaMode, ts::AlphaMode::Blend);
  doc["materials"][0]["alphaMode"] = 3;
  expectError(doc, "materials[0].alphaMode: expected one of");
  doc["materials"][0]["alphaMode"] = "MASK";
  for (json bad : {json(1.5), json(-0.25), json("half"), json(1e300)}) {
    doc["materials"][0]["alphaCutoff"] = bad;
    expectError(doc, "materials[0].alphaCutoff: expected a number in [0, 1]");
  }
}

TEST(HostileGltf, ByteStrideSmallerThanTheElementIsAnError) {
  json doc = triangle();
  doc["bufferViews"][0]["byteStride"] = 4;  // a VEC3 float element is 12 bytes
  expectError(doc, "byteStride 4 of bufferView 0 is smaller than its 12-byte element");
  doc["bufferViews"][0]["byteStride"] = 2;  // below glTF's minimum of 4
  expectError(doc, "byteStride");
  doc["bufferViews"][0]["byteStride"] = 12;
  EXPECT_TRUE(load(doc).ok);
}

TEST(HostileGltf, HierarchiesAreTreesSoVisitsStayLinear) {
  // Each node listing the next one 40 times: 40^10 visits as a DAG.
  json doc = triangle();
  size_t base = doc["nodes"].size();
  for (size_t level = 0; level < 10; ++level)
    doc["nodes"].push_back({{"children", std::vector<size_t>(40, base + level + 1)}});
  doc["nodes"].push_back({{"mesh", 0}});
  doc["scenes"][0]["nodes"].push_back(base);
  expectError(doc, "has more than one parent");
  doc = triangle();
  doc["scenes"][0]["nodes"] = {0, 0, 1, 2};
  expectError(doc, "lists node 0 twice");
}

TEST(HostileGltf, DeeplyNestedExtrasAreRefused) {
  std::string deep(100000, '[');
  std::string text = triangle().dump();
  text.insert(text.size() - 1, ",\"extras\":" + deep + std::string(100000, ']'));
  Loaded r = load(text);
  ASSERT_FALSE(r.ok);
  EXPECT_NE(r.error.find("nested deeper than"), std::string::npos) << r.error;
}

// ---- degenerate cameras
// --------------------------------------------------------------------------

TEST(HostileGltf, DegenerateCamerasAreErrorsNotBlackImages) {
  json doc = triangle();
  doc["nodes"][2]["scale"] = {0, 0, 0};
  expectError(doc, "zero scale");
  doc = triangle();
  doc["nodes"][2]["scale"] = {1, 0, 1};
  expectError(doc, "zero scale");
  doc = triangle();
  doc["nodes"][2]["matrix"] = {1, 0, 0, 0, 1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 3, 1};  // x and y parallel
  doc["nodes"][2].erase("translation");
  expectError(doc, "degenerate");
  doc = triangle();
  doc["nodes"][2]["translation"] = {1e39, 0, 0};
  expectError(doc, "translation");
  doc = triangle();
  doc["cameras"][0]["perspective"]["yfov"] = 4.0;  // >= pi
  expectError(doc, "yfov");
  doc["cameras"][0]["perspective"]["yfov"] = 0.0;
  expectError(doc, "yfov");
  doc = triangle();
  doc["cameras"][0]["perspective"]["zfar"] = 0.05;  // nearer than znear 0.1
  expectError(doc, "zfar");
  doc["cameras"][0]["perspective"]["zfar"] = 0;  // tinygltf's way of writing "infinite"
  Loaded r = load(doc);
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_TRUE(allFinite(r.scene));
}

TEST(HostileGltf, GeometryBeyondWhatAFloatCameraFramesIsAnError) {
  json doc = triangle({-3e38f, 0, 0, 3e38f, 0, 0, 0, 1, 0});
  doc["nodes"].erase(2);  // no camera: the orbit must frame the bounds
  doc["scenes"][0]["nodes"] = {0, 1};
  expectError(doc, "too large to frame");
}

// ---- warnings and textures
// -----------------------------------------------------------------------

std::string capturedStderr(const std::function<void()>& f) {
  ::testing::internal::CaptureStderr();
  f();
  return ::testing::internal::GetCapturedStderr();
}

TEST(HostileGltf, NoWarningLinePrecedesTheError) {
  // A required extension that is loaded without (a warning) and an accessor past its data.
  json doc = triangle();
  doc["extensionsRequired"] = {"KHR_texture_transform"};
  doc["extensionsUsed"].push_back("KHR_texture_transform");
  doc["accessors"][0]["count"] = 30;
  std::filesystem::path path =
      std::filesystem::temp_directory_path() / "tileshade_hostile_warn.gltf";
  std::ofstream(path) << doc.dump();
  std::string err = capturedStderr([&] { EXPECT_THROW(ts::loadGltf(path.string()), ts::Error); });
  EXPECT_EQ(err, "");
  ts::SceneOptions o;
  o.lightCount = 5;  // more than the file has: the error follows the loading
  doc["accessors"][0]["count"] = 3;
  std::ofstream(path) << doc.dump();
  err = capturedStderr([&] { EXPECT_THROW(ts::loadScene(path.string(), o), ts::Error); });
  EXPECT_EQ(err, "");
  o.lightCount = 1;
  err = capturedStderr([&] { ts::loadScene(path.string(), o); });
  EXPECT_NE(err.find("required extension(s) not supported"), std::string::npos) << err;
  std::filesystem::remove(path);
}

// The triangle textured, its TEXCOORD_0 the positions' first two floats of each vertex.
json texturedTriangle(const std::string& uri) {
  json doc = triangle();
  doc["materials"] = {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}};
  doc["meshes"][0]["primitives"][0]["material"] = 0;
  doc["textures"] = {{{"source", 0}}};
  doc["images"] = {{{"uri", uri}}};
  doc["accessors"].push_back(
      {{"bufferView", 0}, {"componentType", 5126}, {"count", 3}, {"type", "VEC2"}});
  doc["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = 2;
  return doc;
}

TEST(HostileGltf, AMissingTextureIsWarnedOnce) {
  Loaded r = load(texturedTriangle("missing.png"));
  ASSERT_TRUE(r.ok) << r.error;
  std::string all;
  for (const auto& w : r.warnings) all += w + "\n";
  ASSERT_EQ(r.warnings.size(), 1u) << all;
  EXPECT_NE(r.warnings[0].find("missing.png (not found)"), std::string::npos) << r.warnings[0];
}

std::vector<unsigned char> pngHeader(uint32_t width, uint32_t height, bool goodCrc) {
  std::vector<unsigned char> png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n',
                                    0,    0,   0,   13,  'I',  'H',  'D',  'R'};
  for (uint32_t v : {width, height})
    for (int k = 3; k >= 0; --k) png.push_back((unsigned char)(v >> (8 * k)));
  for (unsigned char c : {8, 2, 0, 0, 0}) png.push_back(c);
  for (int k = 0; k < 4; ++k) png.push_back(goodCrc ? 0 : 0xAB);
  for (int k = 0; k < 64; ++k) png.push_back((unsigned char)k);
  return png;
}

TEST(HostileGltf, ACorruptTextureGivesOneWarningWithoutARawLibpngLine) {
  std::string uri = "data:image/png;base64," + base64(pngHeader(16, 16, false));
  Loaded r;
  std::string err = capturedStderr([&] { r = load(texturedTriangle(uri)); });
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(err.find("libpng"), std::string::npos) << err;  // routed into the warning instead
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_NE(r.warnings[0].find("could not be decoded"), std::string::npos) << r.warnings[0];
}

TEST(HostileGltf, ATextureClaimingBillionsOfTexelsIsRefusedBeforeDecoding) {
  std::string uri = "data:image/png;base64," + base64(pngHeader(100000, 100000, true));
  Loaded r = load(texturedTriangle(uri));
  ASSERT_TRUE(r.ok) << r.error;
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_NE(r.warnings[0].find("100000x100000 texels"), std::string::npos) << r.warnings[0];
}

TEST(HostileGltf, FarOffTextureCoordinatesWrapWithoutOverflow) {
  ts::Texture t;
  t.width = 2;
  t.height = 2;
  t.texels = {glm::vec4(1), glm::vec4(2), glm::vec4(3), glm::vec4(4)};
  for (auto wrap :
       {ts::TextureWrap::Repeat, ts::TextureWrap::ClampToEdge, ts::TextureWrap::MirroredRepeat}) {
    t.wrapS = t.wrapT = wrap;
    for (float u : {1e10f, -1e10f, 3e38f, -3e38f}) {
      glm::vec4 v = t.sample({u, 0.25f});
      EXPECT_TRUE(std::isfinite(v.x)) << u;
      EXPECT_GE(v.x, 1.0f);
      EXPECT_LE(v.x, 4.0f);
    }
  }
}

// OpenGL's wrap functions for LINEAR filtering on two texels [1, 3] along u (centres at u = 0.25
// and 0.75): REPEAT blends across the edge, CLAMP_TO_EDGE holds the edge texel, MIRRORED_REPEAT
// reflects every period of 1.
TEST(HostileGltf, TextureWrapModesFollowOpenGL) {
  ts::Texture t;
  t.width = 2;
  t.height = 1;
  t.texels = {glm::vec4(1.0f), glm::vec4(3.0f)};
  auto at = [&](ts::TextureWrap wrap, float u) {
    t.wrapS = wrap;
    return t.sample({u, 0.5f}).x;
  };
  using W = ts::TextureWrap;
  EXPECT_FLOAT_EQ(at(W::Repeat, 0.0f), 2.0f);
  EXPECT_FLOAT_EQ(at(W::Repeat, 1.25f), 1.0f);
  EXPECT_FLOAT_EQ(at(W::ClampToEdge, 0.0f), 1.0f);
  EXPECT_FLOAT_EQ(at(W::ClampToEdge, -7.0f), 1.0f);
  EXPECT_FLOAT_EQ(at(W::ClampToEdge, 1.0f), 3.0f);
  EXPECT_FLOAT_EQ(at(W::ClampToEdge, 9.0f), 3.0f);
  EXPECT_FLOAT_EQ(at(W::ClampToEdge, 0.5f), 2.0f);
  EXPECT_FLOAT_EQ(at(W::MirroredRepeat, 0.0f), 1.0f);
  EXPECT_FLOAT_EQ(at(W::MirroredRepeat, 1.0f), 3.0f);    // the edge of the mirror
  EXPECT_FLOAT_EQ(at(W::MirroredRepeat, 1.25f), 3.0f);   // = u 0.75
  EXPECT_FLOAT_EQ(at(W::MirroredRepeat, 1.75f), 1.0f);   // = u 0.25
  EXPECT_FLOAT_EQ(at(W::MirroredRepeat, -0.25f), 1.0f);  // = u 0.25
  EXPECT_FLOAT_EQ(at(W::MirroredRepeat, 2.75f), 3.0f);   // period 2
  EXPECT_FLOAT_EQ(at(W::MirroredRepeat, 1.5f), 2.0f);
}

TEST(HostileGltf, TheNearestFilterPicksTheTexelUnderTheCoordinate) {
  ts::Texture t;
  t.width = 2;
  t.height = 1;
  t.texels = {glm::vec4(1.0f), glm::vec4(3.0f)};
  t.nearest = true;
  auto at = [&](ts::TextureWrap wrap, float u) {
    t.wrapS = wrap;
    return t.sample({u, 0.5f}).x;
  };
  using W = ts::TextureWrap;
  EXPECT_FLOAT_EQ(at(W::Repeat, 0.49f), 1.0f);
  EXPECT_FLOAT_EQ(at(W::Repeat, 0.51f), 3.0f);
  EXPECT_FLOAT_EQ(at(W::Repeat, -0.25f), 3.0f);
  EXPECT_FLOAT_EQ(at(W::ClampToEdge, -3.0f), 1.0f);
  EXPECT_FLOAT_EQ(at(W::ClampToEdge, 3.0f), 3.0f);
  EXPECT_FLOAT_EQ(at(W::MirroredRepeat, 1.25f), 3.0f);
  EXPECT_FLOAT_EQ(at(W::MirroredRepeat, 1.75f), 1.0f);
  t.nearest = false;
  EXPECT_FLOAT_EQ(at(W::Repeat, 0.5f), 2.0f);  // the bilinear blend, for contrast
}

// ---- issue #16: options that were ignored, messages with the wrong cause ----------------------

json texturedTriangleWithUVs() {
  return texturedTriangle("data:image/png;base64," + base64(pngHeader(2, 2, true)));
}

std::string warningWith(const Loaded& r, const std::string& fragment) {
  for (const auto& w : r.warnings)
    if (w.find(fragment) != std::string::npos) return w;
  return "";
}

TEST(HostileGltf, MinificationFiltersUnlikeTheMagnificationOneAreWarned) {
  json doc = texturedTriangleWithUVs();
  doc["samplers"] = {{{"wrapS", 33071}, {"wrapT", 33648}, {"magFilter", 9728}, {"minFilter", 9984}},
                     {{"minFilter", 9986}},
                     {{"magFilter", 9728}, {"minFilter", 9987}}};
  doc["textures"] = {{{"source", 0}, {"sampler", 0}},
                     {{"source", 0}, {"sampler", 1}},
                     {{"source", 0}, {"sampler", 2}}};
  doc["materials"][0]["emissiveTexture"] = {{"index", 1}};
  doc["materials"][0]["pbrMetallicRoughness"]["metallicRoughnessTexture"] = {{"index", 2}};
  Loaded r = load(doc);
  ASSERT_TRUE(r.ok) << r.error;
  // Wrap modes and the magnification filter are modelled (TextureWrapModesFollowOpenGL,
  // TheNearestFilterPicksTheTexelUnderTheCoordinate); sampler 0's NEAREST minification is the
  // same choice; the other two minify otherwise than they magnify.
  const std::string w = warningWith(r, "sampler setting");
  EXPECT_NE(w.find("2 sampler setting(s)"), std::string::npos) << w;
  EXPECT_NE(w.find("samplers[1].minFilter NEAREST (magFilter LINEAR)"), std::string::npos) << w;
  EXPECT_NE(w.find("samplers[2].minFilter LINEAR (magFilter NEAREST)"), std::string::npos) << w;
  EXPECT_EQ(w.find("samplers[0]"), std::string::npos) << w;
  // A value outside the specification's enumeration is an error, not the default.
  doc["samplers"][0]["wrapS"] = 33072;
  expectError(doc, "samplers[0].wrapS: expected one of 33071, 33648, 10497, got 33072");
  // glTF's defaults, the exporter's samplers and NEAREST throughout say nothing.
  doc["samplers"] = {{{"wrapS", 10497}, {"magFilter", 9729}, {"minFilter", 9987}},
                     json::object(),
                     {{"magFilter", 9728}, {"minFilter", 9728}}};
  Loaded plain = load(doc);
  ASSERT_TRUE(plain.ok) << plain.error;
  EXPECT_EQ(warningWith(plain, "sampler"), "");
}

TEST(HostileGltf, KhrTextureTransformIsWarned) {
  json doc = texturedTriangleWithUVs();
  doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"] = {
      {"KHR_texture_transform", {{"offset", {0.5, 0}}, {"scale", {2, 2}}}}};
  doc["extensionsUsed"].push_back("KHR_texture_transform");
  Loaded r = load(doc);
  ASSERT_TRUE(r.ok) << r.error;
  const std::string w = warningWith(r, "KHR_texture_transform");
  EXPECT_NE(w.find("materials[0].pbrMetallicRoughness.baseColorTexture"), std::string::npos) << w;
}

TEST(HostileGltf, ATexCoordSetThePrimitiveLacksIsAnError) {
  json doc = texturedTriangleWithUVs();
  ASSERT_TRUE(load(doc).ok);
  doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["texCoord"] = 1;
  expectError(doc, "samples texCoord 1 but the primitive has no TEXCOORD_1");
  doc = texturedTriangleWithUVs();
  doc["materials"][0]["emissiveTexture"] = {{"index", 0}, {"texCoord", 3}};
  expectError(doc, "emissiveTexture samples texCoord 3");
}

TEST(HostileGltf, ADeepNodeChainIsTooDeepNotACycle) {
  auto chain = [](int levels) {
    json doc = triangle();
    json& nodes = doc["nodes"];
    nodes[0]["children"] = {3};
    for (int i = 0; i < levels - 1; ++i) {
      json n = json::object();
      if (i + 1 < levels - 1) n["children"] = {int(nodes.size()) + 1};
      nodes.push_back(n);
    }
    return doc;
  };
  EXPECT_TRUE(load(chain(1000)).ok) << load(chain(1000)).error;
  expectError(chain(1001), "deeper than 1000 levels");
  EXPECT_EQ(load(chain(1001)).error.find("cycle"), std::string::npos);
}

TEST(HostileGltf, ANodeCycleIsAnErrorNotDroppedSilently) {
  json doc = triangle();
  doc["nodes"].push_back({{"children", {4}}, {"mesh", 0}});  // 3 -> 4 -> 5 -> 3, no root
  doc["nodes"].push_back({{"children", {5}}});
  doc["nodes"].push_back({{"children", {3}}});
  expectError(doc, "node hierarchy has a cycle through node");
  doc.erase("scenes");
  doc.erase("scene");
  expectError(doc, "node hierarchy has a cycle through node");
  doc["nodes"][5]["children"] = json::array();  // a chain: fine
  EXPECT_TRUE(load(doc).ok) << load(doc).error;
}

TEST(HostileGltf, LightsGivenAsAnObjectAreBlamedNotTheNode) {
  json doc = triangle();
  doc["extensions"]["KHR_lights_punctual"]["lights"] = {{"type", "point"}};
  Loaded r = load(doc);
  ASSERT_FALSE(r.ok);
  EXPECT_NE(r.error.find("extensions.KHR_lights_punctual.lights: expected an array"),
            std::string::npos)
      << r.error;
  EXPECT_EQ(r.error.find("nodes"), std::string::npos) << r.error;
}

TEST(HostileGltf, AYfovThatRoundsToPiAsAFloatIsRefused) {
  json doc = triangle();
  doc["cameras"][0]["perspective"]["yfov"] = 3.14159264;  // below pi; its float is above
  expectError(doc, "yfov 3.14159264 is not below pi (3.141592653589793) as a float");
  doc["cameras"][0]["perspective"]["yfov"] = 3.1415925;  // the largest float below pi
  EXPECT_TRUE(load(doc).ok);
}

// ---- the fuzzers' findings
// --------------------------------------------------------------------------

// Files under tests/data/fuzz/: inputs the fuzzers found crashing, hanging or leaking before the
// fix. Each must load or fail with one line (the sanitizer build runs this too).
TEST(HostileGltf, FuzzerFindingsLoadOrFailCleanly) {
  std::filesystem::path dir =
      std::filesystem::path(ts::test::sourceDir()) / "tests" / "data" / "fuzz";
  if (!std::filesystem::exists(dir)) GTEST_SKIP() << dir << " absent";
  size_t files = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    if (e.path().extension() != ".gltf" && e.path().extension() != ".glb") continue;
    ++files;
    std::ifstream in(e.path(), std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    Loaded r = load(bytes);
    if (!r.ok) {
      EXPECT_EQ(r.error.find('\n'), std::string::npos) << e.path() << ": " << r.error;
    } else {
      EXPECT_TRUE(allFinite(r.scene)) << e.path();
    }
  }
  EXPECT_GT(files, 0u);
}

}  // namespace
