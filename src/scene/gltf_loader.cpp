// glTF 2.0 (.gltf / .glb) -> Scene, through tinygltf. Mappings are documented in scenes/README.md.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <set>
#include <sstream>
#include <thread>

#ifndef TILESHADE_NO_OIIO
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#endif
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <tiny_gltf.h>

#include "scene/gltf_mapping.h"
#include "scene/light_range.h"
#include "scene/scene_loader.h"
#include "util/error.h"

namespace ts {

namespace {

constexpr float kPi = 3.14159265358979f;
constexpr int kOrbitFrames = 240;

std::string oneLine(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == '\r' || s.back() == ' ')) s.pop_back();
  for (size_t i = 0; (i = s.find('\n', i)) != std::string::npos;) s.replace(i, 1, "; ");
  return s;
}

void warn(const std::string& path, const std::string& message) {
  std::cerr << "tileshade: warning: " << path << ": " << message << "\n";
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

class Reader {
 public:
  Reader(const tinygltf::Model& m, const std::string& path) : m_(m), path_(path) {}

  [[noreturn]] void fail(const std::string& what) const {
    throw Error("invalid glTF file " + path_ + ": " + what);
  }

  // The bytes of bufferView `index` from `offset`, checking that `needed` bytes exist.
  const unsigned char* view(int index, size_t offset, size_t needed, const std::string& what) const {
    if (index < 0 || size_t(index) >= m_.bufferViews.size()) fail(what + ": bad bufferView");
    const auto& bv = m_.bufferViews[size_t(index)];
    if (bv.buffer < 0 || size_t(bv.buffer) >= m_.buffers.size()) fail(what + ": bad buffer");
    const auto& buf = m_.buffers[size_t(bv.buffer)];
    if (offset + needed > bv.byteLength || bv.byteOffset + bv.byteLength > buf.data.size())
      fail(what + ": data runs past its bufferView/buffer");
    return buf.data.data() + bv.byteOffset + offset;
  }

  // Accessor `index` as `count * components` doubles (components = that of its type), decoding
  // any component type, normalization, byte stride and sparse substitution.
  std::vector<double> read(int index, int wantComponents, const std::string& what) const {
    if (index < 0 || size_t(index) >= m_.accessors.size()) fail(what + ": bad accessor");
    const auto& a = m_.accessors[size_t(index)];
    int nc = tinygltf::GetNumComponentsInType(uint32_t(a.type));
    int cs = tinygltf::GetComponentSizeInBytes(uint32_t(a.componentType));
    if (nc <= 0 || cs <= 0) fail(what + ": unsupported accessor type");
    if (wantComponents > 0 && nc != wantComponents)
      fail(what + ": expected " + std::to_string(wantComponents) + " components, got " +
           std::to_string(nc));
    size_t count = a.count;
    std::vector<double> out(count * size_t(nc), 0.0);
    if (a.bufferView >= 0 && count > 0) {
      if (size_t(a.bufferView) >= m_.bufferViews.size()) fail(what + ": bad bufferView");
      const auto& bv = m_.bufferViews[size_t(a.bufferView)];
      int stride = a.ByteStride(bv);
      if (stride <= 0) fail(what + ": bad byteStride");
      size_t elem = size_t(nc) * size_t(cs);
      const unsigned char* p =
          view(a.bufferView, a.byteOffset, size_t(stride) * (count - 1) + elem, what);
      for (size_t i = 0; i < count; ++i)
        for (int c = 0; c < nc; ++c)
          out[i * size_t(nc) + size_t(c)] =
              readComponent(p + i * size_t(stride) + size_t(c) * size_t(cs), a.componentType,
                            a.normalized);
    }
    if (a.sparse.isSparse && a.sparse.count > 0) {
      size_t n = size_t(a.sparse.count);
      int ics = tinygltf::GetComponentSizeInBytes(uint32_t(a.sparse.indices.componentType));
      if (ics <= 0) fail(what + ": bad sparse index type");
      const unsigned char* ip = view(a.sparse.indices.bufferView,
                                     size_t(a.sparse.indices.byteOffset), n * size_t(ics), what);
      size_t elem = size_t(nc) * size_t(cs);
      const unsigned char* vp =
          view(a.sparse.values.bufferView, size_t(a.sparse.values.byteOffset), n * elem, what);
      for (size_t i = 0; i < n; ++i) {
        size_t target = size_t(readComponent(ip + i * size_t(ics), a.sparse.indices.componentType,
                                             false));
        if (target >= count) fail(what + ": sparse index out of range");
        for (int c = 0; c < nc; ++c)
          out[target * size_t(nc) + size_t(c)] =
              readComponent(vp + i * elem + size_t(c) * size_t(cs), a.componentType, a.normalized);
      }
    }
    return out;
  }

 private:
  const tinygltf::Model& m_;
  std::string path_;
};

// ---- transforms ------------------------------------------------------------------------------

// In double, as the file's numbers are: far from the origin the node transforms, and the camera
// made from them, keep what float products of matrices would round away (Camera).
glm::dmat4 localMatrix(const tinygltf::Node& n) {
  if (n.matrix.size() == 16) {
    glm::dmat4 m;
    for (int i = 0; i < 16; ++i) glm::value_ptr(m)[i] = n.matrix[size_t(i)];  // column-major
    return m;
  }
  glm::dmat4 m(1.0);
  if (n.translation.size() == 3)
    m = glm::translate(m, glm::dvec3(n.translation[0], n.translation[1], n.translation[2]));
  if (n.rotation.size() == 4) {
    glm::dquat q(n.rotation[3], n.rotation[0], n.rotation[1],
                 n.rotation[2]);  // glTF stores x, y, z, w
    m *= glm::mat4_cast(glm::normalize(q));
  }
  if (n.scale.size() == 3) m = glm::scale(m, glm::dvec3(n.scale[0], n.scale[1], n.scale[2]));
  return m;
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

// Encoded PNG/JPEG/... bytes -> linear RGBA texels: colour channels sRGB-decoded when `srgb` (base
// colour and emissive textures), taken as they are otherwise (metallic-roughness); alpha linear.
DecodedImage decodeImage(const tinygltf::Image& image, int index, bool srgb) {
  DecodedImage result;
  result.texture.srgb = srgb;
  if (image.image.empty()) {
    result.why = "not found";
    return result;
  }
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
  if (tinygltf::LoadImageData(&d, index, &err, &warnings, 0, 0, image.image.data(),
                              int(image.image.size()), nullptr) &&
      d.width > 0 && d.height > 0 && d.component > 0) {
    size_t nc = size_t(d.component);
    const unsigned char* px = d.image.data();
    if (d.bits == 16)
      fill(d.width, d.height, d.component, [&](size_t p, int c) {
        uint16_t v;
        std::memcpy(&v, px + 2 * (p * nc + size_t(c)), 2);
        return double(v) / 65535.0;
      }, false);
    else
      fill(d.width, d.height, d.component, [&](size_t p, int c) { return px[p * nc + size_t(c)]; },
           true);
    result.ok = true;
    return result;
  }
#ifdef TILESHADE_NO_OIIO
  result.why = oneLine(err.empty() ? std::string("built without OpenImageIO") : err);
  return result;
#else
  // Then OpenImageIO from memory (whatever formats it was built with).
  std::string ext = image.mimeType == "image/jpeg" ? "jpg" : "png";
  if (auto dot = image.uri.rfind('.'); !image.uri.empty() && dot != std::string::npos)
    ext = image.uri.substr(dot + 1);
  OIIO::Filesystem::IOMemReader mem(const_cast<unsigned char*>(image.image.data()),
                                    image.image.size());
  auto in = OIIO::ImageInput::open("image." + ext, nullptr, &mem);
  if (!in) {
    result.why = oneLine(err.empty() ? OIIO::geterror() : err);
    return result;
  }
  const auto& spec = in->spec();
  size_t nc = size_t(spec.nchannels);
  std::vector<float> all(size_t(std::max(spec.width, 0)) * size_t(std::max(spec.height, 0)) * nc);
  if (spec.width <= 0 || spec.height <= 0 ||
      !in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, all.data())) {
    result.why = oneLine(in->geterror());
    return result;
  }
  fill(spec.width, spec.height, std::min(spec.nchannels, 4),
       [&](size_t p, int c) { return double(all[p * nc + size_t(c)]); }, false);
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

 private:
  void visit(int node, const glm::dmat4& parent, int depth);
  void addPrimitive(const tinygltf::Primitive& p, const glm::dmat4& world, const std::string& what);
  uint32_t material(int gltfMaterial);
  int texture(int gltfTexture, bool srgb, int texCoord, const std::string& what);
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
  int uvSet_ = 0;           // the base colour's UV set of the material being read
  std::vector<std::string> textureFailures_;
  int skippedPrimitives_ = 0;
  int otherLights_ = 0, orthographic_ = 0, extraCameras_ = 0;
  bool haveCamera_ = false;
  Camera camera_;
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
    std::string what = "material '" + mat.name + "'";
    out.name = mat.name;
    out.baseColor = glm::vec3(1.0f);
    if (pbr.baseColorFactor.size() >= 3)
      out.baseColor = {float(pbr.baseColorFactor[0]), float(pbr.baseColorFactor[1]),
                       float(pbr.baseColorFactor[2])};
    out.metallic = std::clamp(float(pbr.metallicFactor), 0.0f, 1.0f);
    out.roughness = std::clamp(float(pbr.roughnessFactor), 0.0f, 1.0f);
    if (const auto* spec = extension(mat.extensions, "KHR_materials_specular"))
      dielectricF0 = vec3(spec, "specularColorFactor", glm::vec3(1.0f)) *
                     float(number(spec, "specularFactor", 1.0));
    if (mat.emissiveFactor.size() >= 3)
      out.emissive = {float(mat.emissiveFactor[0]), float(mat.emissiveFactor[1]),
                      float(mat.emissiveFactor[2])};
    out.emissive *= float(number(extension(mat.extensions, "KHR_materials_emissive_strength"),
                                 "emissiveStrength", 1.0));
    out.doubleSided = mat.doubleSided;
    uvSet_ = std::max(pbr.baseColorTexture.texCoord, 0);  // the UV set addPrimitive keeps
    if (pbr.baseColorTexture.index >= 0)
      out.baseColorTexture = texture(pbr.baseColorTexture.index, true, uvSet_, what);
    if (pbr.metallicRoughnessTexture.index >= 0)
      out.metallicRoughnessTexture = texture(pbr.metallicRoughnessTexture.index, false,
                                             pbr.metallicRoughnessTexture.texCoord, what);
    if (mat.emissiveTexture.index >= 0)
      out.emissiveTexture =
          texture(mat.emissiveTexture.index, true, mat.emissiveTexture.texCoord, what);
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

// The scene texture of glTF texture `index` decoded in the given colour space (-1 when it cannot
// be: the factor alone is used, and load() warns once for all of them). Only the base colour's
// UV set is kept per vertex; a texture on another set is sampled with it (counted, warned once).
int GltfLoader::texture(int index, bool srgb, int texCoord, const std::string& what) {
  if (std::max(texCoord, 0) != uvSet_) ++otherTexCoords_;
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
    std::string name = !image.uri.empty() ? image.uri : !image.name.empty() ? image.name
                                                      : "image " + std::to_string(source);
    textureFailures_.push_back(name + " (" + one.why + ")");
  }
  images_[key] = result;
  return result;
}

// Decodes every image a material uses (base colour and emissive as sRGB, metallic-roughness as
// linear data), on up to 4 threads (PNG decoding dominates the load time of textured scenes).
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
  }
  std::vector<DecodedImage> results(wanted.size());
  std::atomic<size_t> next{0};
  auto work = [&] {
    for (size_t i; (i = next++) < wanted.size();)
      results[i] = decodeImage(m_.images[size_t(wanted[i].first)], wanted[i].first,
                               wanted[i].second);
  };
  size_t threads = std::min<size_t>({wanted.size(), 4, std::max(1u, std::thread::hardware_concurrency())});
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
  glm::vec3 color(1.0f);
  if (light.color.size() >= 3)
    color = {float(light.color[0]), float(light.color[1]), float(light.color[2])};
  color *= float(light.intensity);
  glm::vec3 position = glm::vec3(world[3]);
  glm::vec3 axis = glm::vec3(-world[2]);
  float axisLength = glm::length(axis);
  float range = light.range > 0.0 ? float(light.range) : rangeFromThreshold(color, gltf::kLightThreshold);
  if (light.type == "point") {
    scene_.lights.push_back(Light::point(position, color, range));
    return;
  }
  if (light.type != "spot" && light.type != "directional") {
    ++otherLights_;
    return;
  }
  if (!(axisLength > 0.0f) || !std::isfinite(axisLength))
    read_.fail(what + ": the " + light.type + " light's node transform has no direction");
  glm::vec3 direction = axis / axisLength;
  if (light.type == "directional") {
    scene_.lights.push_back(Light::directional(direction, color));
    return;
  }
  double inner = light.spot.innerConeAngle, outer = light.spot.outerConeAngle;
  const double halfPi = 1.5707963267948966;
  if (!(inner >= 0.0 && inner < outer && outer <= halfPi))
    read_.fail(what + ": spot cone angles must satisfy 0 <= innerConeAngle < outerConeAngle <= "
               "pi/2, got inner " + std::to_string(inner) + ", outer " + std::to_string(outer));
  scene_.lights.push_back(
      Light::spot(position, direction, color, range, float(inner), float(outer)));
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
  if (p.material >= 0 && size_t(p.material) < m_.materials.size())
    texCoord = std::max(m_.materials[size_t(p.material)].pbrMetallicRoughness.baseColorTexture.texCoord, 0);
  if (auto it = p.attributes.find("TEXCOORD_" + std::to_string(texCoord)); it != p.attributes.end())
    UV = read_.read(it->second, 2, what + " TEXCOORD");
  if (N.size() != 0 && N.size() != P.size()) read_.fail(what + ": NORMAL count differs from POSITION");
  if (UV.size() != 0 && UV.size() / 2 != n) read_.fail(what + ": TEXCOORD count differs from POSITION");

  // Triangle list (of the primitive's vertex indices).
  std::vector<uint32_t> idx;
  if (p.indices >= 0) {
    std::vector<double> raw = read_.read(p.indices, 1, what + " indices");
    idx.reserve(raw.size());
    for (double v : raw) idx.push_back(uint32_t(v));
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
    return glm::vec3(world * glm::dvec4(P[3 * i], P[3 * i + 1], P[3 * i + 2], 1.0));
  };
  auto uv = [&](uint32_t i) {
    return UV.empty() ? glm::vec2(0.0f) : glm::vec2(float(UV[2 * i]), float(UV[2 * i + 1]));
  };
  if (!N.empty()) {
    uint32_t base = uint32_t(scene_.vertices.size());
    for (uint32_t i = 0; i < n; ++i) {
      Vertex v;
      v.position = position(i);
      glm::vec3 nn = normalMatrix * glm::vec3(float(N[3 * i]), float(N[3 * i + 1]), float(N[3 * i + 2]));
      float len = glm::length(nn);
      v.normal = len > 0.0f && std::isfinite(len) ? nn / len : glm::vec3(0.0f, 1.0f, 0.0f);
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
      glm::vec3 fn = glm::cross(p1 - p0, p2 - p0);
      float len = glm::length(fn);
      fn = len > 0.0f ? fn / len : glm::vec3(0.0f, 1.0f, 0.0f);
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
}

void GltfLoader::visit(int index, const glm::dmat4& parent, int depth) {
  if (index < 0 || size_t(index) >= m_.nodes.size()) read_.fail("bad node index " + std::to_string(index));
  if (depth > 1000 || !visiting_.insert(index).second) read_.fail("node hierarchy has a cycle");
  const auto& node = m_.nodes[size_t(index)];
  glm::dmat4 world = parent * localMatrix(node);
  std::string what = "node '" + node.name + "'";

  if (node.mesh >= 0) {
    if (size_t(node.mesh) >= m_.meshes.size()) read_.fail(what + ": bad mesh index");
    const auto& mesh = m_.meshes[size_t(node.mesh)];
    for (size_t i = 0; i < mesh.primitives.size(); ++i)
      addPrimitive(mesh.primitives[i], world,
                   "mesh '" + mesh.name + "' primitive " + std::to_string(i));
  }

  if (const auto* ext = extension(node.extensions, "KHR_lights_punctual")) {
    int li = int(number(ext, "light", -1.0));
    if (li < 0 || size_t(li) >= m_.lights.size()) read_.fail(what + ": bad light index");
    addLight(m_.lights[size_t(li)], world, what);
  }

  if (node.camera >= 0) {
    if (size_t(node.camera) >= m_.cameras.size()) read_.fail(what + ": bad camera index");
    const auto& cam = m_.cameras[size_t(node.camera)];
    if (cam.type != "perspective") {
      ++orthographic_;
    } else if (haveCamera_) {
      ++extraCameras_;
    } else {
      // View = inverse of the node's world matrix, with any scale taken out (rigid).
      glm::dmat4 rigid(1.0);
      for (int c = 0; c < 3; ++c) {
        glm::dvec3 axis(world[c]);
        double len = glm::length(axis);
        rigid[c] = glm::dvec4(len > 0.0 ? axis / len : glm::dvec3(0.0), 0.0);
      }
      rigid[3] = world[3];
      camera_.viewFromWorld = glm::inverse(rigid);
      const auto& pc = cam.perspective;
      camera_.yfov = pc.yfov > 0.0 ? float(pc.yfov) : kPi / 3.0f;
      camera_.znear = pc.znear > 0.0 ? float(pc.znear) : 0.1f;
      camera_.zfar = pc.zfar > pc.znear ? float(pc.zfar) : 0.0f;  // 0: infinite, set below
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
        Camera::lookAt(c + distance * back, c, {0.0f, 1.0f, 0.0f}, yfov, znear, zfar));
  }
}

Scene GltfLoader::load() {
  scene_.name = std::filesystem::path(path_).stem().string();
  scene_.ambient = glm::vec3(0.05f);

  std::vector<int> roots;
  int sceneIndex = m_.defaultScene >= 0 ? m_.defaultScene : (m_.scenes.empty() ? -1 : 0);
  if (sceneIndex >= 0) {
    if (size_t(sceneIndex) >= m_.scenes.size()) read_.fail("bad default scene index");
    const auto& s = m_.scenes[size_t(sceneIndex)];
    roots = s.nodes;
    // tileshade's own export stores the ambient term here.
    if (s.extras.IsObject() && s.extras.Has("tileshade")) {
      const auto& ts = s.extras.Get("tileshade");
      scene_.ambient = vec3(&ts, "ambient", scene_.ambient);
    }
  } else {
    // No scenes: every node that is nobody's child is a root.
    std::vector<bool> child(m_.nodes.size(), false);
    for (const auto& n : m_.nodes)
      for (int c : n.children)
        if (c >= 0 && size_t(c) < child.size()) child[size_t(c)] = true;
    for (size_t i = 0; i < m_.nodes.size(); ++i)
      if (!child[i]) roots.push_back(int(i));
  }
  decodeImages();
  for (int r : roots) visit(r, glm::dmat4(1.0), 0);

  if (skippedPrimitives_ > 0)
    warn(path_, "skipped " + std::to_string(skippedPrimitives_) +
                    " primitive(s) that are not triangles (points/lines) or have no POSITION");
  if (otherTexCoords_ > 0)
    warn(path_, std::to_string(otherTexCoords_) + " texture(s) use another UV set than their "
                "material's base colour texture; sampled with the base colour's set");
  if (otherLights_ > 0)
    warn(path_, "skipped " + std::to_string(otherLights_) +
                    " light(s) of an unknown type (KHR_lights_punctual has point, spot, directional)");
  if (orthographic_ > 0)
    warn(path_, "ignored " + std::to_string(orthographic_) +
                    " orthographic camera(s): only perspective cameras are supported");
  if (!m_.skins.empty() || !m_.animations.empty())
    warn(path_, "ignored " + std::to_string(m_.skins.size()) + " skin(s) and " +
                    std::to_string(m_.animations.size()) +
                    " animation(s): meshes are drawn static, with their nodes' transforms");
  if (!textureFailures_.empty()) {
    std::string list;
    for (size_t i = 0; i < textureFailures_.size() && i < 3; ++i)
      list += (i ? ", " : "") + textureFailures_[i];
    if (textureFailures_.size() > 3) list += ", ...";
    warn(path_, std::to_string(textureFailures_.size()) +
                    " texture(s) could not be decoded, using the factors alone: " + list);
  }
  buildCameraPath();
  return std::move(scene_);
}

}  // namespace

Scene loadGltf(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw Error("cannot read glTF file " + path + ": no such file");
  // .glb files start with the magic "glTF"; anything else is parsed as JSON.
  char magic[4] = {0, 0, 0, 0};
  {
    std::ifstream f(path, std::ios::binary);
    if (!f) throw Error("cannot read glTF file " + path + ": cannot open it");
    f.read(magic, 4);
  }
  bool binary = std::memcmp(magic, "glTF", 4) == 0;

  tinygltf::TinyGLTF gltf;
  gltf.SetImageLoader(keepEncodedImage, nullptr);
  tinygltf::Model model;
  std::string err, warnings;
  bool ok = binary ? gltf.LoadBinaryFromFile(&model, &err, &warnings, path)
                   : gltf.LoadASCIIFromFile(&model, &err, &warnings, path);
  if (!ok)
    throw Error("cannot load glTF file " + path + ": " +
                (err.empty() ? std::string("tinygltf reported no reason") : oneLine(err)));
  if (!warnings.empty()) warn(path, "tinygltf: " + oneLine(warnings));

  static const std::set<std::string> fatal = {"KHR_draco_mesh_compression",
                                              "EXT_meshopt_compression"};
  static const std::set<std::string> supported = {
      "KHR_lights_punctual", "KHR_materials_specular", "KHR_materials_emissive_strength",
      "KHR_mesh_quantization"};
  std::string approximated;
  for (const auto& e : model.extensionsRequired) {
    if (fatal.count(e))
      throw Error("cannot load glTF file " + path + ": it requires " + e + ", which is not supported");
    if (!supported.count(e)) approximated += (approximated.empty() ? "" : ", ") + e;
  }
  if (!approximated.empty())
    warn(path, "required extension(s) not supported, loading without them: " + approximated);

  return GltfLoader(model, path).load();
}

}  // namespace ts
