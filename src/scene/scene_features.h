#pragma once
// What a scene needs from the pipeline: its shading model, the material terms it uses and its
// light types. The kernels are built with only these (build options, kernelDefines) and the
// G-buffer holds only the planes they read (src/gbuffer/gbuffer_layout.h), so a diffuse-only scene
// lit by point lights compiles and stores none of the rest. docs/features.md has the table.
#include <string>

#include "scene/scene.h"

namespace ts {

struct SceneFeatures {
  ShadingModel model = ShadingModel::BlinnPhong;  // kernels/shading.h TS_SHADING
  bool specular = true;      // a specular term (Blinn-Phong ks > 0; metallic-roughness: always)
  bool emissive = true;      // an emission term ke > 0 (the G-buffer's emissive plane)
  bool textures = false;     // textures sampled by the rasterizer (no kernel branches on it)
  bool point = true;         // point lights
  bool spot = false;         // spot lights: cone falloff in the shading, cone culling
  bool directional = false;  // directional lights: applied to every pixel, never culled
  bool normalMaps = false;   // "normal_maps": some material's normal map is applied by the
                             // rasterizers (no kernel branches on it; without, the G-buffer
                             // passes do no tangent work)
  bool shadows = false;      // some light casts a shadow: the kernels sample its shadow map
                             // (TS_HAS_SHADOWS, kernels/shadows.h); on only with such a light,
                             // also in `general` (it needs the maps, not just a branch)

  // Everything on but shadows, for `model`: the general pipeline of comparisons.
  static SceneFeatures general(ShadingModel model);

  // "metallic-roughness specular emissive textures point spot directional normal_maps" (the terms
  // that are on).
  std::string describe() const;
  // OpenCL build options: -DTS_SHADING=… -DTS_HAS_SPECULAR=… -DTS_HAS_EMISSIVE=…
  // -DTS_HAS_SPOT=… -DTS_HAS_DIRECTIONAL=… [-DTS_HAS_SHADOWS]
  std::string kernelDefines() const;
  // Whether every term `need` has is on here (a pipeline with these features renders that scene
  // exactly).
  bool covers(const SceneFeatures& need) const;
  bool operator==(const SceneFeatures& o) const;
  bool operator!=(const SceneFeatures& o) const { return !(*this == o); }
};

// The model the scene's materials were written for: metallic-roughness when any material that a
// triangle uses was (glTF), else Blinn-Phong (the built-ins).
ShadingModel nativeShadingModel(const Scene& scene);

// The features of `scene` shaded with `model`: only the materials that triangles use count, and
// a term counts when some material has it non-zero (a material with zero specular everywhere
// needs no specular term).
SceneFeatures analyzeScene(const Scene& scene, ShadingModel model);

// The user's choice against the analysis `need`:
//   "auto"       need itself
//   "general"    everything on (SceneFeatures::general(need.model)), shadows as need has them
//   "a,b,…"      exactly these of specular, emissive, textures, point, spot, directional,
//                normal_maps, shadows (the model stays need.model)
// Throws ts::Error for an unknown name, or for a list that leaves out a term the scene needs
// (it would render it wrong), naming what is missing.
SceneFeatures chooseFeatures(const std::string& spec, const SceneFeatures& need);

}  // namespace ts
