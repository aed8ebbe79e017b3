// glTF normal maps on the scene side: normalTexture (index, texCoord, scale) and the tangents
// (the file's TANGENT, else generated from the UVs by MikkTSpace's rules: generateTangents), the
// note where neither is possible, bad input, the export and the `normal_maps` scene feature.
#include <gtest/gtest.h>

#include <algorithm>
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
  const GeneratedTangents g = generateTangents(q.positions, q.normals, q.uvs, q.triangles);
  EXPECT_EQ(g.withoutFrame, 0u);
  EXPECT_TRUE(g.copies.empty());
  EXPECT_EQ(g.triangles, q.triangles);
  const auto& t = g.tangents;
  ASSERT_EQ(t.size(), 4u);
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
  const auto t = generateTangents(q.positions, q.normals, q.uvs, q.triangles).tangents;
  for (const glm::vec4& v : t) {
    EXPECT_NEAR(v.x, 1.0f, 1e-6f);
    EXPECT_EQ(v.w, -1.0f);
  }
}

TEST(Tangents, AreMadeOrthogonalToTheVertexNormal) {
  Quad q;
  q.normals[1] = glm::normalize(glm::vec3(0.6f, 1.0f, 0.0f));
  const auto t = generateTangents(q.positions, q.normals, q.uvs, q.triangles).tangents;
  EXPECT_NEAR(glm::dot(glm::vec3(t[1]), q.normals[1]), 0.0f, 1e-6f);
  EXPECT_NEAR(glm::length(glm::vec3(t[1])), 1.0f, 1e-6f);
}

TEST(Tangents, DegenerateUVsGiveNoFrameAndAreCounted) {
  Quad q;
  for (glm::vec2& uv : q.uvs) uv = glm::vec2(0.25f);
  const GeneratedTangents g = generateTangents(q.positions, q.normals, q.uvs, q.triangles);
  EXPECT_EQ(g.withoutFrame, 4u);
  for (const glm::vec4& v : g.tangents) EXPECT_EQ(v, glm::vec4(0.0f));
}

// Two quads side by side in y = 0, x in [0, 2], the right one's UVs mirrored about the shared
// edge x = 1 (u = 2 - x), which they share as vertices 1 and 2 (same position, normal and UV):
// a mirrored seam. Summed over both sides the tangents there would cancel; MikkTSpace's rule
// gives each side its own frame, so both seam vertices are split.
struct MirroredPair {
  std::vector<glm::vec3> positions{{0, 0, 0}, {1, 0, 0}, {1, 0, 1},
                                   {0, 0, 1}, {2, 0, 0}, {2, 0, 1}};
  std::vector<glm::vec3> normals = std::vector<glm::vec3>(6, glm::vec3(0, 1, 0));
  std::vector<glm::vec2> uvs{{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0, 0}, {0, 1}};
  std::vector<uint32_t> triangles{0, 3, 2, 0, 2, 1, 1, 2, 5, 1, 5, 4};
};

TEST(Tangents, AMirroredSeamSplitsItsVerticesWithAFramePerSide) {
  MirroredPair m;
  const GeneratedTangents g = generateTangents(m.positions, m.normals, m.uvs, m.triangles);
  EXPECT_EQ(g.withoutFrame, 0u);
  ASSERT_EQ(g.copies.size(), 2u);  // the seam's two vertices, once more each
  ASSERT_EQ(g.tangents.size(), 8u);
  std::vector<uint32_t> copied = g.copies;
  std::sort(copied.begin(), copied.end());
  EXPECT_EQ(copied, (std::vector<uint32_t>{1, 2}));
  // Every corner of a face has its face's frame: +u runs +x on the left, -x on the right, and
  // the bitangent keeps pointing to -v (+z) on both, so its sign flips.
  for (size_t c = 0; c < g.triangles.size(); ++c) {
    const bool left = c < 6;
    const glm::vec4 t = g.tangents[g.triangles[c]];
    EXPECT_NEAR(t.x, left ? 1.0f : -1.0f, 1e-6f) << "corner " << c;
    EXPECT_NEAR(t.y, 0.0f, 1e-6f);
    EXPECT_NEAR(t.z, 0.0f, 1e-6f);
    EXPECT_EQ(t.w, left ? 1.0f : -1.0f) << "corner " << c;
  }
  // The copies are the right side's: the left keeps the input numbering.
  for (size_t c = 0; c < 6; ++c) EXPECT_EQ(g.triangles[c], m.triangles[c]);
}

// A fan at the origin (normal +z, in z = 0) of two triangles with different UV mappings: the
// vertex's tangent weighs them by their corner angles (both 90 degrees), not their areas, so
// halving one of them (split at the midpoint of its edge from the vertex) leaves it unchanged.
TEST(Tangents, CornerAnglesNotTriangleAreasWeighAVertexsFrame) {
  // Vertex 0 at the origin; triangle A (0, 1, 2) maps u along +x; triangle B (0, 3, 4) along
  // (1, 1, 0) (vertex 3 is at vertex 2's position with another UV: not welded).
  std::vector<glm::vec3> p{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 1, 0}, {-1, 0, 0}, {-0.5f, 0, 0}};
  std::vector<glm::vec3> n(p.size(), glm::vec3(0, 0, 1));
  std::vector<glm::vec2> uv{{0, 0}, {1, 0}, {0, 1}, {1, 1}, {0, 1}, {0, 0.5f}};
  const std::vector<uint32_t> whole{0, 1, 2, 0, 3, 4};
  const std::vector<uint32_t> split{0, 1, 2, 0, 3, 5, 5, 3, 4};  // B halved at vertex 5
  const glm::vec4 a = generateTangents(p, n, uv, whole).tangents[0];
  const glm::vec4 b = generateTangents(p, n, uv, split).tangents[0];
  const glm::dvec3 expected =
      glm::normalize(glm::dvec3(1, 0, 0) + glm::normalize(glm::dvec3(1, 1, 0)));
  for (const glm::vec4& t : {a, b}) {
    EXPECT_NEAR(t.x, float(expected.x), 1e-6f);
    EXPECT_NEAR(t.y, float(expected.y), 1e-6f);
    EXPECT_NEAR(t.z, 0.0f, 1e-6f);
  }
}

// Corners with equal position, normal and UV are one vertex whatever their indices: a quad whose
// second triangle uses duplicates of vertices 0 and 2 gets the frames of the shared quad.
TEST(Tangents, EqualVerticesUnderOtherIndicesShareOneFrame) {
  Quad q;
  q.normals = {glm::normalize(glm::vec3(0.3f, 1, 0)), glm::vec3(0, 1, 0),
               glm::normalize(glm::vec3(0, 1, 0.4f)), glm::vec3(0, 1, 0)};
  const auto shared = generateTangents(q.positions, q.normals, q.uvs, q.triangles).tangents;
  Quad d = q;
  for (uint32_t i : {0u, 2u}) {
    d.positions.push_back(q.positions[i]);
    d.normals.push_back(q.normals[i]);
    d.uvs.push_back(q.uvs[i]);
  }
  d.triangles = {0, 3, 2, 4, 5, 1};  // the second triangle on the copies 4 (of 0) and 5 (of 2)
  const auto duplicated = generateTangents(d.positions, d.normals, d.uvs, d.triangles).tangents;
  EXPECT_EQ(duplicated[4], shared[0]);
  EXPECT_EQ(duplicated[5], shared[2]);
  EXPECT_EQ(duplicated[0], shared[0]);
}

// A triangle with degenerate UVs takes its vertices' frames from their other triangles.
TEST(Tangents, ACornerOfADegenerateUVTriangleTakesItsVertexsFrame) {
  Quad q;
  q.positions.push_back({0.5f, 0, -1});
  q.normals.push_back({0, 1, 0});
  q.uvs.push_back({0.5f, 0});  // on the line v = 0 with vertices 0 and 1: no UV area
  q.triangles.insert(q.triangles.end(), {0, 1, 4});
  const GeneratedTangents g = generateTangents(q.positions, q.normals, q.uvs, q.triangles);
  EXPECT_EQ(g.withoutFrame, 1u);  // vertex 4, on no other triangle
  EXPECT_EQ(g.tangents[4], glm::vec4(0.0f));
  EXPECT_TRUE(g.copies.empty());
  EXPECT_NEAR(g.tangents[0].x, 1.0f, 1e-6f);
  EXPECT_NEAR(g.tangents[1].x, 1.0f, 1e-6f);
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

// Vertex 1's UV moved to (0, 1) mirrors the second triangle's mapping (0, 2, 1) against the
// first's (0, 3, 2): the vertices they share, 0 and 2, are split, and each triangle's corners
// carry its own frame (+x, and +z, the second's dP/du).
TEST(NormalMapGltf, GeneratedTangentsSplitTheVerticesOfAMirroredSeam) {
  const std::string uri = test::uniformPngUri(2, 2, {128, 128, 255});
  REQUIRE_PNG(uri);
  Loaded r = load(test::normalMappedQuad(uri, 1.0, true, {}, {0, 0, 0, 1, 1, 1, 0, 1}));
  EXPECT_TRUE(r.warnings.empty()) << r.warnings[0];
  ASSERT_EQ(r.scene.vertices.size(), 6u);
  ASSERT_EQ(r.scene.tangents.size(), 6u);
  ASSERT_EQ(r.scene.indices.size(), 6u);
  for (size_t c = 0; c < 6; ++c) {
    const glm::vec4 t = r.scene.tangents[r.scene.indices[c]];
    const glm::vec3 expected = c < 3 ? glm::vec3(1, 0, 0) : glm::vec3(0, 0, 1);
    EXPECT_NEAR(glm::length(glm::vec3(t) - expected), 0.0f, 1e-6f) << "corner " << c;
  }
  // The copies are the shared vertices, with their position, normal and UV.
  for (size_t i = 4; i < 6; ++i) {
    const Vertex& v = r.scene.vertices[i];
    const bool ofZero = v.position == glm::vec3(0, 0, 0), ofTwo = v.position == glm::vec3(1, 0, 1);
    EXPECT_TRUE(ofZero || ofTwo) << "vertex " << i;
    EXPECT_EQ(v.uv, ofZero ? glm::vec2(0, 0) : glm::vec2(1, 1));
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
