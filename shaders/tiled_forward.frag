#version 430 core
// The forward family's fragment shader (src/raster/gl_rasterizer.cpp): each fragment forms its
// material planes (material_planes.h, as the G-buffer pass does), then sums the lights of one list
// with kernels/shading.h compiled as GLSL: the same shading function as every technique and the
// reference. The list is the fragment's screen tile's in the light grid (tiled-forward and
// tiled-forward-prez: the OpenCL binning kernels' grid, copied into shader storage buffers) or
// its draw's (u_drawList: forward's one light per additive pass, forward-single's batch list).
// Shadow-casting lights' contributions are multiplied by their shadow factor from
// kernels/shadows.h (TS_HAS_SHADOWS), as the kernels do.

// The depth test before the shader runs (a shader with buffer writes otherwise runs for every
// fragment): with the pre-pass's EQUAL test each pixel is shaded once, without it each fragment
// that passes the test at its turn (later overwritten ones included, as the paper counts them).
// A scene with alphaMode MASK materials (TS_ALPHA_MASK, set by gl_rasterizer.cpp) tests late
// instead: its discard must come before the depth write, so fragments that then fail the depth
// test are shaded and counted too (docs/opengl.md).
// The capture pass always tests early: it records only what passes (its BLEND surfaces never
// discard).
#if !TS_ALPHA_MASK || TS_CAPTURE
layout(early_fragment_tests) in;
#endif

in vec3 v_viewPosition;  // perspective-correct ("smooth")
in vec3 v_normal;
in vec2 v_uv;

layout(location = 0) out vec4 o_color;
// The draw batch that wrote the fragment (forward, forward-single: which list a pixel's visible
// surface shaded, for the conservativeness check); not a draw buffer of tiled forward.
layout(location = 2) out int o_batch;
uniform int u_batch;
// The fragment's triangle (an index into the scene's, as the G-buffer pass writes it): forward's
// base pass keeps each pixel's visible one (location 3), and its light passes (u_visibleOnly)
// shade the fragment of that triangle only. Their depth test EQUAL alone passes every fragment at
// the visible depth, e.g. a face drawn twice in one plane, which the additive blend would sum.
layout(location = 3) out int o_triangle;
uniform int u_firstTriangle;
uniform bool u_visibleOnly;
uniform isampler2D u_visibleTriangle;
// --msaa (u_samples > 1): the visible triangle per sample; a light-pass fragment writes only the
// samples it covers whose visible triangle is its own (gl_SampleMask), as EQUAL tests per sample.
uniform isampler2DMS u_visibleTriangleMS;
uniform int u_samples;

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
uniform bool u_metallicRoughness;
uniform sampler2D u_texture[4];
uniform bool u_hasTexture[4];

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
#include "opencl_as_glsl.h"
#include "kernels/shading.h"

layout(std430, binding = 0) readonly buffer LightPosRange { vec4 light_pos_range[]; };
layout(std430, binding = 1) readonly buffer LightColor { vec4 light_color[]; };
layout(std430, binding = 2) readonly buffer LightSpot { vec4 light_spot[]; };
layout(std430, binding = 3) readonly buffer DirLights { vec4 dir_light[]; };  // dir, colour pairs
layout(std430, binding = 4) readonly buffer TileBins { uvec2 tile_bin[]; };  // (offset, count)
layout(std430, binding = 5) readonly buffer TileLights { uint tile_lights[]; };
// Lighting computations, the paper's Figure 3 count: fragment invocations x lights evaluated
// (fragments later overwritten included), per tile so no counter wraps and few collide.
layout(std430, binding = 6) buffer TileWork { uint tile_work[]; };

#if TS_HAS_SHADOWS
// Shadows (set by gl_rasterizer.cpp only when a light casts one: a scene without pays nothing),
// sampled by kernels/shadows.h, the kernels' own file, from the buffers the kernels get: per light
// its first face (-1: none), the face table, the atlas. The atlas is an R32F texture read with
// texelFetch (the float texel itself, no filtering) rather than a storage buffer: it reaches the
// texture size limit (llvmpipe: 16384^2 texels, 1 GiB) where a storage block may be capped at
// 128 MiB; the texel index is the kernels' row-major one, split by the atlas's width.
layout(std430, binding = 7) readonly buffer LightShadow { int light_shadow[]; };
layout(std430, binding = 8) readonly buffer DirShadow { int dir_light_shadow[]; };
layout(std430, binding = 9) readonly buffer ShadowFaces { vec4 shadow_faces[]; };
uniform sampler2D u_shadowAtlas;
ivec2 ts_atlas_texel(int i) {
  int width = textureSize(u_shadowAtlas, 0).x;
  return ivec2(i % width, i / width);
}
// GLSL passes no buffer: the parameters shadows.h threads through are unused ints (0).
#define TS_SHADOW_FACES int
#define TS_SHADOW_ATLAS int
#define TS_SHADOW_FACE(t, i) shadow_faces[i]
#define TS_SHADOW_TEXEL(a, i) texelFetch(u_shadowAtlas, ts_atlas_texel(i), 0).r
#include "kernels/shadows.h"
#endif

uniform vec3 u_ambient;
uniform int u_dirLightCount;
uniform ivec3 u_tiles;  // tile width, height, tiles per row
// clustered-forward's grid: (slices per tile, slicing's near depth, scale); a fragment's bin is
// tile * slices + its slice, computed from its own view depth as kernels/clustered.cl computes a
// pixel's (so a glass fragment finds its own cluster). slices 1: the tile's list.
uniform vec3 u_slicing;
uniform int u_model;
uniform int u_shading;
uniform int u_specularOn;
uniform int u_spotOn;
uniform int u_emissiveOn;
// The list of the draw instead of the tile's: u_list = (offset, count) into tile_lights.
uniform bool u_drawList;
uniform uvec2 u_list;
// Ambient and emission (and the directional lights, u_dirLightCount): off in forward's light
// passes, which add one light each onto the base pass's image.
uniform bool u_baseTerms;
// The transparent pass (alphaMode BLEND, --blend blend): the colour premultiplied by the
// fragment's alpha (ts_material_alpha), blended "over" the image (ONE, ONE_MINUS_SRC_ALPHA).
uniform bool u_transparent;

#if TS_CAPTURE
// The capture pass of the reference's composite (GlRasterizer::captureTransparent): the same
// fragments as the transparent pass, each recorded with what the double reference shades it
// from; a slot past the capacity is counted, not written, so an overflow is seen and grown.
struct TsCapturedFragment {
  ivec4 where;      // pixel x, y, the draw's place in the back-to-front order, gl_PrimitiveID
  vec4 position;    // view-space P, alpha
  vec4 normal;      // the shading normal N (after normal map and double-sided flip)
  vec4 diffuse;     // the material planes (material_planes.h)
  vec4 specular;
  vec4 emissive;
};
layout(std430, binding = 10) buffer CaptureCount { uint capture_count; };
layout(std430, binding = 11) writeonly buffer Captured { TsCapturedFragment captured[]; };
uniform uint u_captureCapacity;
uniform int u_drawOrder;
#endif

void main() {
  vec3 faceNormal = cross(dFdx(v_viewPosition), dFdy(v_viewPosition));
  int triangle = u_firstTriangle + gl_PrimitiveID;
  // Written on every path (a mask written on some only is undefined on the others); ignored
  // without multisampled targets.
  gl_SampleMask[0] = gl_SampleMaskIn[0];
  if (u_visibleOnly && u_samples > 1) {
    int visible = 0;
    for (int k = 0; k < u_samples; ++k)
      if (texelFetch(u_visibleTriangleMS, ivec2(gl_FragCoord.xy), k).r == triangle)
        visible |= 1 << k;
    visible &= gl_SampleMaskIn[0];
    if (visible == 0) discard;
    gl_SampleMask[0] = visible;
  } else if (u_visibleOnly &&
             texelFetch(u_visibleTriangle, ivec2(gl_FragCoord.xy), 0).r != triangle) {
    discard;
  }
  if (!ts_material_covered(u_material)) discard;  // alphaMode MASK (material_planes.h)
  vec3 N = ts_surface_normal(v_normal, faceNormal, v_viewPosition, false);
#if TS_NORMAL_MAPS
  // Before the double-sided flip (normal_mapping.h); textureLod: non-uniform control flow.
  if (u_hasNormalTexture)
    N = ts_normal_mapped(N, v_tangent, textureLod(u_normalTexture, v_uv, 0.0).rgb, u_normalScale);
#endif
  if (u_doubleSided && !gl_FrontFacing) N = -N;
  TsMaterialPlanes planes = ts_material_planes(u_metallicRoughness, u_material);
  // The position interpolated from the vertices (forward shading's own), not rebuilt from depth.
  vec3 P = v_viewPosition;
#if TS_CAPTURE
  uint slot = atomicAdd(capture_count, 1u);
  if (slot < u_captureCapacity)
    captured[slot] = TsCapturedFragment(ivec4(ivec2(gl_FragCoord.xy), u_drawOrder, gl_PrimitiveID),
                                        vec4(P, ts_material_alpha(u_material)), vec4(N, 0.0),
                                        planes.diffuse, planes.specular, planes.emissive);
  return;
#endif
  vec3 V = normalize(-P);
  vec3 c_diff, kd, ks;
  float gloss, view_term = 1.0;
  if (u_shading == TS_SHADING_METALLIC_ROUGHNESS) {
    ts_metallic_roughness_terms(planes.diffuse.xyz, planes.diffuse.w, planes.specular.x, c_diff,
                                kd, ks, gloss);
    view_term = ts_smith_view_term(N, V, gloss);
  } else {
    c_diff = kd = planes.diffuse.xyz;
    vec4 spec = u_specularOn != 0 ? planes.specular : vec4(0.0, 0.0, 0.0, 1.0);
    ks = spec.xyz;
    gloss = spec.w;
  }
  vec3 ke = u_emissiveOn != 0 ? planes.emissive.xyz : vec3(0.0);
  ts_shading_point p = ts_make_shading_point(P, N, V, gloss, u_shading);
  p.view_term = view_term;

  ivec2 pixel = ivec2(gl_FragCoord.xy);
  int tile = (pixel.y / u_tiles.y) * u_tiles.z + pixel.x / u_tiles.x;
  uvec2 bin;
  if (u_drawList) {
    bin = u_list;
  } else if (u_slicing.x > 1.0) {
    float slice = clamp(log(-P.z / u_slicing.y) * u_slicing.z, 0.0, u_slicing.x - 1.0);
    bin = tile_bin[tile * int(u_slicing.x) + int(slice)];
  } else {
    bin = tile_bin[tile];
  }
  vec3 sum = vec3(0.0);
  for (uint k = 0u; k < bin.y; ++k) {
    uint i = tile_lights[bin.x + k];
    vec4 spot = u_spotOn != 0 ? light_spot[i] : vec4(0.0, 0.0, 0.0, -1.0);
    vec3 c = ts_punctual_light(p, kd, ks, light_pos_range[i], light_color[i], spot, u_model,
                               u_shading, u_specularOn, u_spotOn);
#if TS_HAS_SHADOWS
    // As the kernels' ts_shade_punctual (kernels/gbuffer.h): sampled only where the light reaches.
    int first = light_shadow[i];
    if (first >= 0 && c != vec3(0.0))
      c *= ts_shadow_factor(0, 0, first, P, N, normalize(light_pos_range[i].xyz - P));
#endif
    sum += c;
  }
  vec3 directional = vec3(0.0);
  for (int k = 0; k < u_dirLightCount; ++k) {
    vec3 c = ts_directional_light(p, kd, ks, dir_light[2 * k].xyz, dir_light[2 * k + 1].xyz,
                                  u_shading, u_specularOn);
#if TS_HAS_SHADOWS
    int first = dir_light_shadow[k];
    if (first >= 0 && c != vec3(0.0))
      c *= ts_shadow_factor(0, 0, first, P, N, dir_light[2 * k].xyz);
#endif
    directional += c;
  }
  atomicAdd(tile_work[tile], bin.y + uint(u_dirLightCount));
  vec3 base = u_baseTerms ? ts_surface_base(ke, c_diff, u_ambient) : vec3(0.0);
  sum += directional + base;
  if (u_transparent) {
    float alpha = ts_material_alpha(u_material);
    o_color = vec4(sum * alpha, alpha);
  } else {
    o_color = vec4(sum, 0.0);
  }
  o_batch = u_batch;
  o_triangle = triangle;
}
