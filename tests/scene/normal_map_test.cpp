// glTF normal maps on the scene side: normalTexture (index, texCoord, scale) and the tangents
// (the file's TANGENT, else generated from the UVs: generateTangents, not MikkTSpace), the note
// where neither is possible, bad input, the export and the `normal_maps` scene feature.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "gltf_builder.h"
#include "png_bytes.h"
#include "scene/scene_features.h"
#include "scene/scene_loader.h"
#include "scene/tangents.h"
#include "util/error.h"

namespace ts {
namespace {

using test::json;

struct Loaded {
  Scene scene;
  std::vector<std::string> warnings;
};

Loaded load(const json& doc) {
  const std::string text = doc.dump();
  Loaded r;
  r.scene = loadGltfFromMemory(reinterpret_cast<const unsigned char*>(text.data()), text.size(),
                               "/nonexistent", "normals.gltf", &r.warnings);
  return r;
}

#define REQUIRE_PNG(uri)                                            \
  do {                                                              \
    if ((uri).empty()) GTEST_SKIP() << "built without OpenImageIO"; \
  } while (0)

// ---- generateTangents ------------------------------------------------------------------------

// The quad of gltf_builder.h's normalMappedQuad: positions in y = 0, uv = (x, z).
struct Quad {
  std::vector<glm::vec3> positions{{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}};
  std::vector<glm::vec3> normals = std::vector<glm::vec3>(4, glm::vec3(0, 1, 0));
  std::vector<glm::vec2> uvs{{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  std::vector<uint32_t> triangles{0, 3, 2, 0, 2, 1};
};

TEST(Tangents, FollowPlusUWithTheBitangentTowardsMinusV) {
  Quad q;
  size_t without = 99;
  const auto t = generateTangents(q.positions, q.normals, q.uvs, q.triangles, &without);
  EXPECT_EQ(without, 0u);
  for (const glm::vec4& v : t) {
    EXPECT_NEAR(v.x, 1.0f, 1e-6f);
    EXPECT_NEAR(v.y, 0.0f, 1e-6f);
    EXPECT_NEAR(v.z, 0.0f, 1e-6f);
    EXPECT_EQ(v.w, 1.0f);  // cross(+y, +x) = -z: against dP/dv = +z
  }
}

TEST(Tangents, AMirroredMappingFlipsTheBitangentSign) {
  Quad q;
  for (glm::vec2& uv : q.uvs) uv.y = 1.0f - uv.y;  // v along -z: cross(N, T) = -z runs with it
  const auto t = generateTangents(q.positions, q.normals, q.uvs, q.triangles);
  for (const glm::vec4& v : t) {
    EXPECT_NEAR(v.x, 1.0f, 1e-6f);
    EXPECT_EQ(v.w, -1.0f);
  }
}

TEST(Tangents, AreMadeOrthogonalToTheVertexNormal) {
  Quad q;
  q.normals[1] = glm::normalize(glm::vec3(0.6f, 1.0f, 0.0f));
  const auto t = generateTangents(q.positions, q.normals, q.uvs, q.triangles);
  EXPECT_NEAR(glm::dot(glm::vec3(t[1]), q.normals[1]), 0.0f, 1e-6f);
  EXPECT_NEAR(glm::length(glm::vec3(t[1])), 1.0f, 1e-6f);
}

TEST(Tangents, DegenerateUVsGiveNoFrameAndAreCounted) {
  Quad q;
  for (glm::vec2& uv : q.uvs) uv = glm::vec2(0.25f);
  size_t without = 0;
  const auto t = generateTangents(q.positions, q.normals, q.uvs, q.triangles, &without);
  EXPECT_EQ(without, 4u);
  for (const glm::vec4& v : t) EXPECT_EQ(v, glm::vec4(0.0f));
}

// ---- the loader ------------------------------------------------------------------------------

TEST(NormalMapGltf, ReadsTheNormalTextureAndItsScaleAndGeneratesTangents) {
  const std::string uri = test::uniformPngUri(2, 2, {230, 64, 220});
  REQUIRE_PNG(uri);
  Loaded r = load(test::normalMappedQuad(uri, 0.75));
  EXPECT_TRUE(r.warnings.empty()) << r.warnings[0];
  ASSERT_EQ(r.scene.materials.size(), 1u);
  const Material& m = r.scene.materials[0];
  ASSERT_GE(m.normalTexture, 0);
  EXPECT_EQ(m.normalScale, 0.75f);
  const Texture& t = r.scene.textures[size_t(m.normalTexture)];
  EXPECT_FALSE(t.srgb);  // data, not colour
  EXPECT_EQ(t.texels[0], glm::vec4(230.0f / 255.0f, 64.0f / 255.0f, 220.0f / 255.0f, 1.0f));
  ASSERT_EQ(r.scene.tangents.size(), r.scene.vertices.size());
  for (const glm::vec4& v : r.scene.tangents) {
    EXPECT_NEAR(v.x, 1.0f, 1e-6f);
    EXPECT_EQ(v.w, 1.0f);
  }
}

TEST(NormalMapGltf, TakesTheFilesTangentsWithTheirSign) {
  const std::string uri = test::uniformPngUri(2, 2, {128, 128, 255});
  REQUIRE_PNG(uri);
  std::vector<float> tangents;
  for (int k = 0; k < 4; ++k) tangents.insert(tangents.end(), {0, 0, 2, -1});  // unnormalised
  Loaded r = load(test::normalMappedQuad(uri, 1.0, true, tangents));
  ASSERT_EQ(r.scene.tangents.size(), 4u);
  for (const glm::vec4& v : r.scene.tangents) EXPECT_EQ(v, glm::vec4(0, 0, 1, -1));
}

TEST(NormalMapGltf, TangentsUnderAMirroringNodeFlipTheirSign) {
  const std::string uri = test::uniformPngUri(2, 2, {128, 128, 255});
  REQUIRE_PNG(uri);
  std::vector<float> tangents;
  for (int k = 0; k < 4; ++k) tangents.insert(tangents.end(), {1, 0, 0, 1});
  json doc = test::normalMappedQuad(uri, 1.0, true, tangents);
  doc["nodes"][0]["scale"] = {-1, 1, 1};
  Loaded r = load(doc);
  ASSERT_EQ(r.scene.tangents.size(), 4u);
  for (const glm::vec4& v : r.scene.tangents) EXPECT_EQ(v, glm::vec4(-1, 0, 0, -1));
}

TEST(NormalMapGltf, WithoutTangentsAndUVsTheMapIsIgnoredWithANote) {
  const std::string uri = test::uniformPngUri(2, 2, {230, 64, 220});
  REQUIRE_PNG(uri);
  Loaded r = load(test::normalMappedQuad(uri, 1.0, false));
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_NE(r.warnings[0].find("normal map(s) ignored on 1 primitive(s) without TANGENT or "
                               "texture coordinates"),
            std::string::npos)
      << r.warnings[0];
  EXPECT_EQ(r.warnings[0].find('\n'), std::string::npos);
  ASSERT_EQ(r.scene.tangents.size(), 4u);
  for (const glm::vec4& v : r.scene.tangents) EXPECT_EQ(v, glm::vec4(0.0f));
}

TEST(NormalMapGltf, ANormalTextureIndexOutOfRangeIsOneClearError) {
  json doc = test::normalMappedQuad("data:image/png;base64,", 1.0);
  doc["materials"][0]["normalTexture"]["index"] = 7;
  try {
    load(doc);
    FAIL() << "loaded a normalTexture that indexes no texture";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("normals.gltf"), std::string::npos) << what;
    EXPECT_NE(what.find("normalTexture"), std::string::npos) << what;
    EXPECT_NE(what.find("0..0"), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
}

TEST(NormalMapGltf, ANonNumericScaleIsOneClearError) {
  json doc = test::normalMappedQuad("data:image/png;base64,", 1.0);
  doc["materials"][0]["normalTexture"]["scale"] = "steep";
  EXPECT_THROW(load(doc), Error);
}

TEST(NormalMapGltf, ExportWritesTheMapItsScaleAndTheTangentsBack) {
  const std::string uri = test::uniformPngUri(2, 2, {230, 64, 220});
  REQUIRE_PNG(uri);
  const Scene original = load(test::normalMappedQuad(uri, 0.6)).scene;
  const std::string path =
      (std::filesystem::temp_directory_path() / "tileshade_normal_map_export.gltf").string();
  exportGltf(original, path);
  std::vector<std::string> warnings;
  const Scene back = loadGltf(path, &warnings);
  std::filesystem::remove(path);
  ASSERT_EQ(back.materials.size(), 1u);
  ASSERT_GE(back.materials[0].normalTexture, 0);
  EXPECT_FLOAT_EQ(back.materials[0].normalScale, 0.6f);
  const Texture& map = back.textures[size_t(back.materials[0].normalTexture)];
  EXPECT_EQ(map.texels[0],
            original.textures[size_t(original.materials[0].normalTexture)].texels[0]);
  ASSERT_EQ(back.tangents.size(), back.vertices.size());
  for (size_t i = 0; i < back.vertices.size(); ++i)  // the exporter's vertex order is the file's
    EXPECT_EQ(back.tangents[i], original.tangents[i]);
}

// ---- the scene feature -----------------------------------------------------------------------

TEST(NormalMapFeature, IsOnOnlyForAScenesNormalMapsAndCannotBeLeftOut) {
  const std::string uri = test::uniformPngUri(2, 2, {230, 64, 220});
  REQUIRE_PNG(uri);
  const Scene mapped = load(test::normalMappedQuad(uri, 1.0)).scene;
  const SceneFeatures need = analyzeScene(mapped, ShadingModel::MetallicRoughness);
  EXPECT_TRUE(need.normalMaps);
  EXPECT_NE(need.describe().find("normal_maps"), std::string::npos);
  EXPECT_EQ(need.kernelDefines().find("NORMAL"), std::string::npos);  // no kernel branches on it
  EXPECT_THROW(chooseFeatures("specular,textures,point", need), Error);
  EXPECT_TRUE(chooseFeatures("specular,textures,point,normal_maps", need).normalMaps);

  SceneOptions plain;
  const Scene street = loadScene("builtin:street", plain);
  EXPECT_FALSE(analyzeScene(street, ShadingModel::BlinnPhong).normalMaps);
  EXPECT_TRUE(street.tangents.empty());
}

}  // namespace
}  // namespace ts
