#version 330 core
// The OpenGL rasterizer's fragment stage (src/raster/gl_rasterizer.cpp): writes the G-buffer
// planes of src/gbuffer/gbuffer.h into five render targets (and the triangle id into a sixth).
// The rules mirror the software rasterizer's resolve() (src/raster/rasterizer.cpp); the material
// planes come from the one shared definition in material_planes.h, normal maps (TS_NORMAL_MAPS,
// set by gl_rasterizer.cpp for scenes that have them) from normal_mapping.h.

in vec3 v_viewPosition;  // perspective-correct ("smooth")
in vec3 v_normal;
in vec2 v_uv;

layout(location = 0) out float o_depth;    // linear view depth -z_view
layout(location = 1) out vec4 o_normal;    // view-space unit normal, w = 0
layout(location = 2) out vec4 o_diffuse;
layout(location = 3) out vec4 o_specular;
layout(location = 4) out vec4 o_emissive;
layout(location = 5) out int o_triangle;   // index into the scene's triangles

struct TsMaterial {
  vec3 diffuse;
  vec3 specular;
  float shininess;
  vec3 baseColor;
  float metallic;
  float roughness;
  vec3 emissive;
  float opacity;            // the alpha test's terms (ts_material_covered)
  float alphaCutoff;
  bool alphaMask;           // alphaMode MASK
  bool alphaFromBaseColor;  // written for metallic-roughness: the base colour texture's alpha
};

uniform TsMaterial u_material;
uniform bool u_doubleSided;
uniform bool u_metallicRoughness;            // RasterOptions::model
uniform int u_firstTriangle;                 // of this draw: gl_PrimitiveID counts from it
uniform sampler2D u_texture[4];              // by TS_TEXTURE_* slot
uniform bool u_hasTexture[4];

// Level 0 with the texture's filter and wrap modes (the sampler state set in gl_rasterizer.cpp);
// textureLod because the call sits in non-uniform control flow.
#define TS_SAMPLE(slot) (u_hasTexture[slot] ? textureLod(u_texture[slot], v_uv, 0.0) : vec4(1.0))
#include "material_planes.h"

#include "surface_normal.h"

#if TS_NORMAL_MAPS
in vec4 v_tangent;
uniform sampler2D u_normalTexture;
uniform bool u_hasNormalTexture;
uniform float u_normalScale;
#include "normal_mapping.h"
#endif

void main() {
  // Derivatives outside any branch (undefined in non-uniform control flow).
  vec3 faceNormal = cross(dFdx(v_viewPosition), dFdy(v_viewPosition));
  // alphaMode MASK (material_planes.h): before any output, so the depth test keeps what is behind.
  if (!ts_material_covered(u_material)) discard;
  vec3 n = ts_surface_normal(v_normal, faceNormal, v_viewPosition, false);
#if TS_NORMAL_MAPS
  // Before the double-sided flip (normal_mapping.h); textureLod: non-uniform control flow.
  if (u_hasNormalTexture)
    n = ts_normal_mapped(n, v_tangent, textureLod(u_normalTexture, v_uv, 0.0).rgb, u_normalScale);
#endif
  if (u_doubleSided && !gl_FrontFacing) n = -n;

  TsMaterialPlanes planes = ts_material_planes(u_metallicRoughness, u_material);
  o_depth = -v_viewPosition.z;
  o_normal = vec4(n, 0.0);
  o_diffuse = planes.diffuse;
  o_specular = planes.specular;
  o_emissive = planes.emissive;
  o_triangle = u_firstTriangle + gl_PrimitiveID;
}
