#pragma once
// The G-buffer interchange files, in one place: what `render --dump` writes and `--gbuffer-in`
// reads (docs/output-formats.md, "G-buffer files").
//   gbuffer.json  the descriptor: image and lights file names, camera, which EXR channel holds
//                 which G-buffer field and how depth is encoded, shading model, layout
//   gbuffer.exr   the per-pixel channels the descriptor names
//   lights.json   the lights in view space, in the kernels' layout (ViewLights); a
//                 shadow-casting light names its first shadow-map face ("shadow_face")
//   shadow_atlas.json, shadow_atlas.exr  with shadow-casting lights: the faces in view space
//                 (the kernels' face table, kernels/shadows.h) and the atlas's depths
// The tables below drive both the writer (src/render/gbuffer_dump.cpp) and the reader
// (src/gbuffer/gbuffer_import.cpp): a new G-buffer field or light field is one row here.
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "gbuffer/gbuffer_layout.h"
#include "scene/scene.h"
#include "shading/view_lights.h"

namespace ts {

constexpr int kGBufferFilesVersion = 1;  // "tileshade_gbuffer" in gbuffer.json

// A material/normal field of the descriptor: which channels fill which G-buffer components.
struct GBufferField {
  const char* key;     // descriptor key, e.g. "normal"
  int components;      // channels it names: 1 (a string) or 3 (an array)
  GBufferPlane plane;  // where the values go ...
  int first;           // ... from this component on
  int models;          // bit mask of ShadingModel values it applies to
  bool required;       // false: `fallback` fills it when the descriptor leaves it out
  float fallback;
  const char* dumpChannels[3];  // what `render --dump` writes for it (see dumpKernelChannels)
  const char* meaning;          // one line, for docs and messages
};
constexpr int kModelBit(ShadingModel m) { return 1 << int(m); }
constexpr int kAnyModel = 3;

// Every field, in descriptor order.
const std::vector<GBufferField>& gbufferFields();
// The fields that apply to `model`.
std::vector<const GBufferField*> gbufferFields(ShadingModel model);
// Components no field sets, per model: their fixed values (BP diffuse.w = 1; MR specular yzw = 0;
// normal.w and emissive.w = 0), exactly what both rasterizers write.
glm::vec4 fixedComponents(GBufferPlane plane, ShadingModel model, glm::vec4 values);

// The channels of the dump kernel's output (kernels/dump.cl, decode_gbuffer), in its order.
const std::vector<std::string>& dumpKernelChannels();
// Whether `render --dump` writes a dump channel from the host (decodeStored: values before the
// kernels' renormalisation, which the kernel output lacks) rather than from dump.cl.
bool isHostDumpChannel(const std::string& channel);

// How a depth channel encodes depth.
enum class DepthEncoding {
  Linear,    // linear view depth -z_view (> 0 in front of the camera)
  ViewZ,     // view-space z (< 0 in front of the camera), e.g. a position's z
  Hardware,  // a depth buffer's window depth d in [0, 1] with the projection's near and far
};
enum class DepthRange { ZeroToOne, MinusOneToOne };  // NDC z of the hardware depth's projection

// gbuffer.json, parsed and checked (file names resolved against its folder).
struct GBufferDescriptor {
  std::string path;  // of gbuffer.json itself (for messages)
  std::string imagePath, lightsPath;
  std::optional<int> width, height;  // checked against the image when given
  bool bottomRowFirst = false;       // "origin": "bottom" (row 0 of the image is the bottom)
  // Camera: the tangents of half the field of view (x from y and the aspect when only y is known).
  std::optional<float> tanHalfFovX;
  float tanHalfFovY = 0.0f;
  std::optional<float> znear, zfar;
  // Depth
  std::string depthChannel;
  DepthEncoding depthEncoding = DepthEncoding::Linear;
  double hardwareNear = 0.0;
  std::optional<double> hardwareFar;  // none = infinite far (reversed only)
  DepthRange hardwareRange = DepthRange::ZeroToOne;
  bool hardwareReversed = false;
  std::string maskChannel;   // "" = geometry where depth says so
  bool normalUnorm = false;  // "normal_encoding": "unorm" (n = 2c - 1)
  // Fields: channels per key of gbufferFields(model) that the descriptor names.
  std::vector<std::pair<const GBufferField*, std::vector<std::string>>> fields;
  ShadingModel model = ShadingModel::BlinnPhong;
  std::optional<GBufferFormat> layout;  // the layout it was dumped from (tileshade dumps)
  std::string scene;                    // informative
  std::string shadowAtlasPath;          // "shadow_atlas": shadow_atlas.json ("" = none)
};

// Reads DIR/gbuffer.json (or the .json path given). Throws ts::Error naming the file and the
// field for anything missing, unknown or out of range.
GBufferDescriptor readGBufferDescriptor(const std::string& dirOrFile);
// The same from the descriptor's text (`path` for messages and to resolve its file names).
GBufferDescriptor parseGBufferDescriptor(const std::string& text, const std::string& path);

// lights.json <-> the kernels' view-space lights. The light fields, one table (see the .cpp).
struct LightsFile {
  ViewLights lights;
  glm::vec3 ambient{0.0f};
};
nlohmann::json lightsJson(const ViewLights& lights, glm::vec3 ambient);
// Throws ts::Error naming the file, the light (index and type) and the field.
LightsFile readLightsFile(const std::string& path);
LightsFile parseLightsFile(const std::string& text, const std::string& path);

// shadow_atlas.json: the shadow maps of the lights of lights.json, in view space. Per face the
// records of kernels/shadows.h that a file can give (clip rows, depth row, atlas rectangle, texel
// footprint); the filter and bias for all. ViewLights' face records are built from it once the
// lights say which faces each starts at (gbuffer_import.cpp).
struct ShadowAtlasFaceRecord {
  glm::vec4 clipX{0.0f}, clipY{0.0f}, clipW{0.0f}, depth{0.0f};  // rows of view space
  int x = 0, y = 0, size = 0;                                    // texels; row 0 the top
  glm::vec2 footprint{0.0f};  // a texel's world size at linear depth d: x + y d
};
struct ShadowAtlasFile {
  std::string path, imagePath;
  int width = 0, height = 0;
  std::string filter = "none";  // --shadow-filter's name (raster/shadow_maps.h parses it)
  float biasConstant = 1.5f, biasSlope = 1.5f;
  bool receiverPlane = false;  // "receiver_plane": --shadow-bias receiver,C
  std::vector<ShadowAtlasFaceRecord> faces;
};
// The view-space description of `lights`' shadow faces (lights.hasShadows()), the image named
// shadow_atlas.exr; `world`: an array of extra per-face fields of the scene's atlas (objects: the
// light's scene index, the world matrix, ...), merged into each face if given.
nlohmann::json shadowAtlasJson(const ViewLights& lights, const std::string& filter,
                               const nlohmann::json& world = nullptr);
// Throws ts::Error naming the file, the face and the field (a rectangle outside the atlas, an
// unknown filter, a non-finite row, ...).
ShadowAtlasFile parseShadowAtlasFile(const std::string& text, const std::string& path);

}  // namespace ts
