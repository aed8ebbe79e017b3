// Scene -> self-contained glTF 2.0 (.gltf with data-URI buffers, or .glb), through tinygltf.
// Mappings (the inverse of the loader's) are documented in scenes/README.md.
#include <algorithm>
#include <cctype>
#include <cstring>
#include <map>
#include <sstream>
#include <tuple>

#ifndef TILESHADE_NO_OIIO
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#endif
#include <glm/gtc/quaternion.hpp>
#define GLM_ENABLE_EXPERIMENTAL
#include <glm/gtx/quaternion.hpp>
#include <tiny_gltf.h>

#include "scene/gltf_mapping.h"
#include "scene/scene_loader.h"
#include "util/error.h"
#include "util/file_write.h"
#include "util/float_limit.h"
#include "util/stderr_capture.h"

namespace ts {

namespace {

bool endsWith(std::string s, const std::string& suffix) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

tinygltf::Value number(double v) { return tinygltf::Value(v); }
tinygltf::Value array(glm::vec3 v) {
  return tinygltf::Value(tinygltf::Value::Array{number(v.x), number(v.y), number(v.z)});
}

class Writer {
 public:
  tinygltf::Model model;

  Writer() {
    model.asset.version = "2.0";
    model.asset.generator = "tileshade";
    model.buffers.emplace_back();
  }

  // Appends bytes (4-aligned) as a new bufferView; returns its index.
  int bufferView(const void* data, size_t bytes, int target) {
    auto& buf = model.buffers[0].data;
    while (buf.size() % 4) buf.push_back(0);
    tinygltf::BufferView bv;
    bv.buffer = 0;
    bv.byteOffset = buf.size();
    bv.byteLength = bytes;
    bv.target = target;
    const auto* p = static_cast<const unsigned char*>(data);
    buf.insert(buf.end(), p, p + bytes);
    model.bufferViews.push_back(bv);
    return int(model.bufferViews.size() - 1);
  }

  template <typename T>
  int accessor(const std::vector<T>& data, int components, int type, int componentType,
               int target) {
    tinygltf::Accessor a;
    a.bufferView = bufferView(data.data(), data.size() * sizeof(T), target);
    a.componentType = componentType;
    a.type = type;
    a.count = data.size() / size_t(components);
    model.accessors.push_back(a);
    return int(model.accessors.size() - 1);
  }

  int positions(const std::vector<float>& p) {
    int index = accessor(p, 3, TINYGLTF_TYPE_VEC3, TINYGLTF_COMPONENT_TYPE_FLOAT,
                         TINYGLTF_TARGET_ARRAY_BUFFER);
    auto& a = model.accessors[size_t(index)];
    a.minValues = {1e30, 1e30, 1e30};
    a.maxValues = {-1e30, -1e30, -1e30};
    for (size_t i = 0; i < p.size(); ++i) {
      a.minValues[i % 3] = std::min(a.minValues[i % 3], double(p[i]));
      a.maxValues[i % 3] = std::max(a.maxValues[i % 3], double(p[i]));
    }
    return index;
  }
};

// Linear RGBA float texture -> 8-bit sRGB PNG bytes (OpenImageIO, in memory).
std::vector<unsigned char> encodePng(const Texture& t) {
  std::vector<unsigned char> pixels(size_t(t.width) * size_t(t.height) * 4);
  for (size_t i = 0; i < t.texels.size(); ++i) {
    const glm::vec4& v = t.texels[i];
    for (int c = 0; c < 3; ++c)
      pixels[4 * i + size_t(c)] =
          (unsigned char)((t.srgb ? gltf::linearToSrgb(v[c]) : std::clamp(v[c], 0.0f, 1.0f)) *
                              255.0f +
                          0.5f);
    pixels[4 * i + 3] = (unsigned char)(std::clamp(v.w, 0.0f, 1.0f) * 255.0f + 0.5f);
  }
#ifdef TILESHADE_NO_OIIO
  throw Error("cannot encode a texture as PNG: built without OpenImageIO");
#else
  std::vector<unsigned char> png;
  OIIO::Filesystem::IOVecOutput out(png);
  StderrCapture libraryMessages;  // libpng prints its errors itself
  auto writer = OIIO::ImageOutput::create("png", &out);
  OIIO::ImageSpec spec(t.width, t.height, 4, OIIO::TypeDesc::UINT8);
  bool ok = writer && writer->open("texture.png", spec) &&
            writer->write_image(OIIO::TypeDesc::UINT8, pixels.data()) && writer->close();
  std::string printed = libraryMessages.text();
  if (!ok) {
    std::string why = writer ? writer->geterror() : OIIO::geterror();
    throw Error("cannot encode a texture as PNG: " + why +
                (printed.empty() ? "" : " (" + printed + ")"));
  }
  return png;
#endif
}

}  // namespace

void checkExportPath(const std::string& path) {
  if (!endsWith(path, ".gltf") && !endsWith(path, ".glb"))
    throw Error("cannot export to " + path + ": the file name must end in .gltf or .glb");
}

namespace {

int gltfWrap(TextureWrap wrap) {
  switch (wrap) {
    case TextureWrap::ClampToEdge: return TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE;
    case TextureWrap::MirroredRepeat: return TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT;
    case TextureWrap::Repeat: break;
  }
  return TINYGLTF_TEXTURE_WRAP_REPEAT;
}

}  // namespace

void exportGltf(const Scene& scene, const std::string& path) {
  checkExportPath(path);
  Writer w;
  tinygltf::Model& m = w.model;
  bool emissiveStrength = false;

  // Textures: embedded PNGs (sRGB) in the buffer, one sampler per wrap modes and filter.
  std::map<std::tuple<TextureWrap, TextureWrap, bool>, int> samplers;
  auto samplerOf = [&](const Texture& t) {
    auto [it, added] =
        samplers.emplace(std::make_tuple(t.wrapS, t.wrapT, t.nearest), int(m.samplers.size()));
    if (added) {
      tinygltf::Sampler sampler;
      sampler.magFilter = sampler.minFilter =
          t.nearest ? TINYGLTF_TEXTURE_FILTER_NEAREST : TINYGLTF_TEXTURE_FILTER_LINEAR;
      sampler.wrapS = gltfWrap(t.wrapS);
      sampler.wrapT = gltfWrap(t.wrapT);
      m.samplers.push_back(sampler);
    }
    return it->second;
  };
  for (size_t i = 0; i < scene.textures.size(); ++i) {
    std::vector<unsigned char> png = encodePng(scene.textures[i]);
    tinygltf::Image image;
    image.name = "texture" + std::to_string(i);
    image.mimeType = "image/png";
    image.bufferView = w.bufferView(png.data(), png.size(), 0);
    m.images.push_back(image);
    tinygltf::Texture tex;
    tex.sampler = samplerOf(scene.textures[i]);
    tex.source = int(i);
    m.textures.push_back(tex);
  }

  // Materials in the model they were written for. Metallic-roughness: its own factors and
  // textures. Blinn-Phong: base colour = kd (metallic 0), KHR_materials_specular colour = ks,
  // roughness from shininess (inverse of the loader's mapping). Emissive > 1 through
  // KHR_materials_emissive_strength.
  bool specularExtension = false;
  auto textureIndex = [&](int t) { return t >= 0 && size_t(t) < scene.textures.size() ? t : -1; };
  for (const Material& mat : scene.materials) {
    tinygltf::Material g;
    g.name = mat.name;
    auto& pbr = g.pbrMetallicRoughness;
    if (mat.model == ShadingModel::MetallicRoughness) {
      pbr.baseColorFactor = {mat.baseColor.x, mat.baseColor.y, mat.baseColor.z, mat.opacity};
      pbr.metallicFactor = mat.metallic;
      pbr.roughnessFactor = mat.roughness;
      pbr.baseColorTexture.index = textureIndex(mat.baseColorTexture);
      pbr.metallicRoughnessTexture.index = textureIndex(mat.metallicRoughnessTexture);
    } else {
      pbr.baseColorFactor = {mat.diffuse.x, mat.diffuse.y, mat.diffuse.z, mat.opacity};
      pbr.metallicFactor = 0.0;
      pbr.roughnessFactor = roughnessFromShininess(mat.shininess);
      pbr.baseColorTexture.index = textureIndex(mat.diffuseTexture);
      g.extensions["KHR_materials_specular"] = tinygltf::Value(tinygltf::Value::Object{
          {"specularFactor", number(1.0)}, {"specularColorFactor", array(mat.specular)}});
      specularExtension = true;
      // So that loading it back shades it with the model it was written for.
      g.extras = tinygltf::Value(tinygltf::Value::Object{
          {"tileshade", tinygltf::Value(tinygltf::Value::Object{
                            {"shading_model", tinygltf::Value(toString(mat.model))}})}});
    }
    g.emissiveTexture.index = textureIndex(mat.emissiveTexture);
    float peak = std::max({mat.emissive.x, mat.emissive.y, mat.emissive.z});
    if (peak > 1.0f) {
      g.emissiveFactor = {mat.emissive.x / peak, mat.emissive.y / peak, mat.emissive.z / peak};
      g.extensions["KHR_materials_emissive_strength"] =
          tinygltf::Value(tinygltf::Value::Object{{"emissiveStrength", number(peak)}});
      emissiveStrength = true;
    } else {
      g.emissiveFactor = {mat.emissive.x, mat.emissive.y, mat.emissive.z};
    }
    g.normalTexture.index = textureIndex(mat.normalTexture);  // with the TANGENT attribute below
    g.normalTexture.scale = mat.normalScale;
    g.doubleSided = mat.doubleSided;
    g.alphaMode = toString(mat.alphaMode);
    g.alphaCutoff = mat.alphaCutoff;
    m.materials.push_back(g);
  }

  // One mesh, one primitive per material that has triangles, with its own compact vertex arrays.
  tinygltf::Mesh mesh;
  mesh.name = scene.name;
  std::vector<std::vector<uint32_t>> byMaterial(scene.materials.size());
  for (size_t t = 0; t < scene.triangleCount(); ++t) {
    uint32_t mi = t < scene.triangleMaterial.size() ? scene.triangleMaterial[t] : 0;
    if (mi >= byMaterial.size())
      throw Error("cannot export scene '" + scene.name + "': triangle " + std::to_string(t) +
                  " has no valid material");
    byMaterial[mi].push_back(uint32_t(t));
  }
  std::vector<uint32_t> remap(scene.vertices.size(), UINT32_MAX);
  for (size_t mi = 0; mi < byMaterial.size(); ++mi) {
    if (byMaterial[mi].empty()) continue;
    std::vector<float> pos, nrm, uv, tan;
    std::vector<uint32_t> idx, used;
    for (uint32_t t : byMaterial[mi]) {
      for (int k = 0; k < 3; ++k) {
        uint32_t v = scene.indices[3 * size_t(t) + size_t(k)];
        if (remap[v] == UINT32_MAX) {
          remap[v] = uint32_t(used.size());
          used.push_back(v);
          const Vertex& vx = scene.vertices[v];
          pos.insert(pos.end(), {vx.position.x, vx.position.y, vx.position.z});
          nrm.insert(nrm.end(), {vx.normal.x, vx.normal.y, vx.normal.z});
          uv.insert(uv.end(), {vx.uv.x, vx.uv.y});
          if (!scene.tangents.empty()) {
            const glm::vec4& t4 = scene.tangents[v];
            tan.insert(tan.end(), {t4.x, t4.y, t4.z, t4.w});
          }
        }
        idx.push_back(remap[v]);
      }
    }
    for (uint32_t v : used) remap[v] = UINT32_MAX;
    tinygltf::Primitive p;
    p.mode = TINYGLTF_MODE_TRIANGLES;
    p.material = int(mi);
    p.attributes["POSITION"] = w.positions(pos);
    p.attributes["NORMAL"] = w.accessor(nrm, 3, TINYGLTF_TYPE_VEC3, TINYGLTF_COMPONENT_TYPE_FLOAT,
                                        TINYGLTF_TARGET_ARRAY_BUFFER);
    p.attributes["TEXCOORD_0"] = w.accessor(
        uv, 2, TINYGLTF_TYPE_VEC2, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TARGET_ARRAY_BUFFER);
    if (!tan.empty())  // the tangents as loaded or generated, so that they come back as they were
      p.attributes["TANGENT"] = w.accessor(
          tan, 4, TINYGLTF_TYPE_VEC4, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TARGET_ARRAY_BUFFER);
    p.indices = w.accessor(idx, 1, TINYGLTF_TYPE_SCALAR, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT,
                           TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
    mesh.primitives.push_back(p);
  }

  tinygltf::Scene gscene;
  gscene.name = scene.name;
  // Not expressible in glTF: the ambient term, kept for tileshade's own loader.
  gscene.extras = tinygltf::Value(tinygltf::Value::Object{
      {"tileshade", tinygltf::Value(tinygltf::Value::Object{{"ambient", array(scene.ambient)}})}});
  if (!mesh.primitives.empty()) {
    m.meshes.push_back(mesh);
    tinygltf::Node node;
    node.name = scene.name;
    node.mesh = 0;
    m.nodes.push_back(node);
    gscene.nodes.push_back(int(m.nodes.size() - 1));
  }

  // Camera frame 0 as a perspective camera node (rotation + translation of the inverse view).
  if (!scene.cameraPath.empty()) {
    const SceneCamera& c = scene.cameraPath[0];
    tinygltf::Camera cam;
    cam.type = "perspective";
    cam.name = "frame0";
    cam.perspective.yfov = c.yfov;
    cam.perspective.znear = c.znear;
    cam.perspective.zfar = c.zfar;
    m.cameras.push_back(cam);
    glm::dmat4 world = glm::inverse(c.viewFromWorld);
    glm::dquat q = glm::normalize(glm::quat_cast(glm::dmat3(world)));
    tinygltf::Node node;
    node.name = "camera";
    node.camera = 0;
    node.translation = {world[3].x, world[3].y, world[3].z};
    node.rotation = {q.x, q.y, q.z, q.w};
    m.nodes.push_back(node);
    gscene.nodes.push_back(int(m.nodes.size() - 1));
  }

  // Lights: KHR_lights_punctual, colour normalised to a peak of 1 with the peak as intensity,
  // each on its own node: translated to the position (point, spot), rotated so that its -Z is
  // the light's direction (spot, directional).
  for (size_t i = 0; i < scene.lights.size(); ++i) {
    const SceneLight& l = scene.lights[i];
    float peak = std::max({l.color.x, l.color.y, l.color.z});
    tinygltf::Light light;
    light.type = toString(l.type);
    light.intensity = peak > 0.0f ? peak : 0.0f;
    glm::vec3 color = peak > 0.0f ? l.color / peak : glm::vec3(1.0f);
    light.color = {color.x, color.y, color.z};
    if (l.hasRange()) light.range = l.range;
    if (l.type == SceneLightType::Spot) {
      // A float pi/2 is above pi/2, which strict loaders refuse: written as pi/2 itself.
      light.spot.innerConeAngle = std::min(double(l.innerConeAngle), kHalfPi);
      light.spot.outerConeAngle = std::min(double(l.outerConeAngle), kHalfPi);
    }
    if (l.castsShadow)
      light.extras =
          tinygltf::Value(tinygltf::Value::Object{{"castsShadow", tinygltf::Value(true)}});
    m.lights.push_back(light);
    tinygltf::Node node;
    node.name = "light" + std::to_string(i);
    if (l.hasRange()) node.translation = {l.position.x, l.position.y, l.position.z};
    if (l.type != SceneLightType::Point) {
      glm::quat q = glm::rotation(glm::vec3(0.0f, 0.0f, -1.0f), glm::normalize(l.direction));
      node.rotation = {q.x, q.y, q.z, q.w};
    }
    node.extensions["KHR_lights_punctual"] =
        tinygltf::Value(tinygltf::Value::Object{{"light", tinygltf::Value(int(i))}});
    m.nodes.push_back(node);
    gscene.nodes.push_back(int(m.nodes.size() - 1));
  }

  m.scenes.push_back(gscene);
  m.defaultScene = 0;
  if (specularExtension) m.extensionsUsed.push_back("KHR_materials_specular");
  if (emissiveStrength) m.extensionsUsed.push_back("KHR_materials_emissive_strength");
  if (!m.lights.empty()) m.extensionsUsed.push_back("KHR_lights_punctual");
  if (m.buffers[0].data.empty()) m.buffers.clear();

  // Serialised in memory (buffers as data URIs in .gltf), then written with a checked write:
  // tinygltf's own file writer does not report a full disk.
  tinygltf::TinyGLTF gltf;
  bool binary = endsWith(path, ".glb");
  std::ostringstream out;
  if (!gltf.WriteGltfSceneToStream(&m, out, /*prettyPrint=*/!binary, binary))
    throw Error("cannot write glTF file " + path + ": tinygltf could not serialise the scene");
  writeFile(path, out.str());
}

}  // namespace ts
