#version 430 core
// A G-buffer shaded in OpenGL (src/raster/gl_gbuffer_shading.cpp): a full-screen pass over the
// encoded fp32 planes (textures), every light from shader storage buffers, each pixel shaded with
// kernels/shading.h itself, compiled as GLSL (the file the OpenCL kernels build, read from their
// folder). The pixel's decoding mirrors ts_load_surface and the sums kernels/brute.cl, so the
// image is the `brute` technique's to fp32 rounding.
#include "opencl_as_glsl.h"
#include "kernels/shading.h"

layout(std430, binding = 0) readonly buffer LightPosRange { vec4 light_pos_range[]; };
layout(std430, binding = 1) readonly buffer LightColor { vec4 light_color[]; };
layout(std430, binding = 2) readonly buffer LightSpot { vec4 light_spot[]; };
layout(std430, binding = 3) readonly buffer DirLights { vec4 dir_light[]; };  // dir, colour pairs

uniform sampler2D u_depth;  // R32F, row 0 = image row 0 (the framebuffer's rows likewise)
uniform sampler2D u_normal;
uniform sampler2D u_diffuse;
uniform sampler2D u_specular;
uniform sampler2D u_emissive;
uniform vec4 u_camera;  // (tan x, tan y, width, height), as the kernels' camera
uniform vec3 u_ambient;
uniform int u_lightCount;
uniform int u_dirLightCount;
// The kernels' build-time features (SceneFeatures::kernelDefines), here uniforms.
uniform int u_model;     // TS_MODEL_*
uniform int u_shading;   // TS_SHADING_*
uniform int u_specularOn;
uniform int u_spotOn;
uniform int u_emissiveOn;

layout(location = 0) out vec4 o_color;

void main() {
  ivec2 texel = ivec2(gl_FragCoord.xy);
  int width = int(u_camera.z), height = int(u_camera.w);
  float depth = texelFetch(u_depth, texel, 0).r;
  if (depth <= 0.0) {
    o_color = vec4(0.0);
    return;
  }
  vec3 P = ts_view_position(texel.x, texel.y, depth, u_camera.x, u_camera.y, width, height);
  vec3 V = normalize(-P);
  vec4 normal = texelFetch(u_normal, texel, 0);
  vec3 N = normalize(normal.xyz);
  vec4 diffuse = texelFetch(u_diffuse, texel, 0);
  vec3 c_diff, kd, ks;
  float gloss, view_term = 1.0;
  if (u_shading == TS_SHADING_METALLIC_ROUGHNESS) {
    ts_metallic_roughness_terms(diffuse.xyz, diffuse.w, normal.w, c_diff, kd, ks, gloss);
    view_term = ts_smith_view_term(N, V, gloss);
  } else {
    c_diff = kd = diffuse.xyz;
    vec4 spec = u_specularOn != 0 ? texelFetch(u_specular, texel, 0) : vec4(0.0, 0.0, 0.0, 1.0);
    ks = spec.xyz;
    gloss = spec.w;
  }
  vec3 ke = u_emissiveOn != 0 ? texelFetch(u_emissive, texel, 0).xyz : vec3(0.0);
  ts_shading_point p = ts_make_shading_point(P, N, V, gloss, u_shading);
  p.view_term = view_term;

  vec3 sum = vec3(0.0);
  for (int i = 0; i < u_lightCount; ++i) {
    vec4 spot = u_spotOn != 0 ? light_spot[i] : vec4(0.0, 0.0, 0.0, -1.0);
    sum += ts_punctual_light(p, kd, ks, light_pos_range[i], light_color[i], spot, u_model,
                             u_shading, u_specularOn, u_spotOn);
  }
  vec3 directional = vec3(0.0);
  for (int k = 0; k < u_dirLightCount; ++k)
    directional += ts_directional_light(p, kd, ks, dir_light[2 * k].xyz, dir_light[2 * k + 1].xyz,
                                        u_shading, u_specularOn);
  sum += directional + ts_surface_base(ke, c_diff, u_ambient);
  o_color = vec4(sum, 0.0);
}
