#pragma once
// Internal to src/scene/: the types and shapes of the glTF JSON properties tileshade reads,
// checked before tinygltf parses the file. tinygltf silently drops an optional property of the
// wrong type (a translation given as a string is no translation), truncates integers to int
// (bufferView 4294967296 reads bufferView 0) and converts numbers beyond float's range to inf:
// each of those would load as another scene without a word. Also bounds the nesting depth
// (tinygltf converts extras and extensions recursively).
#include <cstddef>
#include <string>

#include <nlohmann/json.hpp>

namespace ts::gltf {

// Throws ts::Error "invalid glTF file NAME: nodes[3].translation: expected an array of 3
// numbers, got "1,2,3"" for the first property that is not what the glTF 2.0 specification
// (and tileshade, for the values it cannot represent) allows.
void checkJson(const nlohmann::json& document, const std::string& name);

// The JSON text of a file's bytes: all of a .gltf, the first (JSON) chunk of a .glb. Returns
// false when a .glb's header or chunk is malformed (tinygltf then reports it).
bool jsonText(const unsigned char* bytes, size_t size, std::string& text);

}  // namespace ts::gltf
