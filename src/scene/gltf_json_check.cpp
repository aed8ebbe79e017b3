#include "scene/gltf_json_check.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <limits>
#include <vector>

#include "util/checked_size.h"
#include "util/error.h"
#include "util/short_text.h"

namespace ts::gltf {
namespace {

using json = nlohmann::json;

constexpr double kFloatMax = std::numeric_limits<float>::max();
constexpr size_t kMaxDepth = 64;  // glTF itself nests about 8 deep; the rest is extras

// A lower bound of a number property (the specification's minimum or exclusiveMinimum).
struct Minimum {
  double value = -kFloatMax;
  bool exclusive = false;
};
constexpr Minimum kAny{};
constexpr Minimum kAtLeastZero{0.0, false};
constexpr Minimum kAboveZero{0.0, true};

class Checker {
 public:
  Checker(const json& doc, const std::string& name) : doc_(doc), name_(name) {}

  void run() {
    checkDepth();
    if (!doc_.is_object()) fail("", "the document", "a JSON object", doc_);
    index(doc_, "scene", "", count("scenes"));
    objects(doc_, "scenes", "", [&](const json& s, const std::string& at) {
      indices(s, "nodes", at, count("nodes"));
      if (const json* extras = get(s, "extras"); extras && extras->is_object())
        if (const json* own = get(*extras, "tileshade"); own && own->is_object())
          numbers(*own, "ambient", at + ".extras.tileshade", 3, kAtLeastZero);
    });
    // The lights before the nodes that index them: a malformed list is its own error, not a
    // node's bad index.
    object(doc_, "extensions", "", [&](const json& e, const std::string& at) {
      object(e, "KHR_lights_punctual", at, [&](const json& k, const std::string& kat) {
        objects(k, "lights", kat, [&](const json& l, const std::string& lat) { light(l, lat); });
      });
    });
    objects(doc_, "nodes", "", [&](const json& n, const std::string& at) { node(n, at); });
    objects(doc_, "meshes", "", [&](const json& m, const std::string& at) {
      objects(m, "primitives", at,
              [&](const json& p, const std::string& pat) { primitive(p, pat); });
    });
    objects(doc_, "accessors", "", [&](const json& a, const std::string& at) { accessor(a, at); });
    objects(doc_, "bufferViews", "", [&](const json& v, const std::string& at) {
      index(v, "buffer", at, count("buffers"));
      size(v, "byteOffset", at, 0);
      size(v, "byteLength", at, 1);
      integer(v, "byteStride", at, 4, 252);
      insideItsBuffer(v, at);
    });
    objects(doc_, "buffers", "", [&](const json& b, const std::string& at) {
      string(b, "uri", at);
      size(b, "byteLength", at, 1);
    });
    objects(doc_, "materials", "", [&](const json& m, const std::string& at) { material(m, at); });
    objects(doc_, "textures", "", [&](const json& t, const std::string& at) {
      index(t, "source", at, count("images"));
      index(t, "sampler", at, count("samplers"));
    });
    // The enumerations of the specification: another value would be sampled as the default.
    objects(doc_, "samplers", "", [&](const json& s, const std::string& at) {
      oneOf(s, "magFilter", at, {9728, 9729});
      oneOf(s, "minFilter", at, {9728, 9729, 9984, 9985, 9986, 9987});
      oneOf(s, "wrapS", at, {33071, 33648, 10497});
      oneOf(s, "wrapT", at, {33071, 33648, 10497});
    });
    objects(doc_, "images", "", [&](const json& i, const std::string& at) {
      string(i, "uri", at);
      string(i, "mimeType", at);
      index(i, "bufferView", at, count("bufferViews"));
    });
    objects(doc_, "cameras", "", [&](const json& c, const std::string& at) {
      string(c, "type", at);
      object(c, "perspective", at, [&](const json& p, const std::string& pat) {
        number(p, "yfov", pat, kAboveZero);
        number(p, "znear", pat, kAboveZero);
        number(p, "zfar", pat, kAtLeastZero);  // 0: infinite, as tinygltf writes it
        number(p, "aspectRatio", pat, kAboveZero);
      });
    });
    for (const char* key : {"extensionsUsed", "extensionsRequired"}) strings(doc_, key, "");
  }

 private:
  void node(const json& n, const std::string& at) {
    numbers(n, "matrix", at, 16, kAny);
    numbers(n, "translation", at, 3, kAny);
    numbers(n, "rotation", at, 4, kAny);
    numbers(n, "scale", at, 3, kAny);
    index(n, "mesh", at, count("meshes"));
    index(n, "camera", at, count("cameras"));
    index(n, "skin", at, count("skins"));
    indices(n, "children", at, count("nodes"));
    object(n, "extensions", at, [&](const json& e, const std::string& eat) {
      object(e, "KHR_lights_punctual", eat,
             [&](const json& k, const std::string& kat) { index(k, "light", kat, lightCount()); });
    });
    castsShadow(n, at);
  }

  // extras may be anything; an object's castsShadow (a light's or its node's) is a boolean.
  void castsShadow(const json& obj, const std::string& at) {
    const json* extras = get(obj, "extras");
    if (extras && extras->is_object()) boolean(*extras, "castsShadow", at + ".extras");
  }

  // byteOffset + byteLength within the buffer's declared byteLength (which tinygltf makes the size
  // of the data it loads): tinygltf 2.7 hands an image's bufferView to the image decoder without
  // this check (a heap read past the buffer, found by tests/fuzz/gltf_fuzzer).
  void insideItsBuffer(const json& v, const std::string& at) {
    const json* buffer = get(v, "buffer");
    const json* length = get(v, "byteLength");
    if (!buffer || !length) return;  // tinygltf requires both
    const json& b = doc_.at("buffers").at(buffer->get<size_t>());
    const json* declared = get(b, "byteLength");
    if (!declared || !declared->is_number_unsigned()) return;  // tinygltf requires it
    const json* offset = get(v, "byteOffset");
    CheckedSize end = CheckedSize(offset ? offset->get<uint64_t>() : 0) + length->get<uint64_t>();
    if (!end.fitsWithin(declared->get<uint64_t>()))
      throw Error("invalid glTF file " + name_ + ": " + at + ": byteOffset + byteLength (" +
                  (end.overflowed() ? std::string("more than 2^64") : std::to_string(end.value())) +
                  ") runs past buffer " + std::to_string(buffer->get<size_t>()) + "'s " +
                  std::to_string(declared->get<uint64_t>()) + " bytes");
  }

  void primitive(const json& p, const std::string& at) {
    object(p, "attributes", at, [&](const json& a, const std::string& aat) {
      for (auto it = a.begin(); it != a.end(); ++it)
        index(a, it.key().c_str(), aat, count("accessors"));
    });
    index(p, "indices", at, count("accessors"));
    index(p, "material", at, count("materials"));
    integer(p, "mode", at, 0, 6);
  }

  void accessor(const json& a, const std::string& at) {
    index(a, "bufferView", at, count("bufferViews"));
    size(a, "byteOffset", at, 0);
    oneOf(a, "componentType", at, {5120, 5121, 5122, 5123, 5125, 5126});
    boolean(a, "normalized", at);
    size(a, "count", at, 1);
    string(a, "type", at);
    // tinygltf keeps the sparse fields in ints: larger values would be truncated.
    object(a, "sparse", at, [&](const json& s, const std::string& sat) {
      integer(s, "count", sat, 1, INT32_MAX);
      object(s, "indices", sat, [&](const json& i, const std::string& iat) {
        index(i, "bufferView", iat, count("bufferViews"));
        integer(i, "byteOffset", iat, 0, INT32_MAX);
        oneOf(i, "componentType", iat, {5121, 5123, 5125});
      });
      object(s, "values", sat, [&](const json& v, const std::string& vat) {
        index(v, "bufferView", vat, count("bufferViews"));
        integer(v, "byteOffset", vat, 0, INT32_MAX);
      });
    });
  }

  void material(const json& m, const std::string& at) {
    auto textureInfo = [&](const json& parent, const char* key, const std::string& where) {
      object(parent, key, where, [&](const json& t, const std::string& tat) {
        index(t, "index", tat, count("textures"));
        integer(t, "texCoord", tat, 0, 65535);
      });
    };
    object(m, "pbrMetallicRoughness", at, [&](const json& p, const std::string& pat) {
      numbers(p, "baseColorFactor", pat, 4, kAny);
      number(p, "metallicFactor", pat, kAny);
      number(p, "roughnessFactor", pat, kAny);
      textureInfo(p, "baseColorTexture", pat);
      textureInfo(p, "metallicRoughnessTexture", pat);
    });
    numbers(m, "emissiveFactor", at, 3, kAny);
    for (const char* t : {"emissiveTexture", "normalTexture", "occlusionTexture"})
      textureInfo(m, t, at);
    object(m, "normalTexture", at,
           [&](const json& t, const std::string& tat) { number(t, "scale", tat, kAny); });
    boolean(m, "doubleSided", at);
    // Another name would be drawn opaque; a cutoff outside [0, 1] masks all or nothing.
    oneOfNames(m, "alphaMode", at, {"OPAQUE", "MASK", "BLEND"});
    unitNumber(m, "alphaCutoff", at);
    object(m, "extensions", at, [&](const json& e, const std::string& eat) {
      object(e, "KHR_materials_specular", eat, [&](const json& s, const std::string& sat) {
        number(s, "specularFactor", sat, kAny);
        numbers(s, "specularColorFactor", sat, 3, kAtLeastZero);
      });
      object(e, "KHR_materials_emissive_strength", eat, [&](const json& s, const std::string& sat) {
        number(s, "emissiveStrength", sat, kAtLeastZero);
      });
    });
  }

  void light(const json& l, const std::string& at) {
    string(l, "type", at);
    numbers(l, "color", at, 3, kAtLeastZero);
    number(l, "intensity", at, kAtLeastZero);
    number(l, "range", at, kAboveZero);
    object(l, "spot", at, [&](const json& s, const std::string& sat) {
      number(s, "innerConeAngle", sat, kAny);
      number(s, "outerConeAngle", sat, kAny);
    });
    castsShadow(l, at);
  }

  // ---- rules ----------------------------------------------------------------------------------

  [[noreturn]] void fail(const std::string& at, const std::string& key, const std::string& expected,
                         const json& got) const {
    const std::string text = shortText(got.dump(-1, ' ', false, json::error_handler_t::replace));
    std::string where = at.empty() ? key : at + "." + key;
    throw Error("invalid glTF file " + name_ + ": " + where + ": expected " + expected + ", got " +
                text);
  }

  static const json* get(const json& obj, const char* key) {
    if (!obj.is_object()) return nullptr;
    auto it = obj.find(key);
    return it == obj.end() ? nullptr : &*it;
  }

  size_t count(const char* topLevel) const {
    const json* a = get(doc_, topLevel);
    return a && a->is_array() ? a->size() : 0;
  }

  size_t lightCount() const {
    const json* e = get(doc_, "extensions");
    const json* k = e ? get(*e, "KHR_lights_punctual") : nullptr;
    const json* l = k ? get(*k, "lights") : nullptr;
    return l && l->is_array() ? l->size() : 0;
  }

  using Body = std::function<void(const json&, const std::string&)>;

  void object(const json& parent, const char* key, const std::string& at, const Body& body) {
    const json* v = get(parent, key);
    if (!v) return;
    if (!v->is_object()) fail(at, key, "an object", *v);
    body(*v, at.empty() ? key : at + "." + key);
  }

  // An array of objects, each checked by body with its path "key[i]".
  void objects(const json& parent, const char* key, const std::string& at, const Body& body) {
    const json* v = get(parent, key);
    if (!v) return;
    if (!v->is_array()) fail(at, key, "an array of objects", *v);
    std::string base = at.empty() ? key : at + "." + key;
    for (size_t i = 0; i < v->size(); ++i) {
      std::string item = base + "[" + std::to_string(i) + "]";
      if (!(*v)[i].is_object()) fail("", item, "an object", (*v)[i]);
      body((*v)[i], item);
    }
  }

  // An integer (not truncated: the whole JSON value) within lo..hi.
  void integer(const json& obj, const char* key, const std::string& at, int64_t lo, int64_t hi) {
    const json* v = get(obj, key);
    if (!v) return;
    bool ok = v->is_number_integer() &&
              (v->is_number_unsigned() ? v->get<uint64_t>() <= uint64_t(hi)
                                       : v->get<int64_t>() >= lo && v->get<int64_t>() <= hi);
    if (!ok) fail(at, key, "an integer in " + std::to_string(lo) + ".." + std::to_string(hi), *v);
  }

  // An index into an array of `n` elements.
  static bool indexOk(const json& v, size_t n) {
    return v.is_number_integer() && (v.is_number_unsigned() || v.get<int64_t>() >= 0) &&
           v.get<uint64_t>() < n;
  }
  static std::string indexText(size_t n) {
    return n == 0 ? std::string("no index (the list it would index is empty or absent)")
                  : "an index in 0.." + std::to_string(n - 1);
  }

  void index(const json& obj, const char* key, const std::string& at, size_t n) {
    const json* v = get(obj, key);
    if (v && !indexOk(*v, n)) fail(at, key, indexText(n), *v);
  }

  void indices(const json& obj, const char* key, const std::string& at, size_t n) {
    const json* v = get(obj, key);
    if (!v) return;
    if (!v->is_array()) fail(at, key, "an array of indices", *v);
    for (size_t i = 0; i < v->size(); ++i)
      if (!indexOk((*v)[i], n))
        fail(at, std::string(key) + "[" + std::to_string(i) + "]", indexText(n), (*v)[i]);
  }

  // A byte offset, length or count: a non-negative integer >= min.
  void size(const json& obj, const char* key, const std::string& at, uint64_t min) {
    const json* v = get(obj, key);
    if (!v) return;
    bool ok = v->is_number_unsigned() && v->get<uint64_t>() >= min;
    if (!ok) fail(at, key, "an integer >= " + std::to_string(min), *v);
  }

  void oneOf(const json& obj, const char* key, const std::string& at, std::vector<int> allowed) {
    const json* v = get(obj, key);
    if (!v) return;
    for (int a : allowed)
      if (v->is_number_integer() && v->get<int64_t>() == a) return;
    std::string list;
    for (int a : allowed) list += (list.empty() ? "" : ", ") + std::to_string(a);
    fail(at, key, "one of " + list, *v);
  }

  void oneOfNames(const json& obj, const char* key, const std::string& at,
                  std::vector<const char*> allowed) {
    const json* v = get(obj, key);
    if (!v) return;
    for (const char* a : allowed)
      if (v->is_string() && v->get<std::string>() == a) return;
    std::string list;
    for (const char* a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
    fail(at, key, "one of " + list, *v);
  }

  // A finite number in [0, 1].
  void unitNumber(const json& obj, const char* key, const std::string& at) {
    const json* v = get(obj, key);
    if (v && !(numberOk(*v, kAtLeastZero) && v->get<double>() <= 1.0))
      fail(at, key, "a number in [0, 1]", *v);
  }

  bool numberOk(const json& v, Minimum min) const {
    if (!v.is_number()) return false;
    double d = v.get<double>();
    if (!std::isfinite(d) || std::fabs(d) > kFloatMax) return false;
    return min.exclusive ? d > min.value : d >= min.value;
  }

  static std::string rangeText(Minimum min) {
    std::string s = " within float's range (|x| <= 3.4e38)";
    if (min.value == 0.0) s += min.exclusive ? " and > 0" : " and >= 0";
    return s;
  }

  void number(const json& obj, const char* key, const std::string& at, Minimum min) {
    const json* v = get(obj, key);
    if (v && !numberOk(*v, min)) fail(at, key, "a number" + rangeText(min), *v);
  }

  void numbers(const json& obj, const char* key, const std::string& at, size_t n, Minimum min) {
    const json* v = get(obj, key);
    if (!v) return;
    bool ok = v->is_array() && v->size() == n;
    for (size_t i = 0; ok && i < n; ++i) ok = numberOk((*v)[i], min);
    if (!ok) fail(at, key, "an array of " + std::to_string(n) + " numbers" + rangeText(min), *v);
  }

  void boolean(const json& obj, const char* key, const std::string& at) {
    const json* v = get(obj, key);
    if (v && !v->is_boolean()) fail(at, key, "true or false", *v);
  }

  void string(const json& obj, const char* key, const std::string& at) {
    const json* v = get(obj, key);
    if (v && !v->is_string()) fail(at, key, "a string", *v);
  }

  void strings(const json& obj, const char* key, const std::string& at) {
    const json* v = get(obj, key);
    if (!v) return;
    bool ok = v->is_array();
    for (size_t i = 0; ok && i < v->size(); ++i) ok = (*v)[i].is_string();
    if (!ok) fail(at, key, "an array of strings", *v);
  }

  // Iterative, so a hostile nesting cannot overflow the stack here.
  void checkDepth() const {
    std::vector<std::pair<const json*, size_t>> stack{{&doc_, 1}};
    while (!stack.empty()) {
      auto [v, depth] = stack.back();
      stack.pop_back();
      if (!v->is_structured()) continue;
      if (depth > kMaxDepth)
        throw Error("invalid glTF file " + name_ + ": JSON nested deeper than " +
                    std::to_string(kMaxDepth) + " levels");
      for (const auto& child : *v) stack.push_back({&child, depth + 1});
    }
  }

  const json& doc_;
  std::string name_;
};

uint32_t readU32(const unsigned char* p) {
  uint32_t v;
  std::memcpy(&v, p, 4);
  return v;  // GLB is little-endian, as every platform tileshade runs on
}

}  // namespace

void checkJson(const nlohmann::json& document, const std::string& name) {
  Checker(document, name).run();
}

bool jsonText(const unsigned char* bytes, size_t size, std::string& text) {
  if (size < 4 || std::memcmp(bytes, "glTF", 4) != 0) {
    text.assign(reinterpret_cast<const char*>(bytes), size);
    return true;
  }
  // Header: magic, version, length; then the first chunk: length, type "JSON", data.
  if (size < 20) return false;
  uint32_t chunkLength = readU32(bytes + 12), chunkType = readU32(bytes + 16);
  if (chunkType != 0x4E4F534Au || chunkLength > size - 20) return false;
  text.assign(reinterpret_cast<const char*>(bytes + 20), chunkLength);
  return true;
}

}  // namespace ts::gltf
