// glTF 2.0 (.gltf / .glb) -> Scene, through tinygltf. Mappings are documented in scenes/README.md.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <thread>
#include <tuple>

#ifndef TILESHADE_NO_OIIO
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#endif
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <tiny_gltf.h>

#include "scene/gltf_json_check.h"
#include "scene/gltf_mapping.h"
#include "scene/light_range.h"
#include "scene/scene_loader.h"
#include "scene/tangents.h"
#include "util/checked_size.h"
#include "util/error.h"
#include "util/file_read.h"
#include "util/float_limit.h"
#include "util/pi.h"
#include "util/short_text.h"
#include "util/strict_json.h"
#include "util/stderr_capture.h"

namespace ts {

namespace {

constexpr int kOrbitFrames = 240;
// Node levels tileshade follows (each a recursion of the loader's tree walk).
constexpr int kMaxNodeDepth = 1000;

// Lines of a message joined with "; ", empty ones dropped.
std::string oneLine(const std::string& s) {
  std::string out, line;
  std::istringstream in(s);
  while (std::getline(in, line)) {
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
    if (!line.empty()) out += (out.empty() ? "" : "; ") + line;
  }
  return out;
}

// A number in messages: up to 6 significant digits ("1.5", "1e+39").
std::string shortText(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

// "N thing(s): a, b, c, ..." with at most three listed.
std::string listed(const std::vector<std::string>& items) {
  std::string list;
  for (size_t i = 0; i < items.size() && i < 3; ++i) list += (i ? ", " : "") + items[i];
  if (items.size() > 3) list += ", ...";
  return list;
}

// Image callback: keep the encoded bytes, decode later only the images used as base colour.
bool keepEncodedImage(tinygltf::Image* image, const int, std::string*, std::string*, int, int,
                      const unsigned char* bytes, int size, void*) {
  image->image.assign(bytes, bytes + size);
  image->width = image->height = image->component = image->bits = -1;  // still encoded
  image->as_is = true;
  return true;
}

// ---- accessors -------------------------------------------------------------------------------

double readComponent(const unsigned char* p, int componentType, bool normalized) {
  switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      int8_t v;
      std::memcpy(&v, p, 1);
      return normalized ? std::max(double(v) / 127.0, -1.0) : double(v);
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: {
      uint8_t v = *p;
      return normalized ? double(v) / 255.0 : double(v);
    }
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      int16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? std::max(double(v) / 32767.0, -1.0) : double(v);
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      uint16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? double(v) / 65535.0 : double(v);
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
      uint32_t v;
      std::memcpy(&v, p, 4);
      return normalized ? double(v) / 4294967295.0 : double(v);
    }
    case TINYGLTF_COMPONENT_TYPE_FLOAT: {
      float v;
      std::memcpy(&v, p, 4);
      return double(v);
    }
    case TINYGLTF_COMPONENT_TYPE_DOUBLE: {
      double v;
      std::memcpy(&v, p, 8);
      return v;
    }
  }
  return 0.0;
}

// Elements an accessor without a bufferView (all zeros, maybe with sparse values) may have: its
// count is not backed by any data, so nothing else bounds the allocation.
constexpr size_t kMaxElementsWithoutData = size_t(1) << 24;

class Reader {
 public:
  Reader(const tinygltf::Model& m, const std::string& path) : m_(m), path_(path) {}

  [[noreturn]] void fail(const std::string& what) const {
    throw Error("invalid glTF file " + path_ + ": " + what);
  }

  // The bytes [offset, offset + needed) of bufferView `index`, after checking, in overflow-checked
  // arithmetic, that they lie inside the view and the view inside its buffer.
  const unsigned char* view(int index, size_t offset, CheckedSize needed,
                            const std::string& what) const {
    if (index < 0 || size_t(index) >= m_.bufferViews.size()) fail(what + ": bad bufferView");
    const auto& bv = m_.bufferViews[size_t(index)];
    if (bv.buffer < 0 || size_t(bv.buffer) >= m_.buffers.size()) fail(what + ": bad buffer");
    const auto& buf = m_.buffers[size_t(bv.buffer)];
    std::string name = "bufferView " + std::to_string(index);
    if (!(CheckedSize(bv.byteOffset) + bv.byteLength).fitsWithin(buf.data.size()))
      fail(what + ": " + name + " (offset " + std::to_string(bv.byteOffset) + ", length " +
           std::to_string(bv.byteLength) + ") runs past its buffer of " +
           std::to_string(buf.data.size()) + " bytes");
    if (!(CheckedSize(offset) + needed).fitsWithin(bv.byteLength))
      fail(what + ": data runs past " + name + " (offset " + std::to_string(offset) + " + " +
           (needed.overflowed() ? std::string("more than 2^64") : std::to_string(needed.value())) +
           " bytes > its " + std::to_string(bv.byteLength) + ")");
    return buf.data.data() + bv.byteOffset + offset;
  }

  // Accessor `index` as `count * components` doubles (components = that of its type), decoding
  // any component type, normalization, byte stride and sparse substitution. Every size is checked
  // against the data before anything is allocated.
  std::vector<double> read(int index, int wantComponents, const std::string& what) const {
    const auto& a = accessor(index, what);
    int nc = tinygltf::GetNumComponentsInType(uint32_t(a.type));
    int cs = tinygltf::GetComponentSizeInBytes(uint32_t(a.componentType));
    if (nc <= 0 || cs <= 0) fail(what + ": unsupported accessor type");
    if (wantComponents > 0 && nc != wantComponents)
      fail(what + ": expected " + std::to_string(wantComponents) + " components, got " +
           std::to_string(nc));
    const size_t count = a.count, elem = size_t(nc) * size_t(cs);
    const unsigned char* p = nullptr;
    size_t stride = elem;
    if (a.bufferView >= 0 && count > 0) {
      stride = byteStride(a, elem, what);
      p = view(a.bufferView, a.byteOffset, CheckedSize(stride) * (count - 1) + elem, what);
    } else if (count > kMaxElementsWithoutData) {
      fail(what + ": count " + std::to_string(count) + " without a bufferView (more than the " +
           std::to_string(kMaxElementsWithoutData) + " elements tileshade accepts without data)");
    }
    // count <= bufferView bytes / stride + 1 here, so the doubles are at most 8x the data.
    std::vector<double> out(count * size_t(nc), 0.0);
    for (size_t i = 0; p && i < count; ++i)
      for (int c = 0; c < nc; ++c)
        out[i * size_t(nc) + size_t(c)] =
            readComponent(p + i * stride + size_t(c) * size_t(cs), a.componentType, a.normalized);
    if (a.sparse.isSparse && a.sparse.count > 0) {
      size_t n = size_t(a.sparse.count);
      if (n > count)
        fail(what + ": " + std::to_string(n) + " sparse values for " + std::to_string(count) +
             " elements");
      std::vector<uint32_t> targets =
          unsignedIntegers(a.sparse.indices.bufferView, size_t(a.sparse.indices.byteOffset),
                           a.sparse.indices.componentType, n, what + " sparse indices");
      const unsigned char* vp = view(a.sparse.values.bufferView, size_t(a.sparse.values.byteOffset),
                                     CheckedSize(n) * elem, what);
      for (size_t i = 0; i < n; ++i) {
        if (targets[i] >= count) fail(what + ": sparse index out of range");
        for (int c = 0; c < nc; ++c)
          out[targets[i] * size_t(nc) + size_t(c)] =
              readComponent(vp + i * elem + size_t(c) * size_t(cs), a.componentType, a.normalized);
      }
    }
    return out;
  }

  // An index accessor (a primitive's `indices`): unsigned byte, short or int scalars, read exactly.
  std::vector<uint32_t> readIndices(int index, const std::string& what) const {
    const auto& a = accessor(index, what);
    if (a.type != TINYGLTF_TYPE_SCALAR || a.normalized || a.sparse.isSparse)
      fail(what + ": indices must be plain unsigned integer scalars");
    if (a.bufferView < 0) fail(what + ": indices without a bufferView");
    int cs = tinygltf::GetComponentSizeInBytes(uint32_t(a.componentType));
    if (cs <= 0) fail(what + ": unsupported component type");
    size_t stride = byteStride(a, size_t(cs), what);
    if (stride != size_t(cs)) fail(what + ": indices must be tightly packed (byteStride)");
    return unsignedIntegers(a.bufferView, a.byteOffset, a.componentType, a.count, what);
  }

 private:
  const tinygltf::Accessor& accessor(int index, const std::string& what) const {
    if (index < 0 || size_t(index) >= m_.accessors.size()) fail(what + ": bad accessor");
    return m_.accessors[size_t(index)];
  }

  // The bufferView's byteStride for elements of `elem` bytes: the element size when absent; an
  // error when smaller than the element (the elements would overlap) or not a multiple of the
  // component size.
  size_t byteStride(const tinygltf::Accessor& a, size_t elem, const std::string& what) const {
    if (a.bufferView < 0 || size_t(a.bufferView) >= m_.bufferViews.size())
      fail(what + ": bad bufferView");
    const auto& bv = m_.bufferViews[size_t(a.bufferView)];
    if (bv.byteStride == 0) return elem;
    int stride = a.ByteStride(bv);
    if (stride <= 0 || size_t(stride) < elem)
      fail(what + ": byteStride " + std::to_string(bv.byteStride) + " of bufferView " +
           std::to_string(a.bufferView) + " is smaller than its " + std::to_string(elem) +
           "-byte element or not a multiple of its component size");
    return size_t(stride);
  }

  // `count` unsigned integers of an UNSIGNED_BYTE/SHORT/INT component type, tightly packed.
  std::vector<uint32_t> unsignedIntegers(int bufferView, size_t offset, int componentType,
                                         size_t count, const std::string& what) const {
    if (componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
        componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
        componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
      fail(what + ": component type " + std::to_string(componentType) +
           " (must be unsigned byte, short or int)");
    size_t cs = size_t(tinygltf::GetComponentSizeInBytes(uint32_t(componentType)));
    const unsigned char* p = view(bufferView, offset, CheckedSize(count) * cs, what);
    std::vector<uint32_t> out(count);
    for (size_t i = 0; i < count; ++i)
      out[i] = uint32_t(readComponent(p + i * cs, componentType, false));
    return out;
  }

  const tinygltf::Model& m_;
  std::string path_;
};

// ---- transforms ------------------------------------------------------------------------------

// The node's local matrix (sizes and float range of matrix/TRS were checked in the JSON), in
// double, as the file's numbers are: far from the origin the node transforms, and the camera made
// from them, keep what float products of matrices would round away (Camera). A rotation is
// normalised; one of zero length has no rotation to normalise: an error.
glm::dmat4 localMatrix(const tinygltf::Node& n, const Reader& read, const std::string& what) {
  if (n.matrix.size() == 16) {
    glm::dmat4 m;
    for (int i = 0; i < 16; ++i) glm::value_ptr(m)[i] = n.matrix[size_t(i)];  // column-major
    return m;
  }
  glm::dmat4 m(1.0);
  if (n.translation.size() == 3)
    m = glm::translate(m, glm::dvec3(n.translation[0], n.translation[1], n.translation[2]));
  if (n.rotation.size() == 4) {
    glm::dquat q(n.rotation[3], n.rotation[0], n.rotation[1], n.rotation[2]);  // x, y, z, w in glTF
    double length = glm::length(q);
    if (!(length > 0.0) || !std::isfinite(length))
      read.fail(what + ": rotation quaternion of zero length");
    m *= glm::mat4_cast(q / length);
  }
  if (n.scale.size() == 3) m = glm::scale(m, glm::dvec3(n.scale[0], n.scale[1], n.scale[2]));
  return m;
}

bool isFinite(const glm::mat4& m) {
  for (int i = 0; i < 16; ++i)
    if (!std::isfinite(glm::value_ptr(m)[i])) return false;
  return true;
}

bool isFinite(glm::vec3 v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// A colour or factor from doubles, each within float's range (ts::Error naming `what` beyond).
glm::vec3 floatVec3(double x, double y, double z, const Reader& read, const std::string& what) {
  glm::dvec3 d(x, y, z);
  for (int c = 0; c < 3; ++c)
    if (!(std::fabs(d[c]) <= double(std::numeric_limits<float>::max())))
      read.fail(what + " = " + std::to_string(d[c]) + " is beyond float's range (3.4e38)");
  return glm::vec3(d);
}

// ---- extension values --------------------------------------------------------------------------

const tinygltf::Value* extension(const tinygltf::ExtensionMap& ext, const std::string& name) {
  auto it = ext.find(name);
  return it == ext.end() || !it->second.IsObject() ? nullptr : &it->second;
}

double number(const tinygltf::Value* obj, const std::string& key, double fallback) {
  if (!obj || !obj->Has(key)) return fallback;
  const auto& v = obj->Get(key);
  return v.IsNumber() || v.IsInt() || v.IsReal() ? v.GetNumberAsDouble() : fallback;
}

glm::vec3 vec3(const tinygltf::Value* obj, const std::string& key, glm::vec3 fallback) {
  if (!obj || !obj->Has(key)) return fallback;
  const auto& v = obj->Get(key);
  if (!v.IsArray() || v.ArrayLen() < 3) return fallback;
  return {float(v.Get(0).GetNumberAsDouble()), float(v.Get(1).GetNumberAsDouble()),
          float(v.Get(2).GetNumberAsDouble())};
}

// ---- images ----------------------------------------------------------------------------------

struct DecodedImage {
  bool ok = false;
  Texture texture;
  std::string why;
};

// Texels a texture may have: 2^26 (an 8K x 8K image) is 1 GiB of float RGBA texels.
constexpr uint64_t kMaxTexels = uint64_t(1) << 26;

// Width and height from a PNG's IHDR or a JPEG's frame header (false for other formats or a
// truncated header), so that an image claiming billions of pixels is refused before decoding.
bool encodedImageSize(const std::vector<unsigned char>& b, uint64_t& width, uint64_t& height) {
  auto be = [&](size_t at, int bytes) {
    uint64_t v = 0;
    for (int k = 0; k < bytes; ++k) v = (v << 8) | b[at + size_t(k)];
    return v;
  };
  if (b.size() >= 24 && std::memcmp(b.data(), "\x89PNG\r\n\x1a\n", 8) == 0) {
    width = be(16, 4);
    height = be(20, 4);
    return true;
  }
  if (b.size() < 4 || b[0] != 0xFF || b[1] != 0xD8) return false;
  // JPEG: segments FF xx LEN..., up to a start-of-frame marker (C0-CF but C4, C8, CC).
  for (size_t at = 2; at + 9 <= b.size();) {
    if (b[at] != 0xFF) return false;
    unsigned marker = b[at + 1];
    if (marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC) {
      height = be(at + 5, 2);
      width = be(at + 7, 2);
      return true;
    }
    at += 2 + size_t(be(at + 2, 2));
  }
  return false;
}

// Encoded PNG/JPEG/... bytes -> linear RGBA texels: colour channels sRGB-decoded when `srgb` (base
// colour and emissive textures), taken as they are otherwise (metallic-roughness); alpha linear.
// Never throws: a failure (also running out of memory) is the result's `why`.
DecodedImage decodeImageOrThrow(const tinygltf::Image& image, int index, bool srgb);

DecodedImage decodeImage(const tinygltf::Image& image, int index, bool srgb) {
  try {
    return decodeImageOrThrow(image, index, srgb);
  } catch (const std::bad_alloc&) {
    DecodedImage result;
    result.why = "out of memory decoding it";
    return result;
  } catch (const std::length_error&) {
    DecodedImage result;
    result.why = "too large to decode";
    return result;
  }
}

DecodedImage decodeImageOrThrow(const tinygltf::Image& image, int index, bool srgb) {
  DecodedImage result;
  result.texture.srgb = srgb;
  if (image.image.empty()) {
    result.why = "not found";
    return result;
  }
  auto tooLarge = [&](uint64_t w, uint64_t h) {
    if (w * h <= kMaxTexels) return false;  // w, h < 2^32 each: no overflow
    result.why = std::to_string(w) + "x" + std::to_string(h) + " texels, more than the " +
                 std::to_string(kMaxTexels) + " tileshade keeps per texture";
    return true;
  };
  uint64_t width = 0, height = 0;
  if (encodedImageSize(image.image, width, height) && tooLarge(width, height)) return result;
  static const std::vector<float> lut = [] {
    std::vector<float> t(256);
    for (int i = 0; i < 256; ++i) t[size_t(i)] = gltf::srgbToLinear(float(i) / 255.0f);
    return t;
  }();
  Texture& out = result.texture;
  // Writes texel p from `channels` values fetched by get(p, c) in [0,1] (sRGB-encoded colour).
  auto fill = [&](int w, int h, int channels, auto get, bool eightBit) {
    out.width = w;
    out.height = h;
    out.texels.resize(size_t(w) * size_t(h));
    for (size_t p = 0; p < out.texels.size(); ++p) {
      auto colour = [&](int c) {
        if (!srgb) return eightBit ? float(get(p, c)) / 255.0f : float(get(p, c));
        return eightBit ? lut[size_t(get(p, c))] : gltf::srgbToLinear(float(get(p, c)));
      };
      auto alpha = [&](int c) { return eightBit ? float(get(p, c)) / 255.0f : float(get(p, c)); };
      if (channels <= 2)
        out.texels[p] = glm::vec4(glm::vec3(colour(0)), channels == 2 ? alpha(1) : 1.0f);
      else
        out.texels[p] = glm::vec4(colour(0), colour(1), colour(2), channels >= 4 ? alpha(3) : 1.0f);
    }
  };
  // First tinygltf's own decoder (stb_image in Debian's build: PNG, JPEG, BMP, TGA, ...).
  tinygltf::Image d;
  std::string err, warnings;
  if (image.image.size() > size_t(INT32_MAX)) {
    result.why = "larger than 2 GiB";
    return result;
  }
  if (tinygltf::LoadImageData(&d, index, &err, &warnings, 0, 0, image.image.data(),
                              int(image.image.size()), nullptr) &&
      d.width > 0 && d.height > 0 && d.component > 0) {
    if (tooLarge(uint64_t(d.width), uint64_t(d.height))) return result;
    size_t nc = size_t(d.component);
    const unsigned char* px = d.image.data();
    if (d.bits == 16)
      fill(
          d.width, d.height, d.component,
          [&](size_t p, int c) {
            uint16_t v;
            std::memcpy(&v, px + 2 * (p * nc + size_t(c)), 2);
            return double(v) / 65535.0;
          },
          false);
    else
      fill(
          d.width, d.height, d.component, [&](size_t p, int c) { return px[p * nc + size_t(c)]; },
          true);
    result.ok = true;
    return result;
  }
#ifdef TILESHADE_NO_OIIO
  result.why = oneLine(err.empty() ? std::string("built without OpenImageIO") : err);
  return result;
#else
  // A PNG that stb_image cannot decode is not retried with OpenImageIO: its PNG reader leaks when
  // libpng longjmps out of a corrupt file (found by tests/fuzz/gltf_fuzzer), and stb_image reads
  // every valid PNG.
  if (image.image.size() >= 8 && std::memcmp(image.image.data(), "\x89PNG\r\n\x1a\n", 8) == 0) {
    result.why = oneLine(err.empty() ? std::string("not a valid PNG") : err);
    return result;
  }
  // Then OpenImageIO from memory (whatever formats it was built with).
  std::string ext = image.mimeType == "image/jpeg" ? "jpg" : "png";
  if (auto dot = image.uri.rfind('.'); !image.uri.empty() && dot != std::string::npos)
    ext = image.uri.substr(dot + 1);
  OIIO::Filesystem::IOMemReader mem(const_cast<unsigned char*>(image.image.data()),
                                    image.image.size());
  // Image libraries print their own lines (libjpeg's "Corrupt JPEG data: ...", libpng's
  // "libpng error: ..."): they become part of the reason instead of raw stderr lines.
  StderrCapture libraryMessages;
  auto in = OIIO::ImageInput::open("image." + ext, nullptr, &mem);
  auto failed = [&](const std::string& why) {
    std::string printed = libraryMessages.text();
    result.why = oneLine(why.empty() ? printed : printed.empty() ? why : why + "; " + printed);
    return result;
  };
  if (!in) return failed(err.empty() ? OIIO::geterror() : err);
  const auto& spec = in->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0)
    return failed("no pixels (" + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                  ")");
  if (tooLarge(uint64_t(spec.width), uint64_t(spec.height))) {
    libraryMessages.text();
    return result;
  }
  size_t nc = size_t(spec.nchannels);
  std::vector<float> all(size_t(spec.width) * size_t(spec.height) * nc);
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, all.data()))
    return failed(in->geterror());
  libraryMessages.text();
  // glTF textures hold [0, 1] data; a float format's NaN, inf or out-of-range values are clamped
  // (NaN to 0) so that they cannot reach the G-buffer.
  fill(
      spec.width, spec.height, std::min(spec.nchannels, 4),
      [&](size_t p, int c) {
        double v = all[p * nc + size_t(c)];
        return std::isnan(v) ? 0.0 : std::clamp(v, 0.0, 1.0);
      },
      false);
  result.ok = true;
  return result;
#endif
}

// ---- the loader ------------------------------------------------------------------------------

class GltfLoader {
 public:
  GltfLoader(const tinygltf::Model& model, const std::string& path)
      : m_(model), path_(path), read_(model, path) {}

  Scene load();
  // What load() found worth a warning, one line each (without the path).
  const std::vector<std::string>& warnings() const;

 private:
  void visit(int node, const glm::dmat4& parent, int depth);
  void failOnCycles() const;
  void addPrimitive(const tinygltf::Primitive& p, const glm::dmat4& world, const std::string& what);
  void addTangents(const tinygltf::Primitive& p, const glm::dmat4& world, bool mirror, size_t first,
                   bool fromNormals, size_t fileVertices, const std::vector<uint32_t>& corners,
                   bool hasUVs, const std::string& what);
  void requireTexCoords(const tinygltf::Primitive& p, const tinygltf::Material& mat, int index,
                        const std::string& what) const;
  uint32_t material(int gltfMaterial);
  int texture(const tinygltf::TextureInfo& info, bool srgb, const std::string& at,
              const std::string& what);
  int decodedTexture(const tinygltf::TextureInfo& info, bool srgb, const std::string& what);
  void noteUnmodelledSampling(const tinygltf::TextureInfo& info, const std::string& at);
  void decodeImages();
  void addLight(const tinygltf::Light& light, const glm::dmat4& world, const std::string& what);
  void buildCameraPath();

  const tinygltf::Model& m_;
  std::string path_;
  Reader read_;
  Scene scene_;
  std::map<int, uint32_t> materials_;  // glTF material (-1 = none) -> scene material
  // (glTF image, sRGB) -> scene texture (-1 = failed): an image is decoded once per colour space
  std::map<std::pair<int, bool>, int> images_;
  std::map<std::pair<int, bool>, DecodedImage> decoded_;  // decoded up front, in parallel
  int otherTexCoords_ = 0;  // textures on another UV set than the base colour's
  // What the texture sampling (one level, the magnification filter, untransformed UVs:
  // Texture::sample) does not model, warned once each: "samplers[0].minFilter NEAREST (magFilter
  // LINEAR)", texture references with KHR_texture_transform.
  std::set<std::string> unmodelledSamplers_;
  std::vector<std::string> transformedTextures_;
  std::set<int> samplingGiven_;  // scene textures whose sampling a reference has set
  // (scene texture, wrapS, wrapT, nearest) -> its copy sampled so
  std::map<std::tuple<int, TextureWrap, TextureWrap, bool>, int> samplingVariants_;
  int uvSet_ = 0;  // the base colour's UV set of the material being read
  std::vector<std::string> textureFailures_;
  std::vector<std::string> clampedFactors_;  // "materials[2].metallicFactor 1.5"
  std::vector<std::string> warnings_;        // printed by the caller once the file has loaded
  int skippedPrimitives_ = 0;
  size_t degenerateNormals_ = 0;  // zero-length normals replaced by +Y
  // Per scene vertex (kept in Scene::tangents only when some primitive is normal-mapped).
  std::vector<glm::vec4> tangents_;
  bool normalMapped_ = false;
  std::vector<std::string> normalMapsWithoutUVs_;  // primitives whose normal map is ignored
  size_t verticesWithoutFrame_ = 0;                // of normal-mapped primitives: no tangent frame
  int otherLights_ = 0, orthographic_ = 0, extraCameras_ = 0;
  bool haveCamera_ = false;
  SceneCamera camera_;
  std::set<int> visiting_;
};

uint32_t GltfLoader::material(int index) {
  auto it = materials_.find(index);
  if (it != materials_.end()) return it->second;
  Material out;
  out.model = ShadingModel::MetallicRoughness;
  glm::vec3 dielectricF0(0.04f);
  if (index < 0 || size_t(index) >= m_.materials.size()) {
    // No material: a neutral grey dielectric (glTF's default, a white rough metal, would be black
    // in Blinn-Phong).
    out.name = "default";
    out.baseColor = glm::vec3(0.8f);
    out.metallic = 0.0f;
    out.roughness = roughnessFromShininess(32.0f);
  } else {
    const auto& mat = m_.materials[size_t(index)];
    const auto& pbr = mat.pbrMetallicRoughness;
    std::string what = "material '" + ts::shortText(mat.name) + "'";
    std::string at = "materials[" + std::to_string(index) + "]";
    out.name = mat.name;
    // glTF bounds the factors to [0, 1]: values outside are clamped there, with one warning
    // listing them (load()). Their products with strengths must stay within float's range.
    auto unit = [&](double v, const std::string& field) {
      if (v < 0.0 || v > 1.0) clampedFactors_.push_back(at + "." + field + " " + shortText(v));
      return float(std::clamp(v, 0.0, 1.0));
    };
    out.baseColor = glm::vec3(1.0f);
    if (pbr.baseColorFactor.size() >= 3)
      for (int c = 0; c < 3; ++c)
        out.baseColor[c] = unit(pbr.baseColorFactor[size_t(c)], "baseColorFactor");
    if (pbr.baseColorFactor.size() >= 4)
      out.opacity = unit(pbr.baseColorFactor[3], "baseColorFactor");
    // alphaMode and alphaCutoff are checked in the JSON (gltf_json_check.cpp): one of the three
    // names, a cutoff in [0, 1].
    if (mat.alphaMode == "MASK") out.alphaMode = AlphaMode::Mask;
    else if (mat.alphaMode == "BLEND") out.alphaMode = AlphaMode::Blend;
    out.alphaCutoff = float(mat.alphaCutoff);
    out.metallic = unit(pbr.metallicFactor, "metallicFactor");
    out.roughness = unit(pbr.roughnessFactor, "roughnessFactor");
    if (const auto* spec = extension(mat.extensions, "KHR_materials_specular")) {
      float factor = unit(number(spec, "specularFactor", 1.0), "specularFactor");
      glm::vec3 colour = vec3(spec, "specularColorFactor", glm::vec3(1.0f));
      dielectricF0 =
          floatVec3(double(colour.x) * factor, double(colour.y) * factor, double(colour.z) * factor,
                    read_, what + ": specularColorFactor x specularFactor");
    }
    glm::dvec3 emissive(0.0);
    if (mat.emissiveFactor.size() >= 3)
      for (int c = 0; c < 3; ++c)
        emissive[c] = unit(mat.emissiveFactor[size_t(c)], "emissiveFactor");
    emissive *= number(extension(mat.extensions, "KHR_materials_emissive_strength"),
                       "emissiveStrength", 1.0);
    out.emissive = floatVec3(emissive.x, emissive.y, emissive.z, read_,
                             what + ": emissiveFactor x emissiveStrength");
    out.doubleSided = mat.doubleSided;
    uvSet_ = std::max(pbr.baseColorTexture.texCoord, 0);  // the UV set addPrimitive keeps
    if (pbr.baseColorTexture.index >= 0)
      out.baseColorTexture =
          texture(pbr.baseColorTexture, true, at + ".pbrMetallicRoughness.baseColorTexture", what);
    if (pbr.metallicRoughnessTexture.index >= 0)
      out.metallicRoughnessTexture =
          texture(pbr.metallicRoughnessTexture, false,
                  at + ".pbrMetallicRoughness.metallicRoughnessTexture", what);
    if (mat.emissiveTexture.index >= 0)
      out.emissiveTexture = texture(mat.emissiveTexture, true, at + ".emissiveTexture", what);
    if (mat.normalTexture.index >= 0) {
      // Linear data, as metallic-roughness; `scale` is within float's range (checked in the JSON).
      tinygltf::TextureInfo info;
      info.index = mat.normalTexture.index;
      info.texCoord = mat.normalTexture.texCoord;
      info.extensions = mat.normalTexture.extensions;
      out.normalTexture = texture(info, false, at + ".normalTexture", what);
      out.normalScale = float(mat.normalTexture.scale);
    }
  }
  fillBlinnPhongTerms(out, dielectricF0);
  // tileshade's exporter marks materials written for Blinn-Phong (their Blinn-Phong terms come
  // back exactly through the mapping above).
  if (index >= 0 && size_t(index) < m_.materials.size()) {
    const auto& extras = m_.materials[size_t(index)].extras;
    if (extras.IsObject() && extras.Has("tileshade")) {
      const auto& ts = extras.Get("tileshade");
      if (ts.IsObject() && ts.Has("shading_model") && ts.Get("shading_model").IsString() &&
          ts.Get("shading_model").Get<std::string>() == "blinn-phong")
        out.model = ShadingModel::BlinnPhong;
    }
  }
  scene_.materials.push_back(out);
  uint32_t id = uint32_t(scene_.materials.size() - 1);
  materials_[index] = id;
  return id;
}

TextureWrap textureWrap(int gltfWrap) {
  if (gltfWrap == TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE) return TextureWrap::ClampToEdge;
  if (gltfWrap == TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT) return TextureWrap::MirroredRepeat;
  return TextureWrap::Repeat;  // glTF's default and REPEAT (10497)
}

// The scene texture of the texture reference `info` (at `at` in the file), decoded in the given
// colour space, with its sampler's wrap modes and magnification filter (-1 when it cannot be
// decoded: the factor alone is used, and load() warns once for all of them). Only the base
// colour's UV set is kept per vertex; a texture on another set is sampled with it (counted,
// warned once).
int GltfLoader::texture(const tinygltf::TextureInfo& info, bool srgb, const std::string& at,
                        const std::string& what) {
  noteUnmodelledSampling(info, at);
  const int decoded = decodedTexture(info, srgb, what);
  if (decoded < 0) return -1;
  TextureWrap wrapS = TextureWrap::Repeat, wrapT = TextureWrap::Repeat;
  bool nearest = false;
  const int sampler = m_.textures[size_t(info.index)].sampler;
  if (sampler >= 0 && size_t(sampler) < m_.samplers.size()) {
    wrapS = textureWrap(m_.samplers[size_t(sampler)].wrapS);
    wrapT = textureWrap(m_.samplers[size_t(sampler)].wrapT);
    nearest = m_.samplers[size_t(sampler)].magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST;
  }
  // The first reference of an image gives its sampling; a reference with another gets a copy.
  Texture& first = scene_.textures[size_t(decoded)];
  if (samplingGiven_.insert(decoded).second) {
    first.wrapS = wrapS;
    first.wrapT = wrapT;
    first.nearest = nearest;
  }
  if (first.wrapS == wrapS && first.wrapT == wrapT && first.nearest == nearest) return decoded;
  const auto key = std::make_tuple(decoded, wrapS, wrapT, nearest);
  if (auto it = samplingVariants_.find(key); it != samplingVariants_.end()) return it->second;
  Texture copy = first;
  copy.wrapS = wrapS;
  copy.wrapT = wrapT;
  copy.nearest = nearest;
  scene_.textures.push_back(std::move(copy));
  return samplingVariants_[key] = int(scene_.textures.size() - 1);
}

// The scene texture of the image of texture reference `info`, as first decoded (-1 when it
// cannot be, recorded for load()'s warning).
int GltfLoader::decodedTexture(const tinygltf::TextureInfo& info, bool srgb,
                               const std::string& what) {
  const int index = info.index;
  if (std::max(info.texCoord, 0) != uvSet_) ++otherTexCoords_;
  if (index < 0 || size_t(index) >= m_.textures.size()) {
    textureFailures_.push_back(what + ": texture " + std::to_string(index) + " does not exist");
    return -1;
  }
  int source = m_.textures[size_t(index)].source;
  if (source < 0 || size_t(source) >= m_.images.size()) {
    textureFailures_.push_back("texture " + std::to_string(index) +
                               " has no PNG/JPEG source (KTX2/WebP are not supported)");
    return -1;
  }
  auto key = std::make_pair(source, srgb);
  auto it = images_.find(key);
  if (it != images_.end()) return it->second;
  const auto& image = m_.images[size_t(source)];
  auto d = decoded_.find(key);
  DecodedImage one = d == decoded_.end() ? decodeImage(image, source, srgb) : std::move(d->second);
  int result = -1;
  if (one.ok) {
    scene_.textures.push_back(std::move(one.texture));
    result = int(scene_.textures.size() - 1);
  } else {
    std::string name = !image.uri.empty()    ? image.uri
                       : !image.name.empty() ? image.name
                                             : "image " + std::to_string(source);
    textureFailures_.push_back(ts::shortText(name) + " (" + one.why + ")");
  }
  images_[key] = result;
  return result;
}

// Records what of the texture reference `info` (at `at` in the file) and its sampler the
// sampling does not model: a minification filter unlike the magnification one,
// KHR_texture_transform.
void GltfLoader::noteUnmodelledSampling(const tinygltf::TextureInfo& info, const std::string& at) {
  if (info.extensions.count("KHR_texture_transform")) transformedTextures_.push_back(at);
  if (info.index < 0 || size_t(info.index) >= m_.textures.size()) return;
  const int index = m_.textures[size_t(info.index)].sampler;
  if (index < 0 || size_t(index) >= m_.samplers.size()) return;  // glTF's default: REPEAT, linear
  const auto& sampler = m_.samplers[size_t(index)];
  const std::string name = "samplers[" + std::to_string(index) + "].";
  // Sampling uses the magnification filter (one level, as OpenGL's textureLod(.., 0)): a
  // minification filter that would choose texels differently is not modelled. Its mipmap choice
  // is moot with one level.
  const bool nearestMag = sampler.magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST;
  const int min = sampler.minFilter;
  const bool nearestMin = min == TINYGLTF_TEXTURE_FILTER_NEAREST ||
                          min == TINYGLTF_TEXTURE_FILTER_NEAREST_MIPMAP_NEAREST ||
                          min == TINYGLTF_TEXTURE_FILTER_NEAREST_MIPMAP_LINEAR;
  if (min >= 0 && nearestMin != nearestMag)
    unmodelledSamplers_.insert(name + "minFilter " + (nearestMin ? "NEAREST" : "LINEAR") +
                               " (magFilter " + (nearestMag ? "NEAREST" : "LINEAR") + ")");
}

// Decodes every image a material uses (base colour and emissive as sRGB, metallic-roughness and
// normal maps as linear data), on up to 4 threads (PNG decoding dominates the load time of textured
// scenes).
void GltfLoader::decodeImages() {
  std::vector<std::pair<int, bool>> wanted;
  auto want = [&](int t, bool srgb) {
    if (t < 0 || size_t(t) >= m_.textures.size()) return;
    int source = m_.textures[size_t(t)].source;
    auto key = std::make_pair(source, srgb);
    if (source >= 0 && size_t(source) < m_.images.size() &&
        std::find(wanted.begin(), wanted.end(), key) == wanted.end())
      wanted.push_back(key);
  };
  for (const auto& mat : m_.materials) {
    want(mat.pbrMetallicRoughness.baseColorTexture.index, true);
    want(mat.pbrMetallicRoughness.metallicRoughnessTexture.index, false);
    want(mat.emissiveTexture.index, true);
    want(mat.normalTexture.index, false);
  }
  std::vector<DecodedImage> results(wanted.size());
  std::atomic<size_t> next{0};
  auto work = [&] {
    for (size_t i; (i = next++) < wanted.size();)
      results[i] =
          decodeImage(m_.images[size_t(wanted[i].first)], wanted[i].first, wanted[i].second);
  };
  size_t threads =
      std::min<size_t>({wanted.size(), 4, std::max(1u, std::thread::hardware_concurrency())});
  std::vector<std::thread> pool;
  for (size_t t = 1; t < threads; ++t) pool.emplace_back(work);
  work();
  for (auto& t : pool) t.join();
  for (size_t i = 0; i < wanted.size(); ++i) decoded_[wanted[i]] = std::move(results[i]);
}

// One KHR_lights_punctual light at a node: point and spot lights at the node's origin, spot and
// directional lights along the node's -Z. Colour = color x intensity (candela, lux: taken as is);
// a point or spot light without a range (glTF: infinite) gets r = sqrt(max(C)/t) with the
// attenuation threshold t = 5/256.
void GltfLoader::addLight(const tinygltf::Light& light, const glm::dmat4& world,
                          const std::string& what) {
  // Colour components and intensity are >= 0 and within float's range (checked in the JSON);
  // components above 1 (beyond the specification) are taken as they are. Their product must
  // stay a float.
  glm::dvec3 c(1.0);
  if (light.color.size() >= 3) c = {light.color[0], light.color[1], light.color[2]};
  c *= light.intensity;
  glm::vec3 color = floatVec3(c.x, c.y, c.z, read_, what + ": light colour x intensity");
  // The node's world position and axis stay double: a float position 1e5 from the origin is
  // rounded by up to 4e-3, which the double view transform would then keep (Light::position); a
  // float length of the axis of a node scaled by 1e30 overflows.
  const glm::dvec3 position(world[3]);
  const glm::dvec3 axis(-world[2]);
  const double axisLength = glm::length(axis);
  float range =
      light.range > 0.0 ? float(light.range) : rangeFromThreshold(color, gltf::kLightThreshold);
  if (light.type == "point") {
    scene_.lights.push_back(SceneLight::point(position, color, range));
    return;
  }
  if (light.type != "spot" && light.type != "directional") {
    ++otherLights_;
    return;
  }
  if (!(axisLength > 0.0) || !std::isfinite(axisLength))
    read_.fail(what + ": the " + light.type +
               " light's node transform has a zero scale along "
               "its -Z axis (no direction)");
  const glm::vec3 direction(axis / axisLength);
  if (light.type == "directional") {
    scene_.lights.push_back(SceneLight::directional(direction, color));
    return;
  }
  // A float of pi/2 (what float-based exporters, tileshade's too, write) is taken as pi/2.
  double inner = light.spot.innerConeAngle, outer = light.spot.outerConeAngle;
  if (!(withinFloatRounding(inner, 0.0, kHalfPi) && withinFloatRounding(outer, 0.0, kHalfPi) &&
        inner < outer))
    read_.fail(what +
               ": spot cone angles must satisfy 0 <= innerConeAngle < outerConeAngle <= "
               "pi/2 (" +
               fullText(kHalfPi) + "), got inner " + fullText(inner) + ", outer " +
               fullText(outer));
  inner = std::clamp(inner, 0.0, kHalfPi);
  outer = std::clamp(outer, 0.0, kHalfPi);
  scene_.lights.push_back(
      SceneLight::spot(position, direction, color, range, float(inner), float(outer)));
}

// Every UV set the material's textures name must be an attribute of the primitive: without it
// there is nothing to sample the texture with.
void GltfLoader::requireTexCoords(const tinygltf::Primitive& p, const tinygltf::Material& mat,
                                  int index, const std::string& what) const {
  const std::pair<const tinygltf::TextureInfo*, const char*> used[] = {
      {&mat.pbrMetallicRoughness.baseColorTexture, "pbrMetallicRoughness.baseColorTexture"},
      {&mat.pbrMetallicRoughness.metallicRoughnessTexture,
       "pbrMetallicRoughness.metallicRoughnessTexture"},
      {&mat.emissiveTexture, "emissiveTexture"}};
  for (const auto& [info, key] : used) {
    if (info->index < 0) continue;
    const std::string set = "TEXCOORD_" + std::to_string(std::max(info->texCoord, 0));
    if (!p.attributes.count(set))
      read_.fail(what + ": materials[" + std::to_string(index) + "]." + key + " samples texCoord " +
                 std::to_string(std::max(info->texCoord, 0)) + " but the primitive has no " + set +
                 " attribute");
  }
}

void GltfLoader::addPrimitive(const tinygltf::Primitive& p, const glm::dmat4& world,
                              const std::string& what) {
  int mode = p.mode < 0 ? TINYGLTF_MODE_TRIANGLES : p.mode;
  if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
      mode != TINYGLTF_MODE_TRIANGLE_FAN) {
    ++skippedPrimitives_;
    return;
  }
  auto pos = p.attributes.find("POSITION");
  if (pos == p.attributes.end()) {
    ++skippedPrimitives_;
    return;
  }
  uint32_t mat = material(p.material);
  std::vector<double> P = read_.read(pos->second, 3, what + " POSITION");
  size_t n = P.size() / 3;
  std::vector<double> N, UV;
  if (auto it = p.attributes.find("NORMAL"); it != p.attributes.end())
    N = read_.read(it->second, 3, what + " NORMAL");
  int texCoord = 0;
  if (p.material >= 0 && size_t(p.material) < m_.materials.size()) {
    const auto& mat = m_.materials[size_t(p.material)];
    texCoord = std::max(mat.pbrMetallicRoughness.baseColorTexture.texCoord, 0);
    requireTexCoords(p, mat, p.material, what);
  }
  if (auto it = p.attributes.find("TEXCOORD_" + std::to_string(texCoord)); it != p.attributes.end())
    UV = read_.read(it->second, 2, what + " TEXCOORD");
  if (N.size() != 0 && N.size() != P.size())
    read_.fail(what + ": NORMAL count differs from POSITION");
  if (UV.size() != 0 && UV.size() / 2 != n)
    read_.fail(what + ": TEXCOORD count differs from POSITION");
  // Vertex data a float holds (a binary buffer can hold NaN and inf bits, and doubles beyond
  // float's range): anything else would put NaN into the G-buffer.
  auto requireFinite = [&](const std::vector<double>& v, size_t components, const char* name) {
    for (size_t i = 0; i < v.size(); ++i)
      if (!(std::fabs(v[i]) <= double(std::numeric_limits<float>::max())))
        read_.fail(what + " " + name + ": element " + std::to_string(i / components) + " holds " +
                   shortText(v[i]) + " (NaN, inf or beyond float's range)");
  };
  requireFinite(P, 3, "POSITION");
  requireFinite(N, 3, "NORMAL");
  requireFinite(UV, 2, "TEXCOORD");
  if (n > size_t(UINT32_MAX) - scene_.vertices.size())
    read_.fail(what + ": more than 2^32 vertices in the scene");

  // Triangle list (of the primitive's vertex indices).
  std::vector<uint32_t> idx;
  if (p.indices >= 0) {
    idx = read_.readIndices(p.indices, what + " indices");
  } else {
    idx.resize(n);
    for (size_t i = 0; i < n; ++i) idx[i] = uint32_t(i);
  }
  std::vector<uint32_t> tris;
  if (mode == TINYGLTF_MODE_TRIANGLES) {
    tris.assign(idx.begin(), idx.begin() + long(idx.size() / 3 * 3));
  } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
    for (size_t i = 2; i < idx.size(); ++i) {
      if (i % 2 == 0) tris.insert(tris.end(), {idx[i - 2], idx[i - 1], idx[i]});
      else tris.insert(tris.end(), {idx[i - 1], idx[i - 2], idx[i]});
    }
  } else {
    for (size_t i = 2; i < idx.size(); ++i) tris.insert(tris.end(), {idx[0], idx[i - 1], idx[i]});
  }
  for (uint32_t i : tris)
    if (i >= n) read_.fail(what + ": vertex index " + std::to_string(i) + " out of range");

  // A mirroring transform turns counter-clockwise faces clockwise: swap to keep them CCW.
  bool mirror = glm::determinant(glm::dmat3(world)) < 0.0;
  glm::mat3 normalMatrix(glm::transpose(glm::inverse(glm::dmat3(world))));
  auto position = [&](uint32_t i) {
    glm::vec3 v(world * glm::dvec4(P[3 * i], P[3 * i + 1], P[3 * i + 2], 1.0));
    if (!isFinite(v))
      read_.fail(what + ": vertex " + std::to_string(i) +
                 " lies beyond float's range once its "
                 "node transforms are applied");
    return v;
  };
  auto uv = [&](uint32_t i) {
    return UV.empty() ? glm::vec2(0.0f) : glm::vec2(float(UV[2 * i]), float(UV[2 * i + 1]));
  };
  const size_t first = scene_.vertices.size();
  if (!N.empty()) {
    uint32_t base = uint32_t(scene_.vertices.size());
    for (uint32_t i = 0; i < n; ++i) {
      Vertex v;
      v.position = position(i);
      glm::vec3 nn =
          normalMatrix * glm::vec3(float(N[3 * i]), float(N[3 * i + 1]), float(N[3 * i + 2]));
      float len = glm::length(nn);
      bool usable = len > 0.0f && std::isfinite(len);
      if (!usable) ++degenerateNormals_;  // zero in the file, or a singular node transform
      v.normal = usable ? nn / len : glm::vec3(0.0f, 1.0f, 0.0f);
      v.uv = uv(i);
      scene_.vertices.push_back(v);
    }
    for (size_t t = 0; t + 2 < tris.size(); t += 3) {
      uint32_t a = tris[t], b = tris[t + 1], c = tris[t + 2];
      if (mirror) std::swap(b, c);
      scene_.indices.insert(scene_.indices.end(), {base + a, base + b, base + c});
      scene_.triangleMaterial.push_back(mat);
    }
  } else {
    // No normals: flat normals per triangle (as the glTF specification asks), world space.
    for (size_t t = 0; t + 2 < tris.size(); t += 3) {
      uint32_t c3[3] = {tris[t], tris[t + 1], tris[t + 2]};
      if (mirror) std::swap(c3[1], c3[2]);
      glm::vec3 p0 = position(c3[0]), p1 = position(c3[1]), p2 = position(c3[2]);
      // In double: the cross product of far-apart float vertices overflows float.
      glm::dvec3 cross =
          glm::cross(glm::dvec3(p1) - glm::dvec3(p0), glm::dvec3(p2) - glm::dvec3(p0));
      double len = glm::length(cross);
      glm::vec3 fn = len > 0.0 ? glm::vec3(cross / len) : glm::vec3(0.0f, 1.0f, 0.0f);  // no area
      uint32_t base = uint32_t(scene_.vertices.size());
      for (int k = 0; k < 3; ++k) {
        Vertex v;
        v.position = k == 0 ? p0 : k == 1 ? p1 : p2;
        v.normal = fn;
        v.uv = uv(c3[k]);
        scene_.vertices.push_back(v);
      }
      scene_.indices.insert(scene_.indices.end(), {base, base + 1, base + 2});
      scene_.triangleMaterial.push_back(mat);
    }
  }
  if (scene_.materials[mat].normalTexture >= 0)
    addTangents(p, world, mirror, first, !N.empty(), n, tris, !UV.empty(), what);
  tangents_.resize(scene_.vertices.size(), glm::vec4(0.0f));  // none: not normal-mapped
}

// The tangents of a normal-mapped primitive's vertices scene_.vertices[first..]: its TANGENT
// attribute (xyz by the node's matrix, w flipped by a mirroring one) when it has normals
// (without, glTF's flat normals replace them and any TANGENT is ignored), else generated from its
// UVs by MikkTSpace's rules (generateTangents; vertices on mirrored UV seams are split), else
// none, with a note (load()): the map is ignored.
// fileVertices: the primitive's vertex count; corners: its triangles in file indices.
void GltfLoader::addTangents(const tinygltf::Primitive& p, const glm::dmat4& world, bool mirror,
                             size_t first, bool fromNormals, size_t fileVertices,
                             const std::vector<uint32_t>& corners, bool hasUVs,
                             const std::string& what) {
  normalMapped_ = true;
  tangents_.resize(scene_.vertices.size(), glm::vec4(0.0f));
  const size_t count = scene_.vertices.size() - first;
  auto tangent = p.attributes.find("TANGENT");
  if (fromNormals && tangent != p.attributes.end()) {
    std::vector<double> T = read_.read(tangent->second, 4, what + " TANGENT");
    if (T.size() / 4 != fileVertices) read_.fail(what + ": TANGENT count differs from POSITION");
    const glm::dmat3 linear(world);
    for (size_t i = 0; i < count; ++i) {
      for (int c = 0; c < 4; ++c)
        if (!(std::fabs(T[4 * i + size_t(c)]) <= double(std::numeric_limits<float>::max())))
          read_.fail(what + " TANGENT: element " + std::to_string(i) + " holds " +
                     shortText(T[4 * i + size_t(c)]) + " (NaN, inf or beyond float's range)");
      const glm::dvec3 t = linear * glm::dvec3(T[4 * i], T[4 * i + 1], T[4 * i + 2]);
      const double length = glm::length(t);
      if (!(length > 0.0) || !std::isfinite(length)) {
        ++verticesWithoutFrame_;
        continue;
      }
      // The bitangent, cross(N, T) w, follows the transform only with w flipped by a mirror.
      const double w = (T[4 * i + 3] < 0.0) != mirror ? -1.0 : 1.0;
      tangents_[first + i] = glm::vec4(glm::vec3(t / length), float(w));
    }
    return;
  }
  if (!hasUVs) {
    normalMapsWithoutUVs_.push_back(what);
    return;
  }
  std::vector<glm::vec3> positions(count), normals(count);
  std::vector<glm::vec2> uvs(count);
  for (size_t i = 0; i < count; ++i) {
    const Vertex& v = scene_.vertices[first + i];
    positions[i] = v.position;
    normals[i] = v.normal;
    uvs[i] = v.uv;
  }
  // The primitive's triangles in its own vertex numbering, as added to scene_.indices.
  const auto tail = scene_.indices.end() - long(corners.size() / 3 * 3);
  std::vector<uint32_t> local(tail, scene_.indices.end());
  for (uint32_t& i : local) i -= uint32_t(first);
  GeneratedTangents generated = generateTangents(positions, normals, uvs, local);
  verticesWithoutFrame_ += generated.withoutFrame;
  // A vertex on a mirrored UV seam has a frame per side: its copies join the primitive's
  // vertices and the corners on the other side use them.
  if (generated.copies.size() > size_t(UINT32_MAX) - scene_.vertices.size())
    read_.fail(what + ": more than 2^32 vertices in the scene once its mirrored UV seams split");
  const std::vector<Vertex> own(scene_.vertices.begin() + long(first), scene_.vertices.end());
  for (uint32_t source : generated.copies) scene_.vertices.push_back(own[source]);
  std::transform(generated.triangles.begin(), generated.triangles.end(),
                 scene_.indices.end() - long(generated.triangles.size()),
                 [&](uint32_t i) { return i + uint32_t(first); });
  tangents_.resize(scene_.vertices.size(), glm::vec4(0.0f));
  std::copy(generated.tangents.begin(), generated.tangents.end(), tangents_.begin() + long(first));
}

void GltfLoader::visit(int index, const glm::dmat4& parent, int depth) {
  if (index < 0 || size_t(index) >= m_.nodes.size())
    read_.fail("bad node index " + std::to_string(index));
  // A guard: failOnCycles() has refused every cycle before the walk.
  if (!visiting_.insert(index).second)
    read_.fail("node hierarchy has a cycle through node " + std::to_string(index));
  if (depth >= kMaxNodeDepth)
    read_.fail("node hierarchy is deeper than " + std::to_string(kMaxNodeDepth) + " levels (node " +
               std::to_string(index) + " is at level " + std::to_string(depth + 1) + ")");
  const auto& node = m_.nodes[size_t(index)];
  std::string what = "node " + std::to_string(index) + " '" + node.name + "'";
  glm::dmat4 world = parent * localMatrix(node, read_, what);
  if (!isFinite(glm::mat4(world)))
    read_.fail(what +
               ": its world transform overflows float (translation, scale or matrix "
               "values, or their product over the hierarchy, beyond 3.4e38)");

  if (node.mesh >= 0) {
    if (size_t(node.mesh) >= m_.meshes.size()) read_.fail(what + ": bad mesh index");
    const auto& mesh = m_.meshes[size_t(node.mesh)];
    for (size_t i = 0; i < mesh.primitives.size(); ++i)
      addPrimitive(mesh.primitives[i], world,
                   "mesh " + std::to_string(node.mesh) + " '" + mesh.name + "' primitive " +
                       std::to_string(i));
  }

  if (const auto* ext = extension(node.extensions, "KHR_lights_punctual")) {
    int li = int(number(ext, "light", -1.0));
    if (li < 0 || size_t(li) >= m_.lights.size()) read_.fail(what + ": bad light index");
    const size_t lightsBefore = scene_.lights.size();  // a light of an unknown type adds none
    addLight(m_.lights[size_t(li)], world, what + " light " + std::to_string(li));
    // extras.castsShadow on the light or on its node (a boolean: checked in the JSON).
    auto marked = [](const tinygltf::Value& extras) {
      return extras.IsObject() && extras.Has("castsShadow") && extras.Get("castsShadow").IsBool() &&
             extras.Get("castsShadow").Get<bool>();
    };
    if (scene_.lights.size() > lightsBefore)
      scene_.lights.back().castsShadow =
          marked(m_.lights[size_t(li)].extras) || marked(node.extras);
  }

  if (node.camera >= 0) {
    if (size_t(node.camera) >= m_.cameras.size()) read_.fail(what + ": bad camera index");
    const auto& cam = m_.cameras[size_t(node.camera)];
    if (cam.type != "perspective") {
      ++orthographic_;
    } else if (haveCamera_) {
      ++extraCameras_;
    } else {
      // View = inverse of the node's world matrix, with any scale taken out (rigid). A zero scale
      // or a flattening matrix leaves no orientation: an error, not a black image.
      glm::dmat4 rigid(1.0);
      for (int c = 0; c < 3; ++c) {
        glm::dvec3 axis(world[c]);
        double len = glm::length(axis);
        if (!(len > 0.0))
          read_.fail(what + ": the camera's node transform has a zero scale (no view direction)");
        rigid[c] = glm::dvec4(axis / len, 0.0);
      }
      if (!(std::fabs(glm::determinant(glm::dmat3(rigid))) > 1e-3))
        read_.fail(what + ": the camera's node transform is degenerate (its axes are parallel)");
      rigid[3] = world[3];
      camera_.viewFromWorld = glm::inverse(rigid);
      // yfov, znear > 0 and zfar >= 0 within float's range were checked in the JSON.
      const auto& pc = cam.perspective;
      // Below pi as the float the camera keeps (a float of 3.14159264 is above pi).
      if (!(double(float(pc.yfov)) < kPiDouble))
        read_.fail(what + ": camera yfov " + fullText(pc.yfov) + " is not below pi (" +
                   fullText(kPiDouble) + ") as a float");
      if (pc.zfar > 0.0 && !(pc.zfar > pc.znear))
        read_.fail(what + ": camera zfar " + shortText(pc.zfar) + " is not beyond znear " +
                   shortText(pc.znear));
      camera_.yfov = float(pc.yfov);
      camera_.znear = float(pc.znear);
      camera_.zfar = float(pc.zfar);  // 0: infinite, set in buildCameraPath
      if (!(camera_.znear > 0.0f))
        read_.fail(what + ": camera znear " + shortText(pc.znear) + " is 0 as a float");
      haveCamera_ = true;
    }
  }

  for (int child : node.children) visit(child, world, depth + 1);
  visiting_.erase(index);
}

void GltfLoader::buildCameraPath() {
  // Bounds of the geometry (a unit box at the origin if there is none).
  Bounds b = scene_.bounds();
  if (scene_.vertices.empty()) b = Bounds{glm::vec3(-1.0f), glm::vec3(1.0f)};
  glm::vec3 c = b.center();
  float radius = std::max(0.5f * glm::length(b.extent()), 1e-3f);
  const float yfov = kPi / 3.0f, tanHalf = std::tan(0.5f * yfov);
  if (haveCamera_) {
    if (camera_.zfar <= 0.0f) {
      glm::vec3 eye = glm::vec3(glm::inverse(camera_.viewFromWorld)[3]);
      camera_.zfar = std::max(1000.0f * camera_.znear, 2.0f * (glm::length(eye - c) + radius));
    }
    scene_.cameraPath.push_back(camera_);
  }
  // Orbit the bounds' centre at 30° elevation, each frame as close as keeps all eight corners of
  // the bounds inside a square 60° view (so any aspect ratio >= 1 shows everything), plus 5%.
  // Frame 0 of the orbit is the framing camera.
  const float elevation = 30.0f * kPi / 180.0f, azimuth0 = 35.0f * kPi / 180.0f;
  for (int k = 0; k < kOrbitFrames; ++k) {
    float a = azimuth0 + 2.0f * kPi * float(k) / float(kOrbitFrames);
    glm::vec3 back(std::cos(elevation) * std::sin(a), std::sin(elevation),
                   std::cos(elevation) * std::cos(a));  // from the centre towards the eye
    glm::vec3 right = glm::normalize(glm::cross(glm::vec3(0.0f, 1.0f, 0.0f), back));
    glm::vec3 up = glm::cross(back, right);
    float distance = 0.0f, depth = 0.0f;
    for (int corner = 0; corner < 8; ++corner) {
      glm::vec3 p(corner & 1 ? b.max.x : b.min.x, corner & 2 ? b.max.y : b.min.y,
                  corner & 4 ? b.max.z : b.min.z);
      glm::vec3 d = p - c;
      float towards = glm::dot(d, back);  // how far the corner sticks out towards the camera
      float side = std::max(std::fabs(glm::dot(d, right)), std::fabs(glm::dot(d, up)));
      distance = std::max(distance, towards + side / tanHalf);
      depth = std::max(depth, std::fabs(towards));
    }
    distance = std::max(1.05f * distance, 1e-3f);
    float znear = std::max(0.5f * (distance - depth), 0.002f * distance);
    float zfar = 1.5f * (distance + radius);
    scene_.cameraPath.push_back(
        SceneCamera::lookAt(c + distance * back, c, {0.0f, 1.0f, 0.0f}, yfov, znear, zfar));
  }
  // Geometry spread over more than float's range (vertices near +-3e38) cannot be framed.
  for (const SceneCamera& cam : scene_.cameraPath)
    if (!isFinite(glm::mat4(cam.viewFromWorld)) || !(cam.znear > 0.0f) || !(cam.zfar > cam.znear) ||
        !std::isfinite(cam.zfar))
      read_.fail("the scene's extent (bounds " + shortText(b.min.x) + ".." + shortText(b.max.x) +
                 " in x) is too large to frame with float cameras");
}

// With at most one parent per node, a cycle of nodes (each the child of the one before) has no
// root: no walk from the roots would reach it, and its meshes and lights would be dropped without
// a word. Found by walking up from every node, each node's walk done once (linear).
void GltfLoader::failOnCycles() const {
  const size_t n = m_.nodes.size();
  std::vector<int> parent(n, -1);
  for (size_t i = 0; i < n; ++i)
    for (int c : m_.nodes[i].children)
      if (c >= 0 && size_t(c) < n) parent[size_t(c)] = int(i);
  enum : char { kUnknown, kOnThisWalk, kReachesARoot };
  std::vector<char> state(n, kUnknown);
  for (size_t i = 0; i < n; ++i) {
    size_t k = i;
    while (state[k] == kUnknown && parent[k] >= 0) {
      state[k] = kOnThisWalk;
      k = size_t(parent[k]);
    }
    if (state[k] == kOnThisWalk)
      read_.fail("node hierarchy has a cycle through node " + std::to_string(k));
    for (size_t j = i; state[j] == kOnThisWalk; j = size_t(parent[j])) state[j] = kReachesARoot;
    state[k] = kReachesARoot;
  }
}

Scene GltfLoader::load() {
  scene_.name = std::filesystem::path(path_).stem().string();
  scene_.ambient = glm::vec3(0.05f);

  // glTF node hierarchies are trees (a node has at most one parent; a scene lists root nodes,
  // each once): otherwise a chain of shared children would be visited exponentially often.
  std::vector<int> parents(m_.nodes.size(), 0);
  for (const auto& n : m_.nodes)
    for (int c : n.children)
      if (c >= 0 && size_t(c) < parents.size() && ++parents[size_t(c)] > 1)
        read_.fail("node " + std::to_string(c) +
                   " has more than one parent (glTF node "
                   "hierarchies are trees)");
  failOnCycles();
  std::vector<int> roots;
  int sceneIndex = m_.defaultScene >= 0 ? m_.defaultScene : (m_.scenes.empty() ? -1 : 0);
  if (sceneIndex >= 0) {
    if (size_t(sceneIndex) >= m_.scenes.size()) read_.fail("bad default scene index");
    const auto& s = m_.scenes[size_t(sceneIndex)];
    roots = s.nodes;
    std::set<int> unique;
    for (int r : roots)
      if (r >= 0 && size_t(r) < parents.size() &&
          (parents[size_t(r)] > 0 || !unique.insert(r).second))
        read_.fail("scene " + std::to_string(sceneIndex) + " lists node " + std::to_string(r) +
                   " twice or although it is another node's child");
    // tileshade's own export stores the ambient term here.
    if (s.extras.IsObject() && s.extras.Has("tileshade")) {
      const auto& ts = s.extras.Get("tileshade");
      scene_.ambient = vec3(&ts, "ambient", scene_.ambient);
    }
  } else {
    // No scenes: every node that is nobody's child is a root.
    for (size_t i = 0; i < m_.nodes.size(); ++i)
      if (parents[i] == 0) roots.push_back(int(i));
  }
  decodeImages();
  for (int r : roots) visit(r, glm::dmat4(1.0), 0);

  auto warn = [&](const std::string& message) { warnings_.push_back(message); };
  if (skippedPrimitives_ > 0)
    warn("skipped " + std::to_string(skippedPrimitives_) +
         " primitive(s) that are not triangles (points/lines) or have no POSITION");
  if (otherTexCoords_ > 0)
    warn(std::to_string(otherTexCoords_) +
         " texture(s) use another UV set than their "
         "material's base colour texture; sampled with the base colour's set");
  if (otherLights_ > 0)
    warn("skipped " + std::to_string(otherLights_) +
         " light(s) of an unknown type (KHR_lights_punctual has point, spot, directional)");
  if (!unmodelledSamplers_.empty())
    warn("ignored " + std::to_string(unmodelledSamplers_.size()) +
         " sampler setting(s), "
         "textures are sampled with their magnification filter: " +
         listed({unmodelledSamplers_.begin(), unmodelledSamplers_.end()}));
  if (!transformedTextures_.empty())
    warn("ignored KHR_texture_transform (offset, rotation, scale) on " +
         std::to_string(transformedTextures_.size()) +
         " texture reference(s): " + listed(transformedTextures_));
  if (orthographic_ > 0)
    warn("ignored " + std::to_string(orthographic_) +
         " orthographic camera(s): only perspective cameras are supported");
  if (!m_.skins.empty() || !m_.animations.empty())
    warn("ignored " + std::to_string(m_.skins.size()) + " skin(s) and " +
         std::to_string(m_.animations.size()) +
         " animation(s): meshes are drawn static, with their nodes' transforms");
  if (!textureFailures_.empty())
    warn(std::to_string(textureFailures_.size()) +
         " texture(s) could not be decoded, using the factors alone: " + listed(textureFailures_));
  if (!clampedFactors_.empty())
    warn("clamped " + std::to_string(clampedFactors_.size()) +
         " material factor(s) outside glTF's [0, 1] to it: " + listed(clampedFactors_));
  if (!normalMapsWithoutUVs_.empty())
    warn("normal map(s) ignored on " + std::to_string(normalMapsWithoutUVs_.size()) +
         " primitive(s) without TANGENT or texture coordinates (no tangent frame can be made): " +
         listed(normalMapsWithoutUVs_));
  if (verticesWithoutFrame_ > 0)
    warn(std::to_string(verticesWithoutFrame_) +
         " vertex(es) of normal-mapped primitives have no tangent frame (degenerate UVs, or a "
         "TANGENT of zero length): the normal map is not applied there");
  if (normalMapped_) scene_.tangents = std::move(tangents_);
  if (degenerateNormals_ > 0)
    warn(std::to_string(degenerateNormals_) +
         " vertex normal(s) of zero length (or under a "
         "singular node transform) replaced by +Y");
  buildCameraPath();
  return std::move(scene_);
}

const std::vector<std::string>& GltfLoader::warnings() const { return warnings_; }

// tinygltf's warnings without those about images: a texture that cannot be read is reported
// once, by the loader's texture list (tinygltf would add "File not found" for the same file).
std::vector<std::string> tinygltfWarnings(const std::string& text) {
  std::vector<std::string> out;
  std::string line;
  std::istringstream in(text);
  while (std::getline(in, line)) {
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
    if (line.empty() || line.rfind("File not found", 0) == 0 ||
        line.find("for image[") != std::string::npos)
      continue;
    out.push_back("tinygltf: " + line);
  }
  return out;
}

// tinygltf's reader of the files a uri names (buffers, images), through readTextFile: a directory
// is "it is a directory", not the out-of-memory of tinygltf's own reader sizing it.
bool readReferencedFile(std::vector<unsigned char>* out, std::string* err, const std::string& path,
                        void*) {
  try {
    const std::string bytes = readTextFile(path, "file");
    out->assign(bytes.begin(), bytes.end());
    return true;
  } catch (const Error& e) {
    if (err) *err += e.what();
    return false;
  }
}

void report(const std::string& name, const std::vector<std::string>& lines,
            std::vector<std::string>* warnings) {
  if (warnings) warnings->insert(warnings->end(), lines.begin(), lines.end());
  else printSceneWarnings(name, lines);
}

}  // namespace

Scene loadGltfFromMemory(const unsigned char* bytes, size_t size, const std::string& baseDir,
                         const std::string& name, std::vector<std::string>* warnings) {
  // tinygltf takes 32-bit sizes.
  if (size > size_t(UINT32_MAX))
    throw Error("cannot load glTF file " + name + ": larger than 4 GiB");
  // The JSON's types and shapes first: tinygltf would drop or truncate what does not fit.
  std::string text;
  if (gltf::jsonText(bytes, size, text)) {
    gltf::checkJson(parseStrictJson(text, "cannot load glTF file " + name), name);
  }
  bool binary = size >= 4 && std::memcmp(bytes, "glTF", 4) == 0;
  tinygltf::TinyGLTF gltf;
  gltf.SetImageLoader(keepEncodedImage, nullptr);
  gltf.SetFsCallbacks({&tinygltf::FileExists, &tinygltf::ExpandFilePath, readReferencedFile,
                       &tinygltf::WriteWholeFile, nullptr});
  tinygltf::Model model;
  std::string err, warningText;
  bool ok =
      binary
          ? gltf.LoadBinaryFromMemory(&model, &err, &warningText, bytes, unsigned(size), baseDir)
          : gltf.LoadASCIIFromString(&model, &err, &warningText,
                                     reinterpret_cast<const char*>(bytes), unsigned(size), baseDir);
  if (!ok)
    throw Error("cannot load glTF file " + name + ": " +
                (err.empty() ? std::string("tinygltf reported no reason")
                             : ts::shortText(oneLine(err), 300)));
  std::vector<std::string> found = tinygltfWarnings(warningText);

  static const std::set<std::string> fatal = {"KHR_draco_mesh_compression",
                                              "EXT_meshopt_compression"};
  static const std::set<std::string> supported = {"KHR_lights_punctual", "KHR_materials_specular",
                                                  "KHR_materials_emissive_strength",
                                                  "KHR_mesh_quantization"};
  std::string approximated;
  for (const auto& e : model.extensionsRequired) {
    if (fatal.count(e))
      throw Error("cannot load glTF file " + name + ": it requires " + ts::shortText(e) +
                  ", which is not supported");
    if (!supported.count(e)) approximated += (approximated.empty() ? "" : ", ") + ts::shortText(e);
  }
  if (!approximated.empty())
    found.push_back("required extension(s) not supported, loading without them: " +
                    ts::shortText(approximated, 300));

  GltfLoader loader(model, name);
  Scene scene = loader.load();
  // Only now, once nothing can fail: an error is the only line about a file that fails.
  found.insert(found.end(), loader.warnings().begin(), loader.warnings().end());
  report(name, found, warnings);
  return scene;
}

Scene loadGltf(const std::string& path, std::vector<std::string>* warnings) {
  const std::string bytes = readTextFile(path, "glTF file");
  return loadGltfFromMemory(reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size(),
                            std::filesystem::path(path).parent_path().string(), path, warnings);
}

}  // namespace ts
