#pragma once
// Small self-contained glTF files for tests: a valid one-triangle scene (buffer as a data URI)
// that tests of hostile input break one property at a time.
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace ts::test {

using json = nlohmann::json;

inline std::string base64(const std::vector<unsigned char>& bytes) {
  static const char* digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (size_t i = 0; i < bytes.size(); i += 3) {
    uint32_t v = uint32_t(bytes[i]) << 16;
    if (i + 1 < bytes.size()) v |= uint32_t(bytes[i + 1]) << 8;
    if (i + 2 < bytes.size()) v |= bytes[i + 2];
    out += digits[(v >> 18) & 63];
    out += digits[(v >> 12) & 63];
    out += i + 1 < bytes.size() ? digits[(v >> 6) & 63] : '=';
    out += i + 2 < bytes.size() ? digits[v & 63] : '=';
  }
  return out;
}

template <typename T>
inline void put(std::vector<unsigned char>& b, T v) {
  unsigned char raw[sizeof(T)];
  std::memcpy(raw, &v, sizeof(T));
  b.insert(b.end(), raw, raw + sizeof(T));
}

inline json dataBuffer(const std::vector<unsigned char>& bytes) {
  return {{"uri", "data:application/octet-stream;base64," + base64(bytes)},
          {"byteLength", bytes.size()}};
}

// One triangle (3 float positions at 0..36, 3 uint16 indices at 36..42, padded to 44) on node 0,
// a point light on node 1 and a perspective camera on node 2: the valid file each test breaks.
inline json triangle(std::vector<float> positions = {0, 0, 0, 1, 0, 0, 0, 1, 0}) {
  std::vector<unsigned char> b;
  for (float v : positions) put(b, v);
  for (uint16_t i : {0, 1, 2}) put(b, i);
  put(b, uint16_t(0));
  json doc = json::parse(R"({
    "asset": {"version": "2.0"},
    "scene": 0,
    "scenes": [{"nodes": [0, 1, 2]}],
    "nodes": [{"mesh": 0},
              {"translation": [0, 0.5, 2], "extensions": {"KHR_lights_punctual": {"light": 0}}},
              {"translation": [0.3, 0.3, 3], "camera": 0}],
    "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1}}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
    "accessors": [
      {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
       "min": [0, 0, 0], "max": [1, 1, 0]},
      {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}],
    "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36},
                    {"buffer": 0, "byteOffset": 36, "byteLength": 6}],
    "extensionsUsed": ["KHR_lights_punctual"],
    "extensions": {"KHR_lights_punctual": {"lights": [
      {"type": "point", "color": [1, 1, 1], "intensity": 2}]}}
  })");
  doc["buffers"] = json::array({dataBuffer(b)});
  return doc;
}

// A unit quad in the plane y = 0 facing +y (u along +x, v along +z: glTF's v runs down the
// image, so the tangent is +x and the bitangent, cross(N, T) w with w = +1, is -z), its
// material's normalTexture the image at `imageUri` (sampled NEAREST) with `scale`, and a camera
// 1.4 above it looking down (the quad fills most of the view): the normal-map tests' scene.
// `tangents` (x y z w per vertex) become a TANGENT attribute when given; withUVs false leaves
// TEXCOORD_0 out.
inline json normalMappedQuad(const std::string& imageUri, double scale, bool withUVs = true,
                             const std::vector<float>& tangents = {},
                             const std::vector<float>& uvs = {0, 0, 1, 0, 1, 1, 0, 1}) {
  std::vector<unsigned char> b;
  for (float v : {0, 0, 0, 1, 0, 0, 1, 0, 1, 0, 0, 1}) put(b, v);  // positions, 0..48
  for (int k = 0; k < 4; ++k)
    for (float v : {0, 1, 0}) put(b, v);            // normals, 48..96
  for (float v : uvs) put(b, v);                    // uvs (default (x, z)), 96..128
  for (uint16_t i : {0, 3, 2, 0, 2, 1}) put(b, i);  // indices, 128..140
  for (float v : tangents) put(b, v);               // 140..204
  json doc = json::parse(R"({
    "asset": {"version": "2.0"},
    "scene": 0,
    "scenes": [{"nodes": [0, 1]}],
    "nodes": [{"mesh": 0},
              {"translation": [0.5, 1.4, 0.5], "rotation": [-0.70710678, 0, 0, 0.70710678],
               "camera": 0}],
    "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1}}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 3,
                                "material": 0}]}],
    "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1]}}],
    "textures": [{"source": 0, "sampler": 0}],
    "samplers": [{"magFilter": 9728, "minFilter": 9728}],
    "accessors": [
      {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
       "min": [0, 0, 0], "max": [1, 0, 1]},
      {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
      {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"},
      {"bufferView": 3, "componentType": 5123, "count": 6, "type": "SCALAR"},
      {"bufferView": 4, "componentType": 5126, "count": 4, "type": "VEC4"}],
    "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48},
                    {"buffer": 0, "byteOffset": 48, "byteLength": 48},
                    {"buffer": 0, "byteOffset": 96, "byteLength": 32},
                    {"buffer": 0, "byteOffset": 128, "byteLength": 12},
                    {"buffer": 0, "byteOffset": 140, "byteLength": 64}]
  })");
  if (tangents.empty()) {
    doc["accessors"].erase(4);
    doc["bufferViews"].erase(4);
  } else {
    doc["meshes"][0]["primitives"][0]["attributes"]["TANGENT"] = 4;
  }
  if (withUVs) doc["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = 2;
  doc["materials"][0]["normalTexture"] = {{"index", 0}, {"scale", scale}};
  doc["images"] = {{{"uri", imageUri}}};
  doc["buffers"] = json::array({dataBuffer(b)});
  return doc;
}

// The triangle's text with `member` (`"key": value`) added at its top level.
inline std::string triangleWith(const std::string& member) {
  std::string text = triangle().dump();
  text.insert(text.size() - 1, "," + member);
  return text;
}

}  // namespace ts::test
