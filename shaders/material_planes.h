/*
 * The G-buffer's material planes of a surface point: ONE definition for both rasterizers.
 *
 * Compiled as C++ by the software rasterizer (src/raster/rasterizer.cpp, resolve()) and as GLSL
 * by the OpenGL rasterizer (src/raster/gl_rasterizer.cpp prepends this file to
 * shaders/gbuffer.frag), so the two agree on which material term goes to which plane and how the
 * textures multiply them (the planes per model: the comment on GBuffer in src/gbuffer/gbuffer.h).
 * Written in the common subset: glm in C++ has GLSL's vec3/vec4 and constructors.
 *
 * The includer defines TS_SAMPLE(slot): the linear RGBA sample of the material's texture in
 * `slot` (TS_TEXTURE_*) at the pixel's UV, or vec4(1) when the material has none. Each is
 * evaluated only where the model reads it (the software path samples lazily).
 *   C++:  a callable `ts_sampler(slot)` passed as the last argument (a template parameter);
 *   GLSL: texture units and presence flags (uniforms), see shaders/gbuffer.frag.
 * TsMaterial has the fields of ts::Material used here (C++: ts::Material itself).
 *
 * ts_material_covered is the one alpha test (glTF alphaMode MASK) of both rasterizers: the
 * software one leaves a fragment it fails out of the visibility pass, the fragment shaders
 * discard it, so both draw what lies behind.
 */
#ifndef TS_MATERIAL_PLANES_H
#define TS_MATERIAL_PLANES_H

#define TS_TEXTURE_DIFFUSE 0            /* Blinn-Phong kd */
#define TS_TEXTURE_BASE_COLOR 1         /* metallic-roughness base colour */
#define TS_TEXTURE_METALLIC_ROUGHNESS 2 /* glTF: G = roughness, B = metallic */
#define TS_TEXTURE_EMISSIVE 3
#define TS_TEXTURE_SLOTS 4

#ifdef __cplusplus
#include <glm/glm.hpp>
#include "scene/scene.h"
namespace ts {
using TsMaterial = Material;
struct TsMaterialPlanes {
  glm::vec4 diffuse, specular, emissive;
};
// The texture index of a slot in a material (-1 = none).
inline int materialTexture(const Material& m, int slot) {
  switch (slot) {
    case TS_TEXTURE_DIFFUSE: return m.diffuseTexture;
    case TS_TEXTURE_BASE_COLOR: return m.baseColorTexture;
    case TS_TEXTURE_METALLIC_ROUGHNESS: return m.metallicRoughnessTexture;
    case TS_TEXTURE_EMISSIVE: return m.emissiveTexture;
  }
  return -1;
}
namespace material_planes_glsl {
using glm::vec3;
using glm::vec4;
#define TS_MATERIAL_TEMPLATE template <typename Sampler>
#define TS_MATERIAL_IN const TsMaterial&
#define TS_SAMPLER_PARAM , const Sampler& ts_sampler
#define TS_SAMPLE(slot) ts_sampler(slot)
#define TS_SAMPLER_ARG , ts_sampler
#define TS_ALPHA_MASKED(m) ((m).alphaMode == AlphaMode::Mask)
#define TS_ALPHA_FROM_BASE_COLOR(m) ((m).model == ShadingModel::MetallicRoughness)
#else
struct TsMaterialPlanes {
  vec4 diffuse;
  vec4 specular;
  vec4 emissive;
};
#define TS_MATERIAL_TEMPLATE
#define TS_MATERIAL_IN TsMaterial
#define TS_SAMPLER_PARAM
#define TS_SAMPLER_ARG
#define TS_ALPHA_MASKED(m) ((m).alphaMask)
#define TS_ALPHA_FROM_BASE_COLOR(m) ((m).alphaFromBaseColor)
#endif

/* metallicRoughness: the G-buffer is rasterized for glTF's model (RasterOptions::model). */
TS_MATERIAL_TEMPLATE
TsMaterialPlanes ts_material_planes(bool metallicRoughness, TS_MATERIAL_IN m TS_SAMPLER_PARAM) {
  TsMaterialPlanes p;
  if (metallicRoughness) {
    vec4 mr = TS_SAMPLE(TS_TEXTURE_METALLIC_ROUGHNESS);
    p.diffuse = vec4(m.baseColor * vec3(TS_SAMPLE(TS_TEXTURE_BASE_COLOR)), m.metallic * mr.z);
    p.specular = vec4(m.roughness * mr.y, 0.0f, 0.0f, 0.0f);
  } else {
    p.diffuse = vec4(m.diffuse * vec3(TS_SAMPLE(TS_TEXTURE_DIFFUSE)), 1.0f);
    p.specular = vec4(m.specular, m.shininess);
  }
  p.emissive = vec4(m.emissive * vec3(TS_SAMPLE(TS_TEXTURE_EMISSIVE)), 0.0f);
  return p;
}

/* The alpha of the surface point: the material's opacity (glTF baseColorFactor's alpha) times
 * the alpha of the base colour texture of the model the material was written in (so what a MASK
 * covers does not change with --shading-model), sampled as the colour planes sample it. */
TS_MATERIAL_TEMPLATE
float ts_material_alpha(TS_MATERIAL_IN m TS_SAMPLER_PARAM) {
  float texel = TS_ALPHA_FROM_BASE_COLOR(m) ? TS_SAMPLE(TS_TEXTURE_BASE_COLOR).w
                                            : TS_SAMPLE(TS_TEXTURE_DIFFUSE).w;
  return m.opacity * texel;
}

/* False where alphaMode MASK leaves the fragment out (alpha below alphaCutoff, glTF's rule). */
TS_MATERIAL_TEMPLATE
bool ts_material_covered(TS_MATERIAL_IN m TS_SAMPLER_PARAM) {
  return !TS_ALPHA_MASKED(m) || !(ts_material_alpha(m TS_SAMPLER_ARG) < m.alphaCutoff);
}

#ifdef __cplusplus
#undef TS_MATERIAL_TEMPLATE
#undef TS_MATERIAL_IN
#undef TS_SAMPLER_PARAM
#undef TS_SAMPLE
#undef TS_SAMPLER_ARG
#undef TS_ALPHA_MASKED
#undef TS_ALPHA_FROM_BASE_COLOR
}  // namespace material_planes_glsl
using material_planes_glsl::ts_material_alpha;
using material_planes_glsl::ts_material_covered;
using material_planes_glsl::ts_material_planes;
}  // namespace ts
#endif

#endif
