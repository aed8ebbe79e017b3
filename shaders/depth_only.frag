#version 330 core
// The depth-only pre-pass of tiled-forward-prez (src/raster/gl_rasterizer.cpp, depthPrepass):
// the hardware depth buffer for the forward pass's EQUAL test, and the linear view depth -z_view
// (as the G-buffer's depth plane) for the OpenCL tile_depth_bounds kernel. The shadow maps
// (drawShadowAtlas) are drawn with it too: -z_view of a face's view is the maps' linear depth.
// alphaMode MASK fragments are left out as the G-buffer and forward passes leave them
// (material_planes.h), and as the software maps do. Location 3 gets the fragment's triangle, as
// tiled_forward.frag's base pass writes it: the forward pass after the pre-pass shades only that
// triangle (u_visibleOnly), as the EQUAL test alone would shade coplanar faces drawn twice.
in vec3 v_viewPosition;
in vec2 v_uv;
layout(location = 1) out float o_depth;
layout(location = 3) out int o_triangle;
uniform int u_firstTriangle;

struct TsMaterial {
  vec3 diffuse;
  vec3 specular;
  float shininess;
  vec3 baseColor;
  float metallic;
  float roughness;
  vec3 emissive;
  float opacity;
  float alphaCutoff;
  bool alphaMask;
  bool alphaFromBaseColor;
};

uniform TsMaterial u_material;
uniform sampler2D u_texture[4];
uniform bool u_hasTexture[4];

#define TS_SAMPLE(slot) (u_hasTexture[slot] ? textureLod(u_texture[slot], v_uv, 0.0) : vec4(1.0))
#include "material_planes.h"

void main() {
  if (!ts_material_covered(u_material)) discard;
  o_depth = -v_viewPosition.z;
  o_triangle = u_firstTriangle + gl_PrimitiveID;
}
