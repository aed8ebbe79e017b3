#include "gbuffer/gbuffer_files.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <limits>
#include <set>

#include "scene/view_space_lights.h"
#include "shading/shading_cpu.h"  // TS_DMIN
#include "util/error.h"
#include "util/file_read.h"
#include "util/float_limit.h"
#include "util/pi.h"
#include "util/short_text.h"
#include "util/strict_json.h"

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace ts {

// ---- G-buffer fields ----------------------------------------------------------------------------

const std::vector<GBufferField>& gbufferFields() {
  constexpr int BP = kModelBit(ShadingModel::BlinnPhong);
  constexpr int MR = kModelBit(ShadingModel::MetallicRoughness);
  static const std::vector<GBufferField> fields = {
      // The normal as stored, before the kernels renormalise it: the kernel's "N" is normalised,
      // and re-encoding a normalised fp16 normal would not give back the stored halves.
      {"normal",
       3,
       GBufferPlane::Normal,
       0,
       kAnyModel,
       true,
       0.0f,
       {"Nraw.x", "Nraw.y", "Nraw.z"},
       "view-space normal (unit, or as stored: the kernels renormalise it)"},
      {"diffuse",
       3,
       GBufferPlane::Diffuse,
       0,
       BP,
       true,
       0.0f,
       {"kd.R", "kd.G", "kd.B"},
       "Blinn-Phong diffuse colour kd (linear RGB)"},
      {"specular",
       3,
       GBufferPlane::Specular,
       0,
       BP,
       false,
       0.0f,
       {"ks.R", "ks.G", "ks.B"},
       "Blinn-Phong specular colour ks (linear RGB)"},
      {"shininess",
       1,
       GBufferPlane::Specular,
       3,
       BP,
       false,
       1.0f,
       {"shininess"},
       "Blinn-Phong exponent s"},
      {"base_color",
       3,
       GBufferPlane::Diffuse,
       0,
       MR,
       true,
       0.0f,
       {"kd.R", "kd.G", "kd.B"},
       "metallic-roughness base colour (linear RGB)"},
      {"metallic", 1, GBufferPlane::Diffuse, 3, MR, false, 0.0f, {"metallic"}, "metallic, 0..1"},
      {"roughness",
       1,
       GBufferPlane::Specular,
       0,
       MR,
       false,
       1.0f,
       {"ks.R"},
       "perceptual roughness, 0..1"},
      {"emissive",
       3,
       GBufferPlane::Emissive,
       0,
       kAnyModel,
       false,
       0.0f,
       {"ke.R", "ke.G", "ke.B"},
       "emitted radiance ke (linear RGB)"},
  };
  return fields;
}

std::vector<const GBufferField*> gbufferFields(ShadingModel model) {
  std::vector<const GBufferField*> out;
  for (const auto& f : gbufferFields())
    if (f.models & kModelBit(model)) out.push_back(&f);
  return out;
}

glm::vec4 fixedComponents(GBufferPlane plane, ShadingModel model, glm::vec4 v) {
  switch (plane) {
    case GBufferPlane::Normal: v.w = 0.0f; break;
    case GBufferPlane::Emissive: v.w = 0.0f; break;
    case GBufferPlane::Diffuse:
      if (model == ShadingModel::BlinnPhong) v.w = 1.0f;
      break;
    case GBufferPlane::Specular:
      if (model == ShadingModel::MetallicRoughness) v.y = v.z = v.w = 0.0f;
      break;
  }
  return v;
}

const std::vector<std::string>& dumpKernelChannels() {
  static const std::vector<std::string> channels = {
      "P.x",  "P.y",  "P.z",  "N.x",       "N.y",  "N.z",  "kd.R", "kd.G", "kd.B",
      "ks.R", "ks.G", "ks.B", "shininess", "ke.R", "ke.G", "ke.B", "mask"};
  return channels;
}

bool isHostDumpChannel(const std::string& channel) {
  const auto& k = dumpKernelChannels();
  return std::find(k.begin(), k.end(), channel) == k.end();
}

// ---- gbuffer.json -------------------------------------------------------------------------------

namespace {

// Field access with one-line errors "FILE: "key": expected ...".
struct JsonFields {
  const std::string& file;
  const json& object;
  std::string prefix;  // e.g. "light 3 (spot): " or "\"depth\": "

  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    throw Error(file + ": " + prefix + "\"" + shortText(key) + "\" " + what);
  }
  bool has(const std::string& key) const { return object.contains(key); }
  double number(const std::string& key) const {
    if (!has(key)) fail(key, "is missing");
    const json& v = object.at(key);
    if (!v.is_number()) fail(key, "must be a number, got " + shortText(v.dump()));
    const double d = v.get<double>();
    if (!std::isfinite(d)) fail(key, "must be finite");
    // Every number here ends up a float (camera, lights): 1e39 would become inf.
    if (std::abs(d) > double(std::numeric_limits<float>::max()))
      fail(key, "must be within float range, got " + shortText(v.dump()));
    return d;
  }
  double positive(const std::string& key) const {
    const double d = number(key);
    if (!(d > 0.0)) fail(key, "must be > 0, got " + shortText(object.at(key).dump()));
    return d;
  }
  // A whole number in [0, limit].
  int index(const std::string& key, int limit) const {
    const double d = number(key);
    if (!(d >= 0.0 && d <= double(limit) && d == std::floor(d)))
      fail(key, "must be a whole number in [0, " + std::to_string(limit) + "], got " +
                    shortText(object.at(key).dump()));
    return int(d);
  }
  glm::vec3 vec3(const std::string& key) const {
    if (!has(key)) fail(key, "is missing");
    const json& v = object.at(key);
    if (!v.is_array() || v.size() != 3)
      fail(key, "must be an array of 3 numbers, got " + shortText(v.dump()));
    glm::vec3 out;
    for (int i = 0; i < 3; ++i) {
      if (!v[size_t(i)].is_number() || !std::isfinite(v[size_t(i)].get<double>()))
        fail(key, "must be an array of 3 finite numbers, got " + shortText(v.dump()));
      // The kernels read floats: 1e39 would become inf.
      if (std::abs(v[size_t(i)].get<double>()) > double(std::numeric_limits<float>::max()))
        fail(key, "must be an array of 3 numbers within float range, got " + shortText(v.dump()));
      out[i] = v[size_t(i)].get<float>();
    }
    return out;
  }
  // A colour (light colour, ambient): as glTF's KHR_lights_punctual, no negative component.
  glm::vec3 colour(const std::string& key) const {
    const glm::vec3 c = vec3(key);
    if (!(c.x >= 0.0f && c.y >= 0.0f && c.z >= 0.0f))
      fail(key, "must be an array of 3 numbers >= 0, got " + object.at(key).dump());
    return c;
  }
  std::string string(const std::string& key) const {
    if (!has(key)) fail(key, "is missing");
    const json& v = object.at(key);
    if (!v.is_string() || v.get<std::string>().empty()) fail(key, "must be a non-empty string");
    return v.get<std::string>();
  }
  template <typename T>
  T oneOf(const std::string& key, const std::vector<std::pair<std::string, T>>& choices) const {
    const std::string s = string(key);
    std::string names;
    for (const auto& [name, value] : choices) {
      if (name == s) return value;
      names += (names.empty() ? "" : ", ") + name;
    }
    fail(key, "must be one of " + names + ", got \"" + shortText(s) + "\"");
  }
  void onlyKeys(const std::set<std::string>& known) const {
    for (auto it = object.begin(); it != object.end(); ++it)
      if (!known.count(it.key())) {
        std::string names;
        for (const auto& k : known) names += (names.empty() ? "" : ", ") + k;
        fail(it.key(), "is not a known field (known: " + names + ")");
      }
  }
};

std::vector<std::string> channelList(const JsonFields& f, const std::string& key, int count) {
  const json& v = f.object.at(key);
  std::vector<std::string> out;
  if (count == 1 && v.is_string()) {
    out.push_back(v.get<std::string>());
  } else if (count > 1 && v.is_array() && int(v.size()) == count) {
    for (const auto& c : v) {
      if (!c.is_string()) f.fail(key, "must name " + std::to_string(count) + " channels");
      out.push_back(c.get<std::string>());
    }
  } else {
    f.fail(key, count == 1 ? "must name one channel (a string)"
                           : "must name " + std::to_string(count) + " channels (an array)");
  }
  for (const auto& c : out)
    if (c.empty()) f.fail(key, "names an empty channel");
  return out;
}

}  // namespace

GBufferDescriptor readGBufferDescriptor(const std::string& dirOrFile) {
  std::error_code ec;
  const fs::path given(dirOrFile);
  const fs::path path = fs::is_directory(given, ec) ? given / "gbuffer.json" : given;
  if (!fs::exists(path, ec))
    throw Error("--gbuffer-in: " + path.string() +
                " does not exist (a folder written by render "
                "--dump, or a descriptor: docs/output-formats.md)");
  return parseGBufferDescriptor(readTextFile(path.string(), "G-buffer descriptor"), path.string());
}

GBufferDescriptor parseGBufferDescriptor(const std::string& text, const std::string& file) {
  const fs::path path(file);
  GBufferDescriptor d;
  d.path = file;
  const json j = parseStrictJson(text, d.path);
  if (!j.is_object()) throw Error(d.path + " must hold a JSON object");
  const JsonFields top{d.path, j, ""};

  std::set<std::string> known = {"tileshade_gbuffer",
                                 "image",
                                 "lights",
                                 "width",
                                 "height",
                                 "origin",
                                 "camera",
                                 "depth",
                                 "mask",
                                 "normal_encoding",
                                 "shading_model",
                                 "layout",
                                 "scene",
                                 "frame",
                                 "raster",
                                 "shadow_atlas"};
  for (const auto& f : gbufferFields()) known.insert(f.key);
  top.onlyKeys(known);
  if (top.number("tileshade_gbuffer") != kGBufferFilesVersion)
    top.fail("tileshade_gbuffer", "must be " + std::to_string(kGBufferFilesVersion));

  const fs::path folder = path.parent_path();
  d.imagePath = (folder / top.string("image")).string();
  d.lightsPath = (folder / (top.has("lights") ? top.string("lights") : "lights.json")).string();
  auto size = [&](const char* key) -> std::optional<int> {
    if (!top.has(key)) return std::nullopt;
    const double v = top.positive(key);
    if (v != std::floor(v) || v > 65536) top.fail(key, "must be a whole number of pixels");
    return int(v);
  };
  d.width = size("width");
  d.height = size("height");
  if (top.has("origin"))
    d.bottomRowFirst = top.oneOf<bool>("origin", {{"top", false}, {"bottom", true}});
  d.model = top.has("shading_model")
                ? top.oneOf<ShadingModel>("shading_model",
                                          {{"blinn-phong", ShadingModel::BlinnPhong},
                                           {"metallic-roughness", ShadingModel::MetallicRoughness}})
                : ShadingModel::BlinnPhong;
  if (top.has("layout"))
    d.layout = top.oneOf<GBufferFormat>("layout", {{"fp32", GBufferFormat::FP32},
                                                   {"fp16", GBufferFormat::FP16},
                                                   {"packed", GBufferFormat::PACKED}});
  if (top.has("scene")) d.scene = top.string("scene");
  if (top.has("shadow_atlas")) d.shadowAtlasPath = (folder / top.string("shadow_atlas")).string();

  // Camera
  if (!top.has("camera")) top.fail("camera", "is missing (the field of view is needed)");
  const json& cj = j.at("camera");
  if (!cj.is_object()) top.fail("camera", "must be an object");
  const JsonFields cam{d.path, cj, "\"camera\": "};
  cam.onlyKeys({"tan_half_fov", "yfov", "yfov_degrees", "znear", "zfar"});
  const int fovGiven =
      int(cam.has("tan_half_fov")) + int(cam.has("yfov")) + int(cam.has("yfov_degrees"));
  if (fovGiven != 1) cam.fail("yfov", "(or tan_half_fov, or yfov_degrees): give exactly one");
  if (cam.has("tan_half_fov")) {
    const json& t = cj.at("tan_half_fov");
    if (!t.is_array() || t.size() != 2 || !t[0].is_number() || !t[1].is_number() ||
        !(t[0].get<double>() > 0.0) || !(t[1].get<double>() > 0.0) ||
        !std::isfinite(t[0].get<double>()) || !std::isfinite(t[1].get<double>()))
      cam.fail("tan_half_fov", "must be [tan x, tan y], both > 0");
    d.tanHalfFovX = t[0].get<float>();
    d.tanHalfFovY = t[1].get<float>();
  } else {
    const bool degrees = cam.has("yfov_degrees");
    const std::string key = degrees ? "yfov_degrees" : "yfov";
    double yfov = cam.positive(key);
    if (degrees) yfov *= kPiDouble / 180.0;
    if (!(double(float(yfov)) < 2.0 * kHalfPi))  // as the float the camera keeps
      cam.fail(key, "must be below 180 degrees (pi = " + fullText(2.0 * kHalfPi) +
                        ") as a float, "
                        "got " +
                        fullText(cam.number(key)));
    d.tanHalfFovY = std::tan(0.5f * float(yfov));  // as CameraIntrinsics::from
  }
  // The kernels divide by these floats: one that rounds to 0 (1e-46) or inf would break them.
  auto usableFloat = [](const JsonFields& f, const std::string& key, float v) {
    if (!(v >= std::numeric_limits<float>::min() && std::isfinite(v)))
      f.fail(key,
             "must be a float from 1.17549435e-38 (the smallest normal) to 3.40282347e+38, "
             "got " +
                 shortText(f.object.at(key).dump()));
    return v;
  };
  if (d.tanHalfFovX) usableFloat(cam, "tan_half_fov", *d.tanHalfFovX);
  usableFloat(cam,
              cam.has("tan_half_fov") ? "tan_half_fov"
              : cam.has("yfov")       ? "yfov"
                                      : "yfov_degrees",
              d.tanHalfFovY);
  if (cam.has("znear")) d.znear = usableFloat(cam, "znear", float(cam.positive("znear")));
  if (cam.has("zfar")) d.zfar = usableFloat(cam, "zfar", float(cam.positive("zfar")));
  if (d.znear && d.zfar && !(*d.zfar > *d.znear)) cam.fail("zfar", "must be greater than znear");

  // Depth
  if (!top.has("depth")) top.fail("depth", "is missing");
  const json& dj = j.at("depth");
  if (!dj.is_object()) top.fail("depth", "must be an object {\"channel\", \"encoding\", ...}");
  const JsonFields depth{d.path, dj, "\"depth\": "};
  depth.onlyKeys({"channel", "encoding", "near", "far", "range", "reversed"});
  d.depthChannel = depth.string("channel");
  d.depthEncoding = depth.oneOf<DepthEncoding>("encoding", {{"linear", DepthEncoding::Linear},
                                                            {"view_z", DepthEncoding::ViewZ},
                                                            {"hardware", DepthEncoding::Hardware}});
  if (d.depthEncoding == DepthEncoding::Hardware) {
    d.hardwareNear = depth.positive("near");
    usableFloat(depth, "near", float(d.hardwareNear));
    d.hardwareRange = depth.oneOf<DepthRange>(
        "range",
        {{"zero_to_one", DepthRange::ZeroToOne}, {"minus_one_to_one", DepthRange::MinusOneToOne}});
    if (depth.has("reversed")) {
      if (!dj.at("reversed").is_boolean()) depth.fail("reversed", "must be true or false");
      d.hardwareReversed = dj.at("reversed").get<bool>();
    }
    if (d.hardwareReversed && d.hardwareRange != DepthRange::ZeroToOne)
      depth.fail("reversed", "needs \"range\": \"zero_to_one\"");
    if (depth.has("far") && !dj.at("far").is_null()) {
      d.hardwareFar = depth.positive("far");
      if (!(*d.hardwareFar > d.hardwareNear)) depth.fail("far", "must be greater than near");
    } else if (!d.hardwareReversed) {
      depth.fail("far", "is missing (null, an infinite far plane, needs \"reversed\": true)");
    }
    if (!d.znear) d.znear = float(d.hardwareNear);
    if (!d.zfar && d.hardwareFar) d.zfar = float(*d.hardwareFar);
  } else {
    for (const char* k : {"near", "far", "range", "reversed"})
      if (depth.has(k)) depth.fail(k, "applies to \"encoding\": \"hardware\" only");
  }
  if (top.has("mask")) d.maskChannel = top.string("mask");
  if (top.has("normal_encoding"))
    d.normalUnorm = top.oneOf<bool>("normal_encoding", {{"signed", false}, {"unorm", true}});

  // Fields of the model
  for (const auto& f : gbufferFields()) {
    const bool applies = f.models & kModelBit(d.model);
    if (!top.has(f.key)) {
      if (applies && f.required)
        top.fail(f.key, std::string("is missing (") + f.meaning + ", needed for " +
                            toString(d.model) + ")");
      continue;
    }
    if (!applies)
      top.fail(f.key, "does not apply to \"shading_model\": \"" + toString(d.model) + "\"");
    d.fields.emplace_back(&f, channelList(top, f.key, f.components));
  }
  return d;
}

// ---- lights.json --------------------------------------------------------------------------------

namespace {

// One light as lights.json holds it: the kernels' view-space values (ViewLights).
struct LightRecord {
  SceneLightType type = SceneLightType::Point;
  glm::vec3 position{0.0f}, color{0.0f}, direction{0.0f};  // direction: where the light travels
  float range = 0.0f;
  float cosOuter = -1.0f;  // spot: ViewLights::spot.w
  float coneScale = 1.0f;  // spot: ViewLights::color.w
  int shadowFace = -1;     // its first face in shadow_atlas.json; -1: casts no shadow
};

// More faces than the largest atlas holds at 16x16 texels (16384^2 / 16^2) is no real file.
constexpr int kMaxShadowFaces = 1 << 20;

constexpr int kPoint = 1 << int(SceneLightType::Point), kSpot = 1 << int(SceneLightType::Spot),
              kDirectional = 1 << int(SceneLightType::Directional);

// The light fields: which types have them, how they are written and read.
struct LightField {
  const char* key;
  int types;
  std::function<json(const LightRecord&)> write;
  std::function<void(LightRecord&, const JsonFields&)> read;  // null: read elsewhere
};

json array3(glm::vec3 v) { return {v.x, v.y, v.z}; }

const std::vector<LightField>& lightFields() {
  static const std::vector<LightField> fields = {
      {"position", kPoint | kSpot, [](const LightRecord& l) { return array3(l.position); },
       [](LightRecord& l, const JsonFields& f) { l.position = f.vec3("position"); }},
      {"color", kPoint | kSpot | kDirectional, [](const LightRecord& l) { return array3(l.color); },
       [](LightRecord& l, const JsonFields& f) { l.color = f.colour("color"); }},
      {"range", kPoint | kSpot, [](const LightRecord& l) { return json(l.range); },
       [](LightRecord& l, const JsonFields& f) { l.range = float(f.positive("range")); }},
      {"direction", kSpot | kDirectional, [](const LightRecord& l) { return array3(l.direction); },
       [](LightRecord& l, const JsonFields& f) {
         l.direction = f.vec3("direction");
         const double len = glm::length(glm::dvec3(l.direction));
         if (std::abs(len - 1.0) > 1e-5)
           f.fail("direction", "must be a unit vector, its length is " + fullText(len));
       }},
      // Spot cone: the kernels' values, or glTF's angles (read below).
      {"cos_outer", kSpot, [](const LightRecord& l) { return json(l.cosOuter); }, nullptr},
      {"cone_scale", kSpot, [](const LightRecord& l) { return json(l.coneScale); }, nullptr},
  };
  return fields;
}

// A spot light's cone from "cos_outer" + "cone_scale" (what dumps write) or from glTF's
// "inner_cone_angle" + "outer_cone_angle" (radians), converted by toViewSpace itself.
void readCone(LightRecord& l, const JsonFields& f) {
  const bool kernelForm = f.has("cos_outer") || f.has("cone_scale");
  const bool angleForm = f.has("inner_cone_angle") || f.has("outer_cone_angle");
  if (kernelForm == angleForm)
    f.fail("outer_cone_angle",
           "(with inner_cone_angle), or cos_outer with cone_scale: give one "
           "pair");
  if (kernelForm) {
    // A cos of a float pi/2 cone (-4.4e-8) is a cos of 0 (util/float_limit.h); 1 is a cone
    // narrower than a float's cos resolves (under 3.5e-4 radians), lighting nothing.
    const double cosOuter = f.number("cos_outer");
    l.coneScale = float(f.positive("cone_scale"));
    if (!withinFloatRounding(cosOuter, 0.0, 1.0, /*scale=*/1.0))
      f.fail("cos_outer", "must be in [0, 1], got " + fullText(cosOuter));
    l.cosOuter = float(std::clamp(cosOuter, 0.0, 1.0));
    return;
  }
  double inner = f.number("inner_cone_angle"), outer = f.number("outer_cone_angle");
  if (!(withinFloatRounding(inner, 0.0, kHalfPi) && withinFloatRounding(outer, 0.0, kHalfPi) &&
        inner < outer))
    f.fail("outer_cone_angle", "must satisfy 0 <= inner_cone_angle < outer_cone_angle <= pi/2 (" +
                                   fullText(kHalfPi) + "), got inner " + fullText(inner) +
                                   ", outer " + fullText(outer));
  inner = std::clamp(inner, 0.0, kHalfPi);
  outer = std::clamp(outer, 0.0, kHalfPi);
  const ViewLights v = toViewSpace(
      {SceneLight::spot(l.position, l.direction, l.color, l.range, float(inner), float(outer))},
      glm::mat4(1.0f));
  l.cosOuter = v.spot[0].w;
  l.coneScale = v.color[0].w;
}

}  // namespace

nlohmann::json lightsJson(const ViewLights& lights, glm::vec3 ambient) {
  std::vector<LightRecord> records;
  for (size_t i = 0; i < lights.size(); ++i) {
    LightRecord l;
    const glm::vec4 s = lights.spot[i];
    l.type = lights.isSpot(i) ? SceneLightType::Spot : SceneLightType::Point;
    l.position = glm::vec3(lights.positionRange[i]);
    l.range = lights.positionRange[i].w;
    l.color = glm::vec3(lights.color[i]);
    l.direction = glm::vec3(s);
    l.cosOuter = s.w;
    l.coneScale = lights.color[i].w;
    l.shadowFace = lights.shadowOf(i);
    records.push_back(l);
  }
  for (size_t i = 0; i < lights.directionalCount(); ++i) {
    LightRecord l;
    l.type = SceneLightType::Directional;
    l.direction = -glm::vec3(lights.directionalDir[i]);  // exact: ViewLights holds "towards"
    l.color = glm::vec3(lights.directionalColor[i]);
    l.shadowFace = lights.directionalShadowOf(i);
    records.push_back(l);
  }
  json list = json::array();
  for (const auto& l : records) {
    json o = {{"type", toString(l.type)}};
    for (const auto& f : lightFields())
      if (f.types & (1 << int(l.type))) o[f.key] = f.write(l);
    if (l.shadowFace >= 0) o["shadow_face"] = l.shadowFace;
    list.push_back(o);
  }
  return {{"dmin", TS_DMIN}, {"ambient", array3(ambient)}, {"lights", list}};
}

LightsFile readLightsFile(const std::string& path) {
  return parseLightsFile(readTextFile(path, "lights file"), path);
}

LightsFile parseLightsFile(const std::string& text, const std::string& path) {
  const json j = parseStrictJson(text, path);
  if (!j.is_object()) throw Error(path + " must hold a JSON object");
  const JsonFields top{path, j, ""};
  top.onlyKeys({"dmin", "ambient", "lights"});
  // The kernels' dmin is a float of TS_DMIN: either reads as it.
  if (top.has("dmin") && !withinFloatRounding(top.number("dmin"), TS_DMIN, TS_DMIN))
    top.fail("dmin",
             "is " + fullText(top.number("dmin")) + " but the kernels use " + fullText(TS_DMIN));
  LightsFile out;
  if (top.has("ambient")) out.ambient = top.colour("ambient");
  if (!top.has("lights") || !j.at("lights").is_array()) top.fail("lights", "must be an array");
  size_t index = 0;
  for (const json& lj : j.at("lights")) {
    const std::string where = "light " + std::to_string(index++);
    if (!lj.is_object()) throw Error(path + ": " + where + " must be an object");
    const JsonFields type{path, lj, where + ": "};
    LightRecord l;
    l.type = type.oneOf<SceneLightType>("type", {{"point", SceneLightType::Point},
                                                 {"spot", SceneLightType::Spot},
                                                 {"directional", SceneLightType::Directional}});
    const JsonFields f{path, lj, where + " (" + toString(l.type) + "): "};
    std::set<std::string> known = {"type", "shadow_face"};
    if (f.has("shadow_face")) l.shadowFace = f.index("shadow_face", kMaxShadowFaces - 1);
    for (const auto& field : lightFields()) {
      if (!(field.types & (1 << int(l.type)))) continue;
      known.insert(field.key);
      if (field.read) field.read(l, f);
    }
    if (l.type == SceneLightType::Spot) {
      known.insert({"inner_cone_angle", "outer_cone_angle"});
      readCone(l, f);
    }
    f.onlyKeys(known);
    if (l.type == SceneLightType::Directional) {
      out.lights.directionalDir.emplace_back(-l.direction, 0.0f);
      out.lights.directionalColor.emplace_back(l.color, 0.0f);
      out.lights.directionalShadow.push_back(l.shadowFace);  // faces: shadow_atlas.json
      continue;
    }
    out.lights.positionRange.emplace_back(l.position, l.range);
    out.lights.shadow.push_back(l.shadowFace);
    if (l.type == SceneLightType::Spot) {
      out.lights.color.emplace_back(l.color, l.coneScale);
      out.lights.spot.emplace_back(l.direction, l.cosOuter);
    } else {
      out.lights.color.emplace_back(l.color, 1.0f);
      out.lights.spot.emplace_back(glm::vec3(0.0f), -1.0f);
    }
  }
  return out;
}

namespace {

json row4(glm::vec4 r) { return {r.x, r.y, r.z, r.w}; }

// A row of 4 finite numbers within float range (a face's clip or depth row).
glm::vec4 readRow(const JsonFields& f, const std::string& key) {
  if (!f.has(key)) f.fail(key, "is missing");
  const json& v = f.object.at(key);
  if (!v.is_array() || v.size() != 4)
    f.fail(key, "must be an array of 4 numbers, got " + shortText(v.dump()));
  glm::vec4 out;
  for (int i = 0; i < 4; ++i) {
    const json& c = v[size_t(i)];
    if (!c.is_number() || !std::isfinite(c.get<double>()) ||
        std::abs(c.get<double>()) > double(std::numeric_limits<float>::max()))
      f.fail(key,
             "must be an array of 4 finite numbers within float range, got " + shortText(v.dump()));
    out[i] = c.get<float>();
  }
  return out;
}

}  // namespace

json shadowAtlasJson(const ViewLights& lights, const std::string& filter, const json& world) {
  constexpr size_t R = TS_SHADOW_FACE_RECORDS;
  const std::vector<glm::vec4>& r = lights.shadowFaces;
  const size_t faces = r.size() / R;
  if (r.size() != faces * R || faces == 0 || !lights.shadowAtlas || lights.shadowAtlasWidth <= 0)
    throw Error("shadow atlas dump: the lights hold no complete face table");
  json list = json::array();
  for (size_t f = 0; f < faces; ++f) {
    const glm::vec4* q = &r[f * R];
    json o = world.is_array() && f < world.size() ? world[f] : json::object();
    o["x"] = int(q[4].x);
    o["y"] = int(q[4].y);
    o["size"] = int(q[4].z);
    o["clip_from_view"] = {row4(q[0]), row4(q[1]), row4(q[2])};
    o["depth_from_view"] = row4(q[3]);
    o["texel_footprint"] = {q[5].x, q[5].y};
    list.push_back(o);
  }
  const int width = lights.shadowAtlasWidth;
  const int height = int(lights.shadowAtlas->size() / size_t(width));
  json out = {{"image", "shadow_atlas.exr"},
              {"width", width},
              {"height", height},
              {"origin", "top"},
              {"depth", "linear -Z of the face's view space; zfar where empty"},
              {"space", "view"},
              {"filter", filter},
              {"bias", {r[5].z, r[5].w}},
              {"faces", list}};
  if (r[6].z != 0.0f) out["receiver_plane"] = true;  // written only when on: older dumps stay
  return out;
}

ShadowAtlasFile parseShadowAtlasFile(const std::string& text, const std::string& file) {
  const json j = parseStrictJson(text, file);
  if (!j.is_object()) throw Error(file + " must hold a JSON object");
  const JsonFields top{file, j, ""};
  top.onlyKeys({"image", "width", "height", "origin", "depth", "space", "filter", "bias",
                "receiver_plane", "faces"});
  ShadowAtlasFile out;
  out.path = file;
  out.imagePath = (fs::path(file).parent_path() / top.string("image")).string();
  constexpr int kMaxSide = 16384;  // kShadowMaxAtlasSide (raster/shadow_atlas.h)
  out.width = top.index("width", kMaxSide);
  out.height = top.index("height", kMaxSide);
  if (out.width == 0 || out.height == 0) top.fail("width", "and \"height\" must be > 0");
  // Only what render --dump writes: rows top first, the faces in the view space of lights.json.
  if (top.has("origin")) static_cast<void>(top.oneOf<bool>("origin", {{"top", true}}));
  if (top.has("space")) static_cast<void>(top.oneOf<bool>("space", {{"view", true}}));
  if (top.has("filter")) out.filter = top.string("filter");
  if (top.has("bias")) {
    const json& b = j.at("bias");
    if (!b.is_array() || b.size() != 2 || !b[0].is_number() || !b[1].is_number() ||
        !(b[0].get<double>() >= 0.0 && b[0].get<double>() <= 1e6) ||
        !(b[1].get<double>() >= 0.0 && b[1].get<double>() <= 1e6))
      top.fail("bias", "must be [constant, slope], two numbers in [0, 1e6]");
    out.biasConstant = b[0].get<float>();
    out.biasSlope = b[1].get<float>();
  }
  if (top.has("receiver_plane")) {
    if (!j.at("receiver_plane").is_boolean()) top.fail("receiver_plane", "must be true or false");
    out.receiverPlane = j.at("receiver_plane").get<bool>();
  }
  if (!top.has("faces") || !j.at("faces").is_array() || j.at("faces").empty())
    top.fail("faces", "must be a non-empty array");
  if (j.at("faces").size() > size_t(kMaxShadowFaces))
    top.fail("faces", "holds more than " + std::to_string(kMaxShadowFaces) + " faces");
  size_t index = 0;
  for (const json& fj : j.at("faces")) {
    const std::string where = "face " + std::to_string(index++) + ": ";
    if (!fj.is_object()) throw Error(file + ": " + where + "must be an object");
    const JsonFields f{file, fj, where};
    // Keys the scene's own dump adds (the world side) are informative here.
    f.onlyKeys({"x", "y", "size", "clip_from_view", "depth_from_view", "texel_footprint", "light",
                "face", "orthographic", "znear", "zfar", "map_from_world"});
    ShadowAtlasFaceRecord r;
    r.x = f.index("x", out.width - 1);
    r.y = f.index("y", out.height - 1);
    r.size = f.index("size", kMaxSide);
    if (r.size == 0 || r.x + r.size > out.width || r.y + r.size > out.height)
      f.fail("size", "puts the face (" + std::to_string(r.x) + ", " + std::to_string(r.y) + ", " +
                         std::to_string(r.size) + ") outside the " + std::to_string(out.width) +
                         "x" + std::to_string(out.height) + " atlas");
    if (!f.has("clip_from_view") || !fj.at("clip_from_view").is_array() ||
        fj.at("clip_from_view").size() != 3)
      f.fail("clip_from_view", "must hold the 3 rows x, y, w of the face's clip matrix");
    const json& clip = fj.at("clip_from_view");
    const json clipRows = {{"x", clip[0]}, {"y", clip[1]}, {"w", clip[2]}};
    const JsonFields rows{file, clipRows, where + "\"clip_from_view\" row "};
    r.clipX = readRow(rows, "x");
    r.clipY = readRow(rows, "y");
    r.clipW = readRow(rows, "w");
    r.depth = readRow(f, "depth_from_view");
    const json& fp = fj.contains("texel_footprint") ? fj.at("texel_footprint") : json();
    if (!fp.is_array() || fp.size() != 2 || !fp[0].is_number() || !fp[1].is_number() ||
        !(fp[0].get<double>() >= 0.0 && fp[0].get<double>() <= 1e30) ||
        !(fp[1].get<double>() >= 0.0 && fp[1].get<double>() <= 1e30))
      f.fail("texel_footprint",
             "must be [a, b], two numbers in [0, 1e30] (a texel's size at "
             "depth d: a + b d)");
    r.footprint = glm::vec2(fp[0].get<float>(), fp[1].get<float>());
    out.faces.push_back(r);
  }
  return out;
}

}  // namespace ts
