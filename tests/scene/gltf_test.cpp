// glTF 2.0 loading and export (src/scene/gltf_loader.cpp, gltf_export.cpp).
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>

#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "scene/material_mapping.h"
#include "scene/scene_loader.h"
#include "test_support.h"
#include "util/error.h"

namespace fs = std::filesystem;

namespace {

using ts::Scene;

// A fresh temporary folder per test, removed afterwards.
class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = fs::temp_directory_path() / ("tileshade_gltf_" + std::string(info->test_suite_name()) +
                                         "_" + info->name() + "_" + std::to_string(::getpid()));
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() { fs::remove_all(path_); }
  std::string file(const std::string& name) const { return (path_ / name).string(); }
  void write(const std::string& name, const std::string& text) const {
    std::ofstream(file(name), std::ios::binary) << text;
  }
  void write(const std::string& name, const std::vector<unsigned char>& bytes) const {
    std::ofstream(file(name), std::ios::binary)
        .write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  }

 private:
  fs::path path_;
};

struct Bytes {
  std::vector<unsigned char> data;
  template <typename T>
  void put(T v) {
    unsigned char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    data.insert(data.end(), b, b + sizeof(T));
  }
  void align4() {
    while (data.size() % 4) data.push_back(0);
  }
};

void expectVec(glm::vec3 got, glm::vec3 want, float tol = 1e-5f) {
  EXPECT_NEAR(got.x, want.x, tol);
  EXPECT_NEAR(got.y, want.y, tol);
  EXPECT_NEAR(got.z, want.z, tol);
}

bool contains(const std::string& haystack, const std::string& needle) {
  return haystack.find(needle) != std::string::npos;
}

// A parent node (translate (1,2,3) * rotate 90° about +Y * scale 2) with children: a mesh node,
// point lights (TRS and matrix), a spot light; and a camera at the root.
const char* kHierarchyGltf = R"({
  "asset": {"version": "2.0"},
  "scene": 0,
  "scenes": [{"nodes": [0, 4]}],
  "nodes": [
    {"name": "parent", "translation": [1, 2, 3],
     "rotation": [0, 0.7071067811865476, 0, 0.7071067811865476], "scale": [2, 2, 2],
     "children": [1, 2, 3, 5]},
    {"name": "meshNode", "translation": [1, 0, 0], "mesh": 0},
    {"name": "pointNode", "translation": [0, 1, 0],
     "extensions": {"KHR_lights_punctual": {"light": 0}}},
    {"name": "matrixLight", "matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,1,1],
     "extensions": {"KHR_lights_punctual": {"light": 1}}},
    {"name": "camera", "translation": [0, 1, 10], "camera": 0},
    {"name": "spotNode", "extensions": {"KHR_lights_punctual": {"light": 2}}}
  ],
  "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.05}}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
  "accessors": [
    {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
     "min": [0, 0, 0], "max": [1, 1, 0]},
    {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}
  ],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36},
                  {"buffer": 0, "byteOffset": 36, "byteLength": 6}],
  "buffers": [{"uri": "tri.bin", "byteLength": 44}],
  "extensionsUsed": ["KHR_lights_punctual"],
  "extensions": {"KHR_lights_punctual": {"lights": [
    {"type": "point", "color": [1, 0.5, 0.25], "intensity": 4, "range": 5},
    {"type": "point", "intensity": 1.953125},
    {"type": "spot", "intensity": 3, "spot": {"innerConeAngle": 0.1, "outerConeAngle": 0.5}}
  ]}}
})";

void writeHierarchy(const TempDir& dir) {
  Bytes b;
  for (float v : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) b.put(v);
  for (uint16_t i : {0, 1, 2}) b.put(i);
  b.align4();
  dir.write("tri.bin", b.data);
  dir.write("scene.gltf", kHierarchyGltf);
}

TEST(GltfLoad, NodeHierarchyLightsAndCamera) {
  TempDir dir;
  writeHierarchy(dir);
  ::testing::internal::CaptureStderr();
  Scene s = ts::loadGltf(dir.file("scene.gltf"));
  std::string err = ::testing::internal::GetCapturedStderr();

  // Triangle (0,0,0),(1,0,0),(0,1,0) under child T(1,0,0) under T(1,2,3) R_y(90°) S(2).
  ASSERT_EQ(s.triangleCount(), 1u);
  glm::vec3 p[3];
  for (int k = 0; k < 3; ++k) p[k] = s.vertices[s.indices[size_t(k)]].position;
  expectVec(p[0], {1, 2, 1});
  expectVec(p[1], {1, 2, -1});
  expectVec(p[2], {1, 4, 1});
  // No normals in the file: flat normals, rotated with the node (+Z -> +X), CCW kept.
  for (int k = 0; k < 3; ++k) expectVec(s.vertices[s.indices[size_t(k)]].normal, {1, 0, 0});
  EXPECT_GT(glm::dot(glm::cross(p[1] - p[0], p[2] - p[0]), glm::vec3(1, 0, 0)), 0.0f);
  ASSERT_EQ(s.materials.size(), 1u);  // the grey default

  // Point lights: colour x intensity; range from the file or from the 5/256 threshold.
  ASSERT_EQ(s.lights.size(), 3u);
  EXPECT_EQ(s.lights[0].type, ts::SceneLightType::Point);
  EXPECT_EQ(s.lights[1].type, ts::SceneLightType::Point);
  expectVec(s.lights[0].position, {1, 4, 3});
  expectVec(s.lights[0].color, {4, 2, 1});
  EXPECT_FLOAT_EQ(s.lights[0].range, 5.0f);
  expectVec(s.lights[1].position, {3, 2, 3});
  expectVec(s.lights[1].color, glm::vec3(1.953125f));
  EXPECT_NEAR(s.lights[1].range, 10.0f, 1e-4f);  // sqrt(1.953125 / (5/256))

  // The spot light: its cone angles, colour x intensity, range from the threshold; no warning.
  EXPECT_EQ(s.lights[2].type, ts::SceneLightType::Spot);
  EXPECT_FLOAT_EQ(s.lights[2].innerConeAngle, 0.1f);
  EXPECT_FLOAT_EQ(s.lights[2].outerConeAngle, 0.5f);
  expectVec(s.lights[2].color, glm::vec3(3.0f));
  EXPECT_NEAR(glm::length(s.lights[2].direction), 1.0f, 1e-6f);
  EXPECT_TRUE(err.empty()) << err;

  // Frame 0 is the file's camera; then an orbit of >= 120 frames.
  ASSERT_GE(s.cameraPath.size(), 121u);
  const ts::SceneCamera& c = s.cameraPath[0];
  expectVec(glm::vec3(glm::inverse(c.viewFromWorld)[3]), {0, 1, 10});
  expectVec(glm::vec3(c.viewFromWorld * glm::vec4(0, 1, 0, 1)), {0, 0, -10});
  EXPECT_FLOAT_EQ(c.yfov, 0.8f);
  EXPECT_FLOAT_EQ(c.znear, 0.05f);
  EXPECT_GT(c.zfar, 10.0f);  // infinite in the file: a finite far plane beyond the scene
  // Orbit frames look at the bounds' centre.
  glm::vec3 centre = s.bounds().center();
  for (size_t k = 1; k < s.cameraPath.size(); k += 30) {
    glm::vec3 v = glm::vec3(s.cameraPath[k].viewFromWorld * glm::vec4(centre, 1.0f));
    EXPECT_NEAR(v.x, 0.0f, 1e-3f);
    EXPECT_NEAR(v.y, 0.0f, 1e-3f);
    EXPECT_LT(v.z, 0.0f);
  }
}

// Node transforms are composed in double, as the file's numbers are: 1e6 from the origin a float
// matrix would round the camera's position by up to 1/32 and move the whole view (issue #12).
TEST(GltfLoad, TransformsFarFromTheOriginStayInDouble) {
  TempDir dir;
  nlohmann::json j = nlohmann::json::parse(kHierarchyGltf);
  j["scenes"] = {{{"nodes", {0}}}};
  j["nodes"] = {{{"name", "far"}, {"translation", {1000000.3, 0, 0}}, {"children", {1, 2}}},
                {{"name", "meshNode"}, {"mesh", 0}},
                {{"name", "camera"}, {"translation", {0, 0, 10}}, {"camera", 0}}};
  j.erase("extensionsUsed");
  j.erase("extensions");
  writeHierarchy(dir);
  dir.write("far.gltf", j.dump());
  Scene s = ts::loadGltf(dir.file("far.gltf"));
  // The vertex at the node's origin is stored as the nearest float, 1000000.3125; the camera
  // stays at 1000000.3, so the vertex lies 0.0125 to its right.
  ASSERT_FALSE(s.vertices.empty());
  EXPECT_EQ(s.vertices[0].position.x, 1000000.3125f);
  glm::dvec4 v =
      s.cameraPath[0].viewFromWorld * glm::dvec4(glm::dvec3(s.vertices[0].position), 1.0);
  EXPECT_NEAR(v.x, 0.0125, 1e-6);
  EXPECT_NEAR(v.z, -10.0, 1e-9);
}

TEST(GltfLoad, LoadSceneAppliesLightCountAndRange) {
  TempDir dir;
  writeHierarchy(dir);
  ts::SceneOptions o;
  o.lightCount = 1;
  o.lightRange = 7.0f;
  ::testing::internal::CaptureStderr();
  Scene s = ts::loadScene(dir.file("scene.gltf"), o);
  ASSERT_EQ(s.lights.size(), 1u);
  EXPECT_EQ(s.lights[0].range, 7.0f);
  expectVec(s.lights[0].color, {4, 2, 1});
  o.lightCount = 5;  // the file has 2 point lights
  EXPECT_THROW(ts::loadScene(dir.file("scene.gltf"), o), ts::Error);
  o = ts::SceneOptions{};
  o.lightSet = "many";
  EXPECT_THROW(ts::loadScene(dir.file("scene.gltf"), o), ts::Error);
  ::testing::internal::GetCapturedStderr();
}

// Interleaved (strided) float attributes, normalized UNSIGNED_BYTE texcoords, UNSIGNED_BYTE
// indices of a triangle strip, a sparse accessor, a non-indexed primitive of normalized SHORT
// positions without normals, and a POINTS primitive that must be skipped.
TEST(GltfLoad, AccessorsStridesNormalizedSparseAndModes) {
  TempDir dir;
  Bytes b;
  const float quad[4][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  for (auto& q : quad) {
    for (float v : q) b.put(v);
    for (float v : {0.f, 0.f, 2.f}) b.put(v);  // unnormalized normal
  }                                            // 0..96
  for (uint8_t v : {0, 0, 0, 0, 255, 0, 0, 0, 255, 255, 0, 0, 0, 255, 0, 0}) b.put(v);  // 96..112
  for (uint8_t v : {0, 1, 3, 2}) b.put(v);                                              // 112..116
  b.put(uint8_t(2));                                                                    // 116
  b.align4();
  for (float v : {2.f, 2.f, 0.f}) b.put(v);  // 120..132
  const int16_t shorts[3][3] = {{32767, 0, 0}, {0, 32767, 0}, {0, 0, 32767}};
  for (auto& s : shorts) {
    for (int16_t v : s) b.put(v);
    b.put(int16_t(0));
  }  // 132..156
  ASSERT_EQ(b.data.size(), 156u);
  dir.write("mesh.bin", b.data);
  dir.write("mesh.gltf", R"({
    "asset": {"version": "2.0"},
    "scenes": [{"nodes": [0]}],
    "nodes": [{"mesh": 0}],
    "meshes": [{"primitives": [
      {"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}, "indices": 3, "mode": 5},
      {"attributes": {"POSITION": 4}},
      {"attributes": {"POSITION": 0}, "mode": 0}
    ]}],
    "accessors": [
      {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
       "min": [0, 0, 0], "max": [2, 2, 0],
       "sparse": {"count": 1, "indices": {"bufferView": 3, "componentType": 5121},
                  "values": {"bufferView": 4}}},
      {"bufferView": 0, "byteOffset": 12, "componentType": 5126, "count": 4, "type": "VEC3"},
      {"bufferView": 1, "componentType": 5121, "normalized": true, "count": 4, "type": "VEC2"},
      {"bufferView": 2, "componentType": 5121, "count": 4, "type": "SCALAR"},
      {"bufferView": 5, "componentType": 5122, "normalized": true, "count": 3, "type": "VEC3",
       "min": [0, 0, 0], "max": [1, 1, 1]}
    ],
    "bufferViews": [
      {"buffer": 0, "byteOffset": 0, "byteLength": 96, "byteStride": 24},
      {"buffer": 0, "byteOffset": 96, "byteLength": 16, "byteStride": 4},
      {"buffer": 0, "byteOffset": 112, "byteLength": 4},
      {"buffer": 0, "byteOffset": 116, "byteLength": 1},
      {"buffer": 0, "byteOffset": 120, "byteLength": 12},
      {"buffer": 0, "byteOffset": 132, "byteLength": 24, "byteStride": 8}
    ],
    "buffers": [{"uri": "mesh.bin", "byteLength": 156}]
  })");
  ::testing::internal::CaptureStderr();
  Scene s = ts::loadGltf(dir.file("mesh.gltf"));
  std::string err = ::testing::internal::GetCapturedStderr();
  EXPECT_TRUE(contains(err, "skipped 1 primitive")) << err;

  ASSERT_EQ(s.triangleCount(), 3u);  // 2 from the strip, 1 non-indexed
  ASSERT_GE(s.vertices.size(), 7u);
  expectVec(s.vertices[0].position, {0, 0, 0});
  expectVec(s.vertices[2].position, {2, 2, 0});  // replaced by the sparse values
  expectVec(s.vertices[1].normal, {0, 0, 1});    // normalized
  EXPECT_FLOAT_EQ(s.vertices[1].uv.x, 1.0f);
  EXPECT_FLOAT_EQ(s.vertices[1].uv.y, 0.0f);
  EXPECT_FLOAT_EQ(s.vertices[2].uv.y, 1.0f);
  EXPECT_FLOAT_EQ(s.vertices[3].uv.x, 0.0f);
  // Strip 0,1,3,2 -> (0,1,3), (3,1,2): both counter-clockwise.
  EXPECT_EQ(std::vector<uint32_t>(s.indices.begin(), s.indices.begin() + 6),
            (std::vector<uint32_t>{0, 1, 3, 3, 1, 2}));
  // Normalized shorts: 32767 -> 1; flat normal of the (1,0,0),(0,1,0),(0,0,1) triangle.
  glm::vec3 q[3];
  for (int k = 0; k < 3; ++k) q[k] = s.vertices[s.indices[6 + size_t(k)]].position;
  expectVec(q[0], {1, 0, 0});
  expectVec(q[1], {0, 1, 0});
  expectVec(q[2], {0, 0, 1});
  expectVec(s.vertices[s.indices[6]].normal, glm::vec3(1.0f / std::sqrt(3.0f)));
  EXPECT_EQ(s.vertices[s.indices[6]].uv, glm::vec2(0.0f));  // no UVs -> 0
}

TEST(GltfLoad, BadFilesThrowWithThePath) {
  TempDir dir;
  auto expectError = [&](const std::string& path, const std::string& fragment) {
    try {
      ts::loadGltf(path);
      ADD_FAILURE() << "no exception for " << path;
    } catch (const ts::Error& e) {
      std::string m = e.what();
      EXPECT_TRUE(contains(m, path)) << m;
      EXPECT_TRUE(contains(m, fragment)) << m;
      EXPECT_FALSE(contains(m, "\n")) << m;
    }
  };
  expectError(dir.file("missing.gltf"), "no such file");
  dir.write("garbage.gltf", "this is not JSON at all");
  expectError(dir.file("garbage.gltf"), "cannot load");
  dir.write("garbage.glb", std::string("glTF\x02\0\0\0garbage", 15));
  expectError(dir.file("garbage.glb"), "cannot load");
  // Valid JSON whose accessor runs past its buffer.
  Bytes b;
  for (int i = 0; i < 9; ++i) b.put(0.0f);
  dir.write("short.bin", b.data);
  dir.write("short.gltf", R"({"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}],
    "nodes": [{"mesh": 0}], "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 30, "type": "VEC3",
                   "min": [0,0,0], "max": [0,0,0]}],
    "bufferViews": [{"buffer": 0, "byteLength": 36}],
    "buffers": [{"uri": "short.bin", "byteLength": 36}]})");
  expectError(dir.file("short.gltf"), "past");
  EXPECT_THROW(ts::loadScene(dir.file("missing.glb"), {}), ts::Error);
}

// ---- export ----------------------------------------------------------------------------------

struct MaterialStats {
  size_t triangles = 0;
  double area = 0.0;
  glm::dvec3 centroidSum{0.0};
};

std::map<std::string, MaterialStats> statsByMaterial(const Scene& s) {
  std::map<std::string, MaterialStats> out;
  for (size_t t = 0; t < s.triangleCount(); ++t) {
    glm::vec3 a = s.vertices[s.indices[3 * t]].position,
              b = s.vertices[s.indices[3 * t + 1]].position,
              c = s.vertices[s.indices[3 * t + 2]].position;
    auto& m = out[s.materials[s.triangleMaterial[t]].name];
    ++m.triangles;
    m.area += 0.5 * double(glm::length(glm::cross(b - a, c - a)));
    m.centroidSum += glm::dvec3(a + b + c) / 3.0;
  }
  return out;
}

void expectRoundTrip(const Scene& original, const Scene& loaded) {
  ASSERT_EQ(loaded.triangleCount(), original.triangleCount());
  auto a = statsByMaterial(original), b = statsByMaterial(loaded);
  ASSERT_EQ(a.size(), b.size());
  for (const auto& [name, sa] : a) {
    SCOPED_TRACE(name);
    ASSERT_TRUE(b.count(name));
    const auto& sb = b.at(name);
    EXPECT_EQ(sa.triangles, sb.triangles);
    EXPECT_NEAR(sa.area, sb.area, 1e-6 * sa.area + 1e-9);
    EXPECT_NEAR(glm::length(sa.centroidSum - sb.centroidSum), 0.0,
                1e-6 * (1.0 + glm::length(sa.centroidSum)));
  }
  for (const auto& m : loaded.materials) {
    SCOPED_TRACE(m.name);
    auto it = std::find_if(original.materials.begin(), original.materials.end(),
                           [&](const ts::Material& o) { return o.name == m.name; });
    ASSERT_NE(it, original.materials.end());
    expectVec(m.diffuse, it->diffuse, 1e-6f);
    expectVec(m.specular, it->specular, 1e-6f);
    expectVec(m.emissive, it->emissive, 1e-5f);
    EXPECT_NEAR(m.shininess, it->shininess, 0.01f * it->shininess);
    EXPECT_EQ(m.doubleSided, it->doubleSided);
    EXPECT_EQ(m.alphaMode, it->alphaMode);
    EXPECT_FLOAT_EQ(m.alphaCutoff, it->alphaCutoff);
    EXPECT_FLOAT_EQ(m.opacity, it->opacity);
    EXPECT_EQ(m.model, it->model);
    if (m.model == ts::ShadingModel::MetallicRoughness) {
      expectVec(m.baseColor, it->baseColor, 1e-6f);
      EXPECT_FLOAT_EQ(m.metallic, it->metallic);
      EXPECT_FLOAT_EQ(m.roughness, it->roughness);
    }
  }
  ASSERT_EQ(loaded.lights.size(), original.lights.size());
  for (size_t i = 0; i < original.lights.size(); ++i) {
    const ts::SceneLight &a = original.lights[i], &b = loaded.lights[i];
    EXPECT_EQ(b.type, a.type) << "light " << i;
    expectVec(b.color, a.color, 1e-5f);
    if (a.hasRange()) {
      expectVec(b.position, a.position, 1e-5f);
      EXPECT_EQ(b.range, a.range);
    }
    if (a.type != ts::SceneLightType::Point) expectVec(b.direction, a.direction, 1e-6f);
    if (a.type == ts::SceneLightType::Spot) {
      EXPECT_FLOAT_EQ(b.innerConeAngle, a.innerConeAngle) << "light " << i;
      EXPECT_FLOAT_EQ(b.outerConeAngle, a.outerConeAngle) << "light " << i;
    }
  }
  expectVec(loaded.ambient, original.ambient, 1e-7f);
  ASSERT_FALSE(loaded.cameraPath.empty());
  const ts::SceneCamera &c0 = original.cameraPath[0], &c1 = loaded.cameraPath[0];
  for (int col = 0; col < 4; ++col)
    for (int row = 0; row < 4; ++row)
      EXPECT_NEAR(c1.viewFromWorld[col][row], c0.viewFromWorld[col][row],
                  1e-4f * (1.0f + std::fabs(c0.viewFromWorld[col][row])));
  EXPECT_FLOAT_EQ(c1.yfov, c0.yfov);
  EXPECT_FLOAT_EQ(c1.znear, c0.znear);
  EXPECT_FLOAT_EQ(c1.zfar, c0.zfar);
}

TEST(GltfExport, StreetRoundTripsThroughGltf) {
  TempDir dir;
  Scene street = ts::makeBuiltinScene("street", "many", 1);
  std::string path = dir.file("street.gltf");
  ts::exportGltf(street, path);
  // Self-contained: the buffer is a data URI; the extensions are declared.
  nlohmann::json j = nlohmann::json::parse(std::ifstream(path));
  ASSERT_EQ(j["buffers"].size(), 1u);
  EXPECT_EQ(j["buffers"][0]["uri"].get<std::string>().rfind("data:", 0), 0u);
  std::set<std::string> used(j["extensionsUsed"].begin(), j["extensionsUsed"].end());
  EXPECT_TRUE(used.count("KHR_lights_punctual"));
  EXPECT_TRUE(used.count("KHR_materials_specular"));
  EXPECT_TRUE(used.count("KHR_materials_emissive_strength"));  // the robots' eyes are > 1
  EXPECT_EQ(j["extensions"]["KHR_lights_punctual"]["lights"].size(), 924u);
  EXPECT_EQ(j["extensions"]["KHR_lights_punctual"]["lights"][0]["range"].get<double>(), 12.5);
  EXPECT_EQ(j["meshes"].size(), 1u);
  EXPECT_EQ(j["cameras"][0]["type"], "perspective");

  ::testing::internal::CaptureStderr();
  Scene loaded = ts::loadGltf(path);
  std::string err = ::testing::internal::GetCapturedStderr();
  EXPECT_TRUE(err.empty()) << err;
  expectRoundTrip(street, loaded);
}

TEST(GltfExport, AtriumRoundTripsThroughGlb) {
  TempDir dir;
  Scene atrium = ts::makeBuiltinScene("atrium", "mixed", 5);
  std::string path = dir.file("atrium.glb");
  ts::exportGltf(atrium, path);
  char magic[4] = {};
  std::ifstream(path, std::ios::binary).read(magic, 4);
  EXPECT_EQ(std::string(magic, 4), "glTF");
  ::testing::internal::CaptureStderr();
  Scene loaded = ts::loadScene(path, {});
  std::string err = ::testing::internal::GetCapturedStderr();
  EXPECT_TRUE(err.empty()) << err;
  expectRoundTrip(atrium, loaded);
}

// Every light type and the metallic-roughness model keep their types and parameters through export
// and load (glTF and GLB).
TEST(GltfExport, SpotDirectionalAndMetallicRoughnessRoundTrip) {
  TempDir dir;
  ts::SceneOptions o;
  o.lightSet = "few";
  o.variant = "spot,sun,metallic-roughness";
  Scene s = ts::loadScene("builtin:street", o);
  s.lights.push_back(ts::SceneLight::spot({1, 5, 2}, {0, 0, 1}, {3, 2, 1}, 7.0f, 0.0f, 1.5707963f));
  s.lights.push_back(
      ts::SceneLight::directional(glm::normalize(glm::vec3(0, -1, -1e-3f)), {1, 1, 1}));
  size_t spots = 0;
  for (const auto& l : s.lights) spots += l.type == ts::SceneLightType::Spot;
  ASSERT_GE(spots, 5u);
  for (const char* name : {"typed.gltf", "typed.glb"}) {
    ts::exportGltf(s, dir.file(name));
    ::testing::internal::CaptureStderr();
    Scene loaded = ts::loadGltf(dir.file(name));
    std::string err = ::testing::internal::GetCapturedStderr();
    EXPECT_TRUE(err.empty()) << err;
    expectRoundTrip(s, loaded);
  }
}

TEST(GltfExport, TexturesRoundTripAsSrgbPng) {
  Scene s;
  s.name = "textured";
  ts::Material m;
  m.name = "checker";
  m.diffuse = glm::vec3(0.9f, 0.8f, 0.7f);
  m.diffuseTexture = 0;
  s.materials.push_back(m);
  ts::Texture t;
  t.width = 4;
  t.height = 2;
  for (int i = 0; i < 8; ++i)
    t.texels.push_back(
        glm::vec4(float(i) / 7.0f, 1.0f - float(i) / 7.0f, i % 2 ? 0.02f : 0.5f, 1.0f));
  s.textures.push_back(t);
  for (glm::vec3 p :
       {glm::vec3(0, 0, 0), glm::vec3(1, 0, 0), glm::vec3(1, 1, 0), glm::vec3(0, 1, 0)}) {
    ts::Vertex v;
    v.position = p;
    v.normal = {0, 0, 1};
    v.uv = {p.x, 1.0f - p.y};
    s.vertices.push_back(v);
  }
  s.indices = {0, 1, 2, 0, 2, 3};
  s.triangleMaterial = {0, 0};
  s.cameraPath.push_back(
      ts::SceneCamera::lookAt({0.5f, 0.5f, 3}, {0.5f, 0.5f, 0}, {0, 1, 0}, 1.0f, 0.1f, 10.0f));
  TempDir dir;
  for (const char* name : {"tex.gltf", "tex.glb"}) {
    SCOPED_TRACE(name);
    ts::exportGltf(s, dir.file(name));
    Scene l = ts::loadGltf(dir.file(name));
    ASSERT_EQ(l.textures.size(), 1u);
    ASSERT_EQ(l.materials[0].diffuseTexture, 0);
    ASSERT_EQ(l.textures[0].width, 4);
    ASSERT_EQ(l.textures[0].height, 2);
    for (size_t i = 0; i < 8; ++i)
      for (int c = 0; c < 4; ++c)
        EXPECT_NEAR(l.textures[0].texels[i][c], t.texels[i][c], 0.006f);  // 8-bit sRGB steps
    expectVec(l.materials[0].diffuse, m.diffuse, 1e-6f);
    EXPECT_EQ(l.vertices[l.indices[1]].uv, s.vertices[s.indices[1]].uv);
  }
}

// alphaMode, alphaCutoff and baseColorFactor's alpha (issue #17) in both models, and the base
// colour texture's alpha channel, kept through export and load.
TEST(GltfExport, AlphaModesCutoffsAndOpacityRoundTrip) {
  Scene s;
  s.name = "alpha";
  ts::Texture t;
  t.width = 2;
  t.height = 1;
  t.texels = {glm::vec4(0.5f, 0.5f, 0.5f, 0.2f), glm::vec4(0.5f, 0.5f, 0.5f, 1.0f)};
  s.textures.push_back(t);
  const ts::AlphaMode modes[] = {ts::AlphaMode::Opaque, ts::AlphaMode::Mask, ts::AlphaMode::Blend};
  for (int k = 0; k < 3; ++k) {
    ts::Material m;
    m.name = "alpha" + std::to_string(k);
    m.model = k == 1 ? ts::ShadingModel::MetallicRoughness : ts::ShadingModel::BlinnPhong;
    m.alphaMode = modes[k];
    m.alphaCutoff = 0.25f + 0.125f * float(k);
    m.opacity = 0.75f - 0.25f * float(k);
    m.diffuseTexture = m.baseColorTexture = 0;
    if (m.model == ts::ShadingModel::MetallicRoughness) ts::fillBlinnPhongTerms(m);
    s.materials.push_back(m);
    for (glm::vec3 p : {glm::vec3(0, 0, 0), glm::vec3(1, 0, 0), glm::vec3(0, 1, 0)}) {
      ts::Vertex v;
      v.position = p + glm::vec3(0, 0, float(k));
      v.normal = {0, 0, 1};
      v.uv = {p.x, p.y};
      s.vertices.push_back(v);
    }
    const uint32_t b = uint32_t(3 * k);
    s.indices.insert(s.indices.end(), {b, b + 1, b + 2});
    s.triangleMaterial.push_back(uint32_t(k));
  }
  s.cameraPath.push_back(
      ts::SceneCamera::lookAt({0.3, 0.3, 5}, {0.3, 0.3, 0}, {0, 1, 0}, 1.0f, 0.1f, 10.0f));
  TempDir dir;
  for (const char* name : {"alpha.gltf", "alpha.glb"}) {
    SCOPED_TRACE(name);
    ts::exportGltf(s, dir.file(name));
    Scene l = ts::loadGltf(dir.file(name));
    expectRoundTrip(s, l);
    ASSERT_EQ(l.materials.size(), 3u);
    EXPECT_EQ(l.materials[2].alphaMode, ts::AlphaMode::Blend);  // not an opaque default
    ASSERT_EQ(l.textures.size(), 1u);
    EXPECT_NEAR(l.textures[0].texels[0].w, 0.2f, 0.5f / 255.0f);
    EXPECT_EQ(l.textures[0].texels[1].w, 1.0f);
  }
}

// glTF sampler wrap modes and filters (issue #16 item 5): kept per scene texture through export
// and load; a second reference to the same image with another sampler gets its own copy.
TEST(GltfExport, TextureWrapModesRoundTrip) {
  Scene s;
  s.name = "wrapped";
  ts::Material m;
  m.diffuseTexture = 0;
  m.emissive = glm::vec3(0.5f);
  m.emissiveTexture = 1;
  s.materials.push_back(m);
  ts::Texture t;
  t.width = 2;
  t.height = 2;
  t.texels = {glm::vec4(0.2f), glm::vec4(0.4f), glm::vec4(0.6f), glm::vec4(0.8f)};
  t.wrapS = ts::TextureWrap::ClampToEdge;
  t.wrapT = ts::TextureWrap::MirroredRepeat;
  s.textures = {t, t};
  s.textures[1].wrapS = ts::TextureWrap::Repeat;
  s.textures[1].nearest = true;
  for (glm::vec3 p : {glm::vec3(0, 0, 0), glm::vec3(1, 0, 0), glm::vec3(0, 1, 0)}) {
    ts::Vertex v;
    v.position = p;
    v.normal = {0, 0, 1};
    v.uv = {2.0f * p.x - 0.5f, 1.5f * p.y};
    s.vertices.push_back(v);
  }
  s.indices = {0, 1, 2};
  s.triangleMaterial = {0};
  s.cameraPath.push_back(
      ts::SceneCamera::lookAt({0.3, 0.3, 3}, {0.3, 0.3, 0}, {0, 1, 0}, 1.0f, 0.1f, 10.0f));
  TempDir dir;
  ts::exportGltf(s, dir.file("wrap.gltf"));
  Scene l = ts::loadGltf(dir.file("wrap.gltf"));
  ASSERT_EQ(l.textures.size(), 2u);
  const ts::Texture& diffuse = l.textures[size_t(l.materials[0].baseColorTexture)];
  const ts::Texture& emissive = l.textures[size_t(l.materials[0].emissiveTexture)];
  EXPECT_EQ(diffuse.wrapS, ts::TextureWrap::ClampToEdge);
  EXPECT_EQ(diffuse.wrapT, ts::TextureWrap::MirroredRepeat);
  EXPECT_EQ(emissive.wrapS, ts::TextureWrap::Repeat);
  EXPECT_EQ(emissive.wrapT, ts::TextureWrap::MirroredRepeat);
  EXPECT_FALSE(diffuse.nearest);
  EXPECT_TRUE(emissive.nearest);

  // Both references on one image, with their own samplers.
  std::ifstream in(dir.file("wrap.gltf"));
  nlohmann::json doc = nlohmann::json::parse(in);
  doc["textures"][1]["source"] = doc["textures"][0]["source"];
  doc["materials"][0]["emissiveTexture"]["index"] = 1;
  dir.write("shared.gltf", doc.dump());
  Scene shared = ts::loadGltf(dir.file("shared.gltf"));
  ASSERT_EQ(shared.textures.size(), 2u);
  EXPECT_NE(shared.materials[0].baseColorTexture, shared.materials[0].emissiveTexture);
  EXPECT_EQ(shared.textures[size_t(shared.materials[0].emissiveTexture)].wrapS,
            ts::TextureWrap::Repeat);
  EXPECT_EQ(shared.textures[0].texels, shared.textures[1].texels);
}

// ---- real content ------------------------------------------------------------------------------

TEST(GltfReal, CrytekSponza) {
  std::string path = ts::test::sharedScene("sponza-crytek/sponza.gltf");
  if (path.empty()) GTEST_SKIP() << "../shared/scenes/sponza-crytek/ not present";
  Scene s = ts::loadGltf(path);
  EXPECT_EQ(s.triangleCount(), 262267u);
  EXPECT_EQ(s.materials.size(), 1u);
  EXPECT_TRUE(s.lights.empty());
  EXPECT_GE(s.cameraPath.size(), 120u);
  glm::vec3 e = s.bounds().extent();  // the atrium in metres: ~37 x 16 x 23
  EXPECT_GT(e.x, 30.0f);
  EXPECT_LT(e.x, 45.0f);
  EXPECT_GT(e.y, 10.0f);
  EXPECT_LT(e.y, 20.0f);
  for (const auto& v : s.vertices) ASSERT_NEAR(glm::length(v.normal), 1.0f, 1e-3f);
}

TEST(GltfReal, DungeonTexturesLightsAndWarnings) {
  std::string path = ts::test::sharedScene("dungeon/level-dungeon.gltf");
  if (path.empty()) GTEST_SKIP() << "../shared/scenes/dungeon/ not present";
  ::testing::internal::CaptureStderr();
  Scene s = ts::loadGltf(path);
  std::string err = ::testing::internal::GetCapturedStderr();
  EXPECT_EQ(s.triangleCount(), 32397u);
  EXPECT_EQ(s.materials.size(), 11u);
  // 10 materials have a base-colour PNG and a normal map (normalTexture, linear data): all 20
  // decode to non-constant linear texels.
  ASSERT_EQ(s.textures.size(), 20u);
  for (const auto& t : s.textures) {
    ASSERT_GT(t.width, 0);
    ASSERT_EQ(t.texels.size(), size_t(t.width) * size_t(t.height));
    float lo = 1e9f, hi = -1e9f;
    for (size_t i = 0; i < t.texels.size(); i += 97) {
      lo = std::min(lo, t.texels[i].y);
      hi = std::max(hi, t.texels[i].y);
    }
    EXPECT_GT(hi - lo, 0.05f);
    EXPECT_GE(lo, 0.0f);
    EXPECT_LE(hi, 1.0f);
  }
  int textured = 0;
  for (const auto& m : s.materials) textured += m.diffuseTexture >= 0;
  EXPECT_EQ(textured, 10);
  int normalMapped = 0;
  for (const auto& m : s.materials) normalMapped += m.normalTexture >= 0;
  EXPECT_EQ(normalMapped, 10);
  EXPECT_EQ(s.tangents.size(), s.vertices.size());  // generated: the file has no TANGENT
  // One point light instanced on two nodes, one directional light instanced on two nodes.
  ASSERT_EQ(s.lights.size(), 4u);
  int points = 0, directionals = 0;
  for (const auto& l : s.lights) {
    if (l.type == ts::SceneLightType::Directional) {
      ++directionals;
      EXPECT_NEAR(glm::length(l.direction), 1.0f, 1e-5f);
      continue;
    }
    ++points;
    EXPECT_FLOAT_EQ(l.range, 4.0f);
    expectVec(l.color, {20.0f, 20.0f, 20.0f * 0.029356954619288445f}, 1e-4f);
  }
  EXPECT_EQ(points, 2);
  EXPECT_EQ(directionals, 2);
  EXPECT_TRUE(contains(err, "1 skin")) << err;
  EXPECT_TRUE(contains(err, "1 animation")) << err;
}

TEST(GltfReal, TwoCylinderEngineGlb) {
  const std::string path =
      "/usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb";
  if (!fs::exists(path)) GTEST_SKIP() << "assimp-testmodels not installed (" << path << ")";
  Scene s = ts::loadGltf(path);
  EXPECT_GT(s.triangleCount(), 100000u);
  EXPECT_LT(s.triangleCount(), 150000u);
  EXPECT_GE(s.materials.size(), 10u);
  EXPECT_GE(s.cameraPath.size(), 120u);
  ts::Bounds b = s.bounds();
  // Every orbit frame (the last 240; frame 0 is the file's own camera when it has one) has the
  // whole model between its near and far planes.
  for (size_t k = s.cameraPath.size() - 240; k < s.cameraPath.size(); ++k) {
    const ts::SceneCamera& c = s.cameraPath[k];
    glm::vec3 v = glm::vec3(c.viewFromWorld * glm::vec4(b.center(), 1.0f));
    EXPECT_LT(-v.z + 0.5f * glm::length(b.extent()), c.zfar);
    EXPECT_GT(-v.z - 0.5f * glm::length(b.extent()), c.znear);
  }
}

}  // namespace
