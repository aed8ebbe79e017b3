#pragma once
// Entry points that turn a --scene spec into a Scene: "builtin:NAME" or a .gltf/.glb path.
#include <string>
#include <vector>

#include "scene/scene.h"
#include "util/enum_names.h"

namespace ts {

// What becomes of alphaMode BLEND materials (`--blend`):
//  refuse     the default: kept, and both rasterizers refuse a scene that draws one, naming the
//             materials (validateForRaster), so a transparent surface is never silently opaque
//  as-opaque  drawn opaque (their alpha ignored)
//  as-mask    drawn as alphaMode MASK with their alphaCutoff
//  blend      kept and composited (Scene::blendComposited): the forward techniques draw them
//             back to front over the opaque scene; the G-buffer holds the opaque surfaces only,
//             so the G-buffer techniques refuse such a frame (docs/techniques.md, "Transparency")
enum class BlendPolicy { Refuse = 0, AsOpaque = 1, AsMask = 2, Blend = 3 };
const EnumNames<BlendPolicy>& blendPolicyNames();
std::string toString(BlendPolicy policy);
// The policy applied to the scene's BLEND materials (refuse: left as they are).
void applyBlendPolicy(Scene& scene, BlendPolicy policy);

struct SceneOptions {
  std::string lightSet;     // "" = the scene's default (built-ins) or the file's own lights (glTF)
  uint32_t seed = 1;        // built-in scenes are deterministic for a seed
  int lightCount = -1;      // -1 = the light set's own count; else exactly N lights
  float lightRange = 0.0f;  // > 0 overrides every light's range
  // Built-in scenes only: a comma list of variants (applyVariants), "" = the scene as designed.
  std::string variant;
  // false (`--normal-maps off`): the materials' normal maps and the tangents are dropped, so the
  // scene renders with its interpolated normals, as before tileshade read normal maps.
  bool normalMaps = true;
  // Which lights cast shadows (chooseShadowCasters, scene/shadow_casters.h): "" keeps the
  // scene's own marks. Their maps are drawn (raster/shadow_maps.h) and shaded with.
  std::string shadows;
  BlendPolicy blend = BlendPolicy::Refuse;  // --blend
};

// The built-in scenes' variants, for measuring what a scene's needs cost (scenes/README.md):
//   diffuse             no specular and no emission in any material (Lambert only)
//   no-emission         no emission
//   metallic-roughness  materials written for glTF's model (from their Blinn-Phong terms)
//   spot                every second light is a spot light pointing down
//   sun                 one directional light (a sun) added
//   glass               glass panes and volumes (alphaMode BLEND) where frame 0 looks
std::vector<std::string> builtinVariants();
// Applies a comma list of variants to a built-in scene; throws ts::Error for an unknown one.
void applyVariants(Scene& scene, const std::string& variants, uint32_t seed);

Scene loadScene(const std::string& spec, const SceneOptions& options);

// The thesis's four scenarios (issue #18) as light sets for any scene, placed from its geometry's
// bounds: thesis-small (128 point lights of range 1.2..5 % of the bounds' diagonal), thesis-big
// (16 of 20..50 %), thesis-big-shadows (big, every light casting a shadow) and thesis-mixed
// (128: every 32nd light big and casting, the others small); the atrium's small/big ranges in
// proportion to its size. Positions uniform inside the bounds shrunk by 5 % a side (a light may
// land inside geometry: these scenes have no free-space map); colour k * range^2, as the
// atrium's. Deterministic for a seed; count -1 = the set's own. glTF scenes take them as
// --lights instead of their own lights.
std::vector<std::string> thesisLightSets();
std::vector<SceneLight> placeThesisLights(const Bounds& bounds, const std::string& set,
                                          uint32_t seed, int count);

// Built-in scenes (src/scene/builtin_*.cpp).
std::vector<std::string> builtinSceneNames();
std::vector<std::string> builtinLightSets(const std::string& scene);  // first = default
Scene makeBuiltinScene(const std::string& name, const std::string& lightSet, uint32_t seed);

// glTF 2.0 (src/scene/gltf_*.cpp). Warnings (skipped primitives, textures that could not be
// decoded, clamped values, ...) go to `warnings` when given, else to stderr as
// "tileshade: warning: ..." lines, and only once the file has loaded: an error is the only line
// about a file that fails. Throws ts::Error (one line, with the path) for an invalid file.
Scene loadGltf(const std::string& path, std::vector<std::string>* warnings = nullptr);
// The same from the bytes of a .gltf or .glb file (the "glTF" magic decides); external URIs are
// resolved against baseDir, `name` stands for the file in messages. For fuzzing and tests.
Scene loadGltfFromMemory(const unsigned char* bytes, size_t size, const std::string& baseDir,
                         const std::string& name, std::vector<std::string>* warnings = nullptr);
// Writes a .gltf (buffers embedded as data URIs) or .glb, by the extension; throws ts::Error for
// another extension or a failed write.
void exportGltf(const Scene& scene, const std::string& path);
// Throws ts::Error unless the path ends in .gltf or .glb (any case).
void checkExportPath(const std::string& path);

// "tileshade: warning: NAME: LINE" on stderr for each line.
void printSceneWarnings(const std::string& name, const std::vector<std::string>& warnings);

}  // namespace ts
