// The OpenGL rasterizer behind `--raster gl` (see gl_rasterizer.h). Design notes: how each
// convention of the software rasterizer (src/raster/rasterizer.cpp) is reproduced with OpenGL.
//
//  - Camera: the x, y and w rows of CameraIntrinsics::projection() (the float tangents the kernels
//    use), so clip x = X / tanHalfFovX, clip y = Y / tanHalfFovY, clip w = -Z as in the software
//    setup. The view transform runs in float in the vertex shader (the software one in double).
//  - Row 0 at the top, and the fill rule: the software image has row 0 at the top and applies the
//    top-left rule with y pointing down. OpenGL's window y points up from row 0 of the
//    framebuffer's memory, and Mesa (llvmpipe) applies its top-left rule to the memory's rows
//    (the edge nearer row 0 is "top"). So the projection negates clip y: framebuffer row r is image
//    row r, no flip on read-back, and an edge through pixel centres is owned by the same side as in
//    the software rasterizer (tested: GlRaster.FillRuleMatchesSoftware). The flip mirrors the
//    window-space winding, so counter-clockwise front faces are declared with glFrontFace(GL_CW).
//  - Depth: the planes store the linear view depth -z_view, interpolated perspective-correctly
//    from the view-space position (a float render target), never the hardware depth. The hidden-
//    surface test uses a 32-bit float depth buffer with "reversed" depth: clip z = znear, so
//    window depth = znear / depth (with glClipControl ZERO_TO_ONE), linear in screen space and
//    with float's relative precision at every distance; the test is GL_GREATER, so of two equal
//    depths the triangle drawn first (the lower index: draws keep the scene's triangle order)
//    wins, as in the software rasterizer. Near plane: clip z <= clip w is w >= znear, the software
//    rasterizer's near clip. Far plane: not clipped; the depth buffer is cleared to znear / zfar,
//    so fragments beyond zfar fail the test (the software rasterizer rejects them per pixel).
//  - Pixel centres at +0.5 and single-sample rasterization: OpenGL's defaults.
//  - Normals, facing, materials, textures: shaders/gbuffer.frag (the same rules as resolve(); the
//    material planes from the shared shaders/material_planes.h, normal maps from the shared
//    shaders/normal_mapping.h, with the tangents as vertex attribute 3 only for a scene that has
//    normal maps: TS_NORMAL_MAPS). Textures are RGBA32F copies of
//    ts::Texture (linear, no sRGB conversion on either side), without mipmaps, with the texture's
//    wrap modes and filter (GL_LINEAR: bilinear with texel centres at half-integers; GL_NEAREST),
//    as Texture::sample.
//  - alphaMode MASK: the shaders discard what ts_material_covered (material_planes.h) leaves out,
//    the test the software visibility pass applies; the forward shader of a scene with MASK
//    materials tests depth late (TS_ALPHA_MASK), since its discard must precede the depth write.
//  - Shadow maps (drawShadowAtlas): depth_only.frag's linear depth into one R32F atlas, a viewport
//    and scissor per face, the same reversed GL_GREATER test (orthographic faces: clip z linear
//    in depth, w = 1), only the batches whose boxes touch the face (touchesFace, as the software
//    maps); compared with the software maps in tests/raster/gl_shadow_maps_test.cpp.
//  - Triangle ids: gl_PrimitiveID plus the draw's first triangle (one draw per run of triangles
//    sharing a material, in scene order: raster/draw_batches.h, whose boxes the forward
//    techniques cull lights against).
// What cannot match bit for bit (float vertex transform, the snapped-triangle attribute
// interpolation, sampler weight precision) is measured in tests/raster/gl_raster_test.cpp and
// described in docs/opengl.md.
#include "raster/gl_rasterizer.h"

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include <epoxy/gl.h>
#include <glm/gtc/matrix_transform.hpp>

#include "raster/draw_batches.h"
#include "raster/egl_context.h"
#include "raster/gl_program.h"
#include "raster/gl_targets.h"
#include "raster/scene_validation.h"
#include "shaders/material_planes.h"
#include "shading/shading_cpu.h"  // TS_SHADOW_FACE_RECORDS (kernels/shadows.h)
#include "util/error.h"

namespace ts {
namespace {

GLint glWrap(TextureWrap wrap) {
  switch (wrap) {
    case TextureWrap::ClampToEdge: return GL_CLAMP_TO_EDGE;
    case TextureWrap::MirroredRepeat: return GL_MIRRORED_REPEAT;
    case TextureWrap::Repeat: break;
  }
  return GL_REPEAT;
}

using Clock = std::chrono::steady_clock;

// Render targets, in the fragment shader's output locations.
enum Target { kDepth, kNormal, kDiffuse, kSpecular, kEmissive, kTriangle, kTargets };

// CameraIntrinsics::projection() with clip y negated (row 0 at the top, see above) and clip z
// replaced by the constant znear (reversed depth: window depth = znear / linear depth).
glm::mat4 clipFromView(const CameraIntrinsics& in) {
  glm::mat4 p = in.projection();
  for (int column = 0; column < 4; ++column) {
    p[column][1] = -p[column][1];
    p[column][2] = 0.0f;
  }
  p[3][2] = in.znear;
  return p;
}

// A shadow face's clip transform (rasterizeDepth's DepthView): x and y as the software's (clip y
// negated, as above), z for the same GL_GREATER test as the G-buffer's: perspective clip z =
// znear (window depth znear / depth, near-clipped at depth znear), orthographic clip z =
// (zfar - depth) / (zfar - znear) with w = 1 (clipped to [znear, zfar], as the software's per
// texel test). The texels get the linear depth itself (depth_only.frag), never the window depth.
glm::mat4 clipFromFaceView(const DepthView& v) {
  glm::dmat4 p(0.0);
  p[0][0] = 1.0 / v.halfX;
  p[1][1] = -1.0 / v.halfY;
  if (v.orthographic) {
    p[2][2] = 1.0 / (v.zfar - v.znear);  // Z = -depth
    p[3][2] = v.zfar / (v.zfar - v.znear);
    p[3][3] = 1.0;
  } else {
    p[3][2] = v.znear;
    p[2][3] = -1.0;  // w = -Z = depth
  }
  return glm::mat4(p);
}

// The window depth of a face's far plane: what its depth buffer is cleared to.
GLfloat farWindowDepth(const DepthView& v) {
  return v.orthographic ? 0.0f : GLfloat(v.znear / v.zfar);
}

// The uniforms the scene's draws set (shaders/gbuffer.vert and the material of the fragment
// shaders that take one); -1 where a program has no such uniform (glUniform ignores it).
struct Uniforms {
  GLint viewFromWorld, normalMatrix, clipFromView;
  GLint diffuse, specular, shininess, baseColor, metallic, roughness, emissive;
  GLint opacity, alphaCutoff, alphaMask, alphaFromBaseColor;
  GLint doubleSided, metallicRoughness, firstTriangle, batch;
  GLint texture[TS_TEXTURE_SLOTS], hasTexture[TS_TEXTURE_SLOTS];
  GLint viewRotation, normalTexture, hasNormalTexture, normalScale;  // programs with normal maps
};

// The texture unit of a material's normal map (after the material planes' slots), and of the
// shadow atlas (the forward shader built with TS_HAS_SHADOWS).
constexpr int kNormalTextureUnit = TS_TEXTURE_SLOTS;
constexpr int kShadowAtlasUnit = TS_TEXTURE_SLOTS + 1;
// And of the base pass's visible triangles that forward's light passes read (u_visibleTriangle),
// and their multisampled form (--msaa: u_visibleTriangleMS, per sample).
constexpr int kVisibleTriangleUnit = TS_TEXTURE_SLOTS + 2;
constexpr int kVisibleTriangleMSUnit = TS_TEXTURE_SLOTS + 3;

// Looks the uniforms up and points texture slot s at texture unit s (leaves `program` in use).
Uniforms uniformsOf(GLuint program) {
  Uniforms u{};
  auto at = [&](const std::string& name) { return glGetUniformLocation(program, name.c_str()); };
  u.viewFromWorld = at("u_viewFromWorld");
  u.normalMatrix = at("u_normalMatrix");
  u.clipFromView = at("u_clipFromView");
  u.diffuse = at("u_material.diffuse");
  u.specular = at("u_material.specular");
  u.shininess = at("u_material.shininess");
  u.baseColor = at("u_material.baseColor");
  u.metallic = at("u_material.metallic");
  u.roughness = at("u_material.roughness");
  u.emissive = at("u_material.emissive");
  u.opacity = at("u_material.opacity");
  u.alphaCutoff = at("u_material.alphaCutoff");
  u.alphaMask = at("u_material.alphaMask");
  u.alphaFromBaseColor = at("u_material.alphaFromBaseColor");
  u.doubleSided = at("u_doubleSided");
  u.metallicRoughness = at("u_metallicRoughness");
  u.firstTriangle = at("u_firstTriangle");
  u.batch = at("u_batch");
  u.viewRotation = at("u_viewRotation");
  u.normalTexture = at("u_normalTexture");
  u.hasNormalTexture = at("u_hasNormalTexture");
  u.normalScale = at("u_normalScale");
  glUseProgram(program);
  glUniform1i(u.normalTexture, kNormalTextureUnit);
  for (int s = 0; s < TS_TEXTURE_SLOTS; ++s) {
    u.texture[s] = at("u_texture[" + std::to_string(s) + "]");
    u.hasTexture[s] = at("u_hasTexture[" + std::to_string(s) + "]");
    glUniform1i(u.texture[s], s);  // slot s samples texture unit s
  }
  return u;
}

// The forward passes' shader storage bindings (shaders/tiled_forward.frag).
enum ForwardStorage {
  kPosRange,
  kColor,
  kSpot,
  kDirectional,
  kTileBins,
  kTileLights,
  kTileWork,
  kLightShadow,  // TS_HAS_SHADOWS: the point/spot and directional first faces, the face table
  kDirectionalShadow,
  kShadowFaces,
  kCaptureCount,  // the capture pass's (shaders/tiled_forward.frag, TS_CAPTURE): bindings 10, 11
  kCaptured,
  kGlassBins,  // tiled forward's transparent grid, bound at kTileBins, kTileLights for its pass
  kGlassLights,
  kForwardStorages
};

// The captured fragment of shaders/tiled_forward.frag (std430: six 16-byte members).
struct CapturedRecord {
  int32_t x, y, order, primitive;
  float position[4];  // P, alpha
  float normal[4];
  float diffuse[4], specular[4], emissive[4];
};
static_assert(sizeof(CapturedRecord) == 96, "std430 layout of TsCapturedFragment");

// The work counter's tiles where the lists are the draws' (forward, forward-single): only
// spreads the atomics, as tiled forward's per-tile counters do.
constexpr int kWorkTile = 16;

}  // namespace

struct GlRasterizer::State {
  const Scene& scene;
  std::vector<DrawBatch> draws;
  // The programs are built with the normal-map code only for a scene that has normal maps
  // (TS_NORMAL_MAPS; a scene without pays nothing), whose tangents go to attribute 3.
  bool normalMaps = false;
  GLuint program = 0, vao = 0, vertexBuffer = 0, indexBuffer = 0, tangentBuffer = 0;
  std::vector<GLuint> textures;  // per scene texture; 0 for an empty one (sampled as 1)
  gl::Targets gbufferTargets;    // kTargets colour targets in Target order, float depth
  // The view of the last G-buffer pass (draw()): the hybrid's transparent pass copies its depth
  // when the frame is the same.
  SceneCamera gbufferCamera;
  int gbufferWidth = 0, gbufferHeight = 0;
  GLint maxSize = 0;  // largest width/height the implementation renders
  Uniforms u{};
  // The forward passes (built on first use: they need OpenGL 4.3, the G-buffer pass 3.3).
  // forwardProgram and fu are the variant in use (selectForward): [0] without shadows, [1] with
  // TS_HAS_SHADOWS, built on the first frame with a shadow-casting light.
  GLuint forwardProgram = 0, depthProgram = 0, captureProgram = 0;
  GLuint forwardVariants[2] = {};
  Uniforms fu{}, du{}, cu{}, variantUniforms[2]{};
  GLuint shadowAtlas = 0;  // R32F texture (tiled_forward.frag says why not a storage buffer)
  // image, pre-pass depth, batch ids, triangle ids
  gl::Targets forwardTargets;  // ensureForwardFramebuffer's four
  // forward's base-pass triangle ids, copied out of forwardTargets for the light passes to read
  // (R32I, the size of visibleWidth x visibleHeight).
  GLuint visibleTriangles = 0;
  int visibleWidth = 0, visibleHeight = 0, visibleSamples = 1;
  // --msaa: the G-buffer's multisampled targets (rasterizeSamples), the single-sample targets
  // one sample or the resolve lands in before its read-back (RGBA32F resolved image, R32F a
  // sample's pre-pass depth, R32I a sample's batch ids), and the sample fetch pass
  // (shaders/sample_fetch.frag).
  gl::Targets gbufferSampleTargets, resolveTargets;
  GLuint fetchProgram = 0, fetchVao = 0;
  GLuint storage[kForwardStorages] = {};
  GLuint timer = 0;  // the passes' GL_TIME_ELAPSED query (timed())
  // The shadow maps (built on first use): the depth pre-pass's shaders into an R32F atlas.
  GLuint shadowProgram = 0;
  Uniforms su{};
  gl::Targets shadowTargets;

  explicit State(const Scene& s) : scene(s) {}

  ~State() {
    // The shared context outlives every rasterizer; free what this one made.
    try {
      EglContext::shared().makeCurrent();
    } catch (const Error&) {
      return;
    }
    gbufferTargets.release();
    gbufferSampleTargets.release();
    resolveTargets.release();
    if (fetchProgram) {
      glDeleteProgram(fetchProgram);
      glDeleteVertexArrays(1, &fetchVao);
    }
    forwardTargets.release();
    shadowTargets.release();
    if (forwardVariants[0]) {
      for (GLuint variant : forwardVariants)
        if (variant) glDeleteProgram(variant);
      if (shadowAtlas) glDeleteTextures(1, &shadowAtlas);
      if (visibleTriangles) glDeleteTextures(1, &visibleTriangles);
      glDeleteProgram(depthProgram);
      if (captureProgram) glDeleteProgram(captureProgram);
      glDeleteBuffers(kForwardStorages, storage);
    }
    if (shadowProgram) glDeleteProgram(shadowProgram);
    if (timer) glDeleteQueries(1, &timer);
    if (!textures.empty()) glDeleteTextures(GLsizei(textures.size()), textures.data());
    glDeleteBuffers(1, &vertexBuffer);
    glDeleteBuffers(1, &indexBuffer);
    if (tangentBuffer) glDeleteBuffers(1, &tangentBuffer);
    glDeleteVertexArrays(1, &vao);
    glDeleteProgram(program);
  }

  void upload() {
    glGenVertexArrays(1, &vao);
    glBindVertexArray(vao);
    glGenBuffers(1, &vertexBuffer);
    glBindBuffer(GL_ARRAY_BUFFER, vertexBuffer);
    glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(scene.vertices.size() * sizeof(Vertex)),
                 scene.vertices.data(), GL_STATIC_DRAW);
    const GLsizei stride = sizeof(Vertex);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, stride,
                          reinterpret_cast<const void*>(offsetof(Vertex, position)));
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, stride,
                          reinterpret_cast<const void*>(offsetof(Vertex, normal)));
    glVertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, stride,
                          reinterpret_cast<const void*>(offsetof(Vertex, uv)));
    for (GLuint a = 0; a < 3; ++a) glEnableVertexAttribArray(a);
    if (normalMaps) {
      glGenBuffers(1, &tangentBuffer);
      glBindBuffer(GL_ARRAY_BUFFER, tangentBuffer);
      glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(scene.tangents.size() * sizeof(glm::vec4)),
                   scene.tangents.data(), GL_STATIC_DRAW);
      glVertexAttribPointer(3, 4, GL_FLOAT, GL_FALSE, sizeof(glm::vec4), nullptr);
      glEnableVertexAttribArray(3);
    }
    glGenBuffers(1, &indexBuffer);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, indexBuffer);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(scene.indices.size() * sizeof(uint32_t)),
                 scene.indices.data(), GL_STATIC_DRAW);
    glBindVertexArray(0);
    gl::checkErrors("uploading the vertices of scene '" + scene.name + "'");

    GLint maxTexture = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxTexture);
    textures.assign(scene.textures.size(), 0);
    for (size_t i = 0; i < scene.textures.size(); ++i) {
      const Texture& t = scene.textures[i];
      if (t.width <= 0 || t.height <= 0) continue;  // Texture::sample gives 1, as "no texture"
      if (t.width > maxTexture || t.height > maxTexture)
        throw Error("scene '" + scene.name + "': texture " + std::to_string(i) + " is " +
                    std::to_string(t.width) + "x" + std::to_string(t.height) +
                    ", larger than the OpenGL limit " + std::to_string(maxTexture));
      glGenTextures(1, &textures[i]);
      glBindTexture(GL_TEXTURE_2D, textures[i]);
      glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
      // Row 0 = v = 0 in both ts::Texture and OpenGL's t = 0: no flip.
      glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, t.width, t.height, 0, GL_RGBA, GL_FLOAT,
                   t.texels.data());
      // textureLod(.., 0) magnifies (lambda 0): the magnification filter is the one used.
      const GLint filter = t.nearest ? GL_NEAREST : GL_LINEAR;
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, filter);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, filter);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, glWrap(t.wrapS));
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, glWrap(t.wrapT));
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_BASE_LEVEL, 0);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);
      gl::checkErrors("uploading texture " + std::to_string(i) + " of scene '" + scene.name + "'");
    }
  }

  // The programs' TS_NORMAL_MAPS, TS_ALPHA_MASK (some material is alphaMode MASK: the
  // forward shader's depth test runs after its discard).
  // capture: the forward shader's TS_CAPTURE build (captureTransparent).
  std::string defines(bool capture = false) const {
    bool masks = false;
    for (const Material& m : scene.materials) masks = masks || m.alphaMode == AlphaMode::Mask;
    return std::string("#define TS_NORMAL_MAPS ") + (normalMaps ? "1" : "0") + "\n" +
           "#define TS_ALPHA_MASK " + (masks ? "1" : "0") + "\n" + "#define TS_CAPTURE " +
           (capture ? "1" : "0") + "\n";
  }

  void buildProgram() {
    program = gl::buildProgram("gbuffer.vert", "gbuffer.frag", defines());
    u = uniformsOf(program);
    // Locations 0..5 of the fragment outputs are fixed in the shader (layout qualifiers).
    gl::checkErrors("setting up the G-buffer program");
  }

  void ensureFramebuffer(int w, int h) {
    gbufferTargets.ensure(
        w, h, {GL_R32F, GL_RGBA32F, GL_RGBA32F, GL_RGBA32F, GL_RGBA32F, GL_R32I},
        "G-buffer framebuffer (five float targets, an integer target, float depth)");
  }
  void ensureSampleFramebuffer(int w, int h, int samples) {
    gbufferSampleTargets.ensure(
        w, h, {GL_R32F, GL_RGBA32F, GL_RGBA32F, GL_RGBA32F, GL_RGBA32F, GL_R32I},
        "multisampled G-buffer framebuffer (five float targets, an integer target, float depth)",
        samples);
  }

  // ---- MSAA: one sample of a multisampled target ------------------------------------------

  void buildFetch() {
    if (fetchProgram) return;
    fetchProgram = gl::buildProgram("fullscreen.vert", "sample_fetch.frag");
    glUseProgram(fetchProgram);
    glUniform1i(glGetUniformLocation(fetchProgram, "u_float"), 0);
    glUniform1i(glGetUniformLocation(fetchProgram, "u_int"), 1);
    glGenVertexArrays(1, &fetchVao);
    gl::checkErrors("setting up the sample fetch program");
  }

  // Sample `sample` of colour target `plane` of the multisampled `from` into colour target
  // `toPlane` of the single-sample `to` (same size), bit for bit (shaders/sample_fetch.frag).
  void fetchSample(const gl::Targets& from, int plane, bool integer, int sample,
                   const gl::Targets& to, int toPlane) {
    buildFetch();
    glBindFramebuffer(GL_FRAMEBUFFER, to.framebuffer);
    GLenum buffers[2] = {GL_NONE, GL_NONE};
    buffers[integer ? 1 : 0] = GLenum(GL_COLOR_ATTACHMENT0 + toPlane);
    glDrawBuffers(2, buffers);
    glViewport(0, 0, to.width, to.height);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    glDisable(GL_SCISSOR_TEST);
    glDisable(GL_STENCIL_TEST);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glUseProgram(fetchProgram);
    glUniform1i(glGetUniformLocation(fetchProgram, "u_integer"), integer ? 1 : 0);
    glUniform1i(glGetUniformLocation(fetchProgram, "u_sample"), sample);
    glActiveTexture(GLenum(GL_TEXTURE0 + (integer ? 1 : 0)));
    glBindTexture(GL_TEXTURE_2D_MULTISAMPLE, from.colour[size_t(plane)]);
    glBindVertexArray(fetchVao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
    glActiveTexture(GL_TEXTURE0);  // the unit every other texture binding assumes
    glEnable(GL_DEPTH_TEST);
    gl::checkErrors("fetching sample " + std::to_string(sample) + " of a multisampled target");
  }

  void ensureResolveFramebuffer(int w, int h) {
    resolveTargets.ensure(w, h, {GL_RGBA32F, GL_R32F, GL_R32I},
                          "MSAA resolve framebuffer (RGBA32F, R32F, R32I, float depth)");
  }

  // applyNormalMaps: RasterOptions::normalMaps (SceneFeatures::normalMaps of forward passes).
  void setMaterial(const Uniforms& u, const Material& m, bool metallicRoughness,
                   bool applyNormalMaps) {
    glUniform3fv(u.diffuse, 1, &m.diffuse.x);
    glUniform3fv(u.specular, 1, &m.specular.x);
    glUniform1f(u.shininess, m.shininess);
    glUniform3fv(u.baseColor, 1, &m.baseColor.x);
    glUniform1f(u.metallic, m.metallic);
    glUniform1f(u.roughness, m.roughness);
    glUniform3fv(u.emissive, 1, &m.emissive.x);
    glUniform1f(u.opacity, m.opacity);
    glUniform1f(u.alphaCutoff, m.alphaCutoff);
    glUniform1i(u.alphaMask, m.alphaMode == AlphaMode::Mask ? 1 : 0);
    glUniform1i(u.alphaFromBaseColor, m.model == ShadingModel::MetallicRoughness ? 1 : 0);
    glUniform1i(u.doubleSided, m.doubleSided ? 1 : 0);
    glUniform1i(u.metallicRoughness, metallicRoughness ? 1 : 0);
    for (int s = 0; s < TS_TEXTURE_SLOTS; ++s) {
      const int index = materialTexture(m, s);
      const GLuint texture = index >= 0 ? textures[size_t(index)] : 0;
      glUniform1i(u.hasTexture[s], texture != 0 ? 1 : 0);
      glActiveTexture(GLenum(GL_TEXTURE0 + s));
      glBindTexture(GL_TEXTURE_2D, texture);
    }
    if (normalMaps) {
      const GLuint texture =
          applyNormalMaps && m.normalTexture >= 0 ? textures[size_t(m.normalTexture)] : 0;
      glUniform1i(u.hasNormalTexture, texture != 0 ? 1 : 0);
      glUniform1f(u.normalScale, m.normalScale);
      glActiveTexture(GLenum(GL_TEXTURE0 + kNormalTextureUnit));
      glBindTexture(GL_TEXTURE_2D, texture);
    }
  }

  void draw(const SceneCamera& camera, const CameraIntrinsics& in, const RasterOptions& options,
            const gl::Targets& targets) {
    glBindFramebuffer(GL_FRAMEBUFFER, targets.framebuffer);
    GLenum buffers[kTargets];
    for (int t = 0; t < kTargets; ++t) buffers[t] = GLenum(GL_COLOR_ATTACHMENT0 + t);
    if (!options.triangleIds) buffers[kTriangle] = GL_NONE;
    glDrawBuffers(kTargets, buffers);
    glViewport(0, 0, in.width, in.height);

    // Fixed-function state, set every frame (the context is shared with other rasterizers).
    glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_GREATER);
    glDepthMask(GL_TRUE);
    glDisable(GL_CULL_FACE);  // nothing is culled, as in the software rasterizer
    glFrontFace(GL_CW);       // counter-clockwise once the y flip is undone
    glDisable(GL_BLEND);
    glDisable(GL_DITHER);
    glDisable(GL_SCISSOR_TEST);
    glDisable(GL_STENCIL_TEST);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);

    const GLfloat zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    for (int t = kDepth; t <= kEmissive; ++t) glClearBufferfv(GL_COLOR, t, zero);
    const GLint none[4] = {-1, -1, -1, -1};
    if (options.triangleIds) glClearBufferiv(GL_COLOR, kTriangle, none);
    const GLfloat farDepth = in.znear / in.zfar;
    glClearBufferfv(GL_DEPTH, 0, &farDepth);

    glUseProgram(program);
    drawScene(u, camera, in, options.model == ShadingModel::MetallicRoughness, options.normalMaps);
    gl::checkErrors("drawing scene '" + scene.name + "'");
    gbufferCamera = camera;
    gbufferWidth = in.width;
    gbufferHeight = in.height;
  }

  // Whether the G-buffer targets' depth is that of `camera` at this size (the last draw()).
  bool gbufferDepthIs(const SceneCamera& camera, int w, int h) const {
    const SceneCamera& c = gbufferCamera;
    return w == gbufferWidth && h == gbufferHeight && c.viewFromWorld == camera.viewFromWorld &&
           c.yfov == camera.yfov && c.znear == camera.znear && c.zfar == camera.zfar;
  }

  // The hybrid's background: `opaque` into the forward image target, and the opaque depth, the
  // G-buffer pass's copied (blit) when it is this frame's, else drawn again by the depth program
  // (the same draws and vertex shader: the same depth, as the capture's pass draws it). Returns
  // whether it was drawn again.
  bool opaqueBackground(const SceneCamera& camera, const CameraIntrinsics& in,
                        const std::vector<glm::vec4>& opaque) {
    passState(in);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, forwardTargets.colour[0]);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, in.width, in.height, GL_RGBA, GL_FLOAT, opaque.data());
    const bool redraw = !gbufferDepthIs(camera, in.width, in.height);
    if (redraw) {
      const GLenum none[1] = {GL_NONE};
      glDrawBuffers(1, none);
      clearDepth(in);
      glDepthFunc(GL_GREATER);
      glUseProgram(depthProgram);
      drawScene(du, camera, in, false, false);
    } else {
      glBindFramebuffer(GL_READ_FRAMEBUFFER, gbufferTargets.framebuffer);
      glBindFramebuffer(GL_DRAW_FRAMEBUFFER, forwardTargets.framebuffer);
      glBlitFramebuffer(0, 0, in.width, in.height, 0, 0, in.width, in.height, GL_DEPTH_BUFFER_BIT,
                        GL_NEAREST);
      glBindFramebuffer(GL_FRAMEBUFFER, forwardTargets.framebuffer);
    }
    gl::checkErrors("the opaque image and depth under the transparent pass");
    return redraw;
  }

  // Every opaque draw of the scene with `u`'s program in use: the camera, then per draw its
  // material. The transparent ones (--blend blend) are drawn after, back to front
  // (drawTransparent); the G-buffer and the depth passes never hold them.
  void drawScene(const Uniforms& u, const SceneCamera& camera, const CameraIntrinsics& in,
                 bool metallicRoughness, bool applyNormalMaps) {
    setCamera(u, camera, in);
    glBindVertexArray(vao);
    for (size_t b = 0; b < draws.size(); ++b)
      if (!transparent(b)) drawBatch(u, b, metallicRoughness, applyNormalMaps);
    glBindVertexArray(0);
  }

  // alphaMode BLEND: only in a scene that composites them (validateForRaster refuses others).
  bool transparent(size_t b) const { return draws[b].material->alphaMode == AlphaMode::Blend; }

  // The transparent draws, farthest first: by the distance from the eye to the centre of each
  // draw's world box (in double), ties in draw order. Within a draw the triangles blend in their
  // order (OpenGL's primitive order), not by depth.
  std::vector<uint32_t> backToFront(const SceneCamera& camera) const {
    std::vector<std::pair<double, uint32_t>> keyed;
    for (size_t b = 0; b < draws.size(); ++b) {
      if (!transparent(b)) continue;
      const glm::dvec3 centre =
          0.5 * (glm::dvec3(draws[b].bounds.min) + glm::dvec3(draws[b].bounds.max));
      const glm::dvec3 view(camera.viewFromWorld * glm::dvec4(centre, 1.0));
      keyed.emplace_back(glm::length(view), uint32_t(b));
    }
    std::stable_sort(keyed.begin(), keyed.end(),
                     [](const auto& a, const auto& b) { return a.first > b.first; });
    std::vector<uint32_t> order;
    for (const auto& k : keyed) order.push_back(k.second);
    return order;
  }

  // The transparent pass over the image of an opaque pass (its depth buffer in place): the draws
  // back to front, depth test on (GREATER, reversed depth) and depth writes off, premultiplied
  // "over" blending into the image (alpha left at 0), each fragment shaded by the forward
  // program with u_transparent. beforeDraw(b): the draw's list (u_list) where lists are the
  // draws'. Adds its time and draws to `out`.
  void drawTransparent(const SceneCamera& camera, const CameraIntrinsics& in,
                       const ForwardLighting& lighting, int directionals,
                       const std::function<void(size_t)>& beforeDraw, ForwardImage& out) {
    const std::vector<uint32_t> order = backToFront(camera);
    if (order.empty()) return;
    const bool metallicRoughness = lighting.features.model == ShadingModel::MetallicRoughness;
    const GLenum image[1] = {GL_COLOR_ATTACHMENT0};
    glDrawBuffers(1, image);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_GREATER);
    glDepthMask(GL_FALSE);
    glEnable(GL_BLEND);
    glBlendEquation(GL_FUNC_ADD);
    glBlendFuncSeparate(GL_ONE, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE);
    glUniform1i(forwardUniform("u_transparent"), 1);
    glUniform1i(forwardUniform("u_baseTerms"), 1);
    glUniform1i(forwardUniform("u_dirLightCount"), GLint(directionals));
    out.transparentMs = timed(
        [&] {
          setCamera(fu, camera, in);
          glBindVertexArray(vao);
          for (uint32_t b : order) {
            if (beforeDraw) beforeDraw(b);
            drawBatch(fu, b, metallicRoughness, lighting.features.normalMaps);
          }
          glBindVertexArray(0);
        },
        out.transparentQueryMs);
    out.transparentDraws = order.size();
    out.draws += order.size();
    glUniform1i(forwardUniform("u_transparent"), 0);
    glDisable(GL_BLEND);
    glDepthMask(GL_TRUE);
    gl::checkErrors("the transparent pass of scene '" + scene.name + "'");
  }

  void setCamera(const Uniforms& u, const SceneCamera& camera, const CameraIntrinsics& in) {
    const glm::mat3 normalMatrix = glm::transpose(glm::inverse(glm::mat3(camera.viewFromWorld)));
    // Tangents lie in the surface: the view's rotation, as the software rasterizer's.
    const glm::mat3 viewRotation{glm::dmat3(camera.viewFromWorld)};
    glUniformMatrix3fv(u.viewRotation, 1, GL_FALSE, &viewRotation[0][0]);
    const glm::mat4 projection = clipFromView(in);
    // GL transforms in float (the software rasterizer in double; docs/opengl.md).
    const glm::mat4 viewFromWorld(camera.viewFromWorld);
    glUniformMatrix4fv(u.viewFromWorld, 1, GL_FALSE, &viewFromWorld[0][0]);
    glUniformMatrix3fv(u.normalMatrix, 1, GL_FALSE, &normalMatrix[0][0]);
    glUniformMatrix4fv(u.clipFromView, 1, GL_FALSE, &projection[0][0]);
  }

  // Draw batch b (the vertex array bound): its material, then its triangles.
  void drawBatch(const Uniforms& u, size_t b, bool metallicRoughness, bool applyNormalMaps) {
    const DrawBatch& d = draws[b];
    setMaterial(u, *d.material, metallicRoughness, applyNormalMaps);
    glUniform1i(u.firstTriangle, GLint(d.firstTriangle));
    glUniform1i(u.batch, GLint(b));
    glDrawElements(GL_TRIANGLES, GLsizei(d.triangles * 3), GL_UNSIGNED_INT,
                   reinterpret_cast<const void*>(size_t(d.firstTriangle) * 3 * sizeof(uint32_t)));
  }

  // ---- Forward passes ----------------------------------------------------------------------

  void buildForward() {
    if (forwardVariants[0]) return;
    if (epoxy_gl_version() < 43)
      throw Error("OpenGL " + EglContext::shared().version() +
                  " has no shader storage buffers (OpenGL 4.3), which forward shading needs");
    depthProgram = gl::buildProgram("gbuffer.vert", "depth_only.frag", defines());
    du = uniformsOf(depthProgram);
    forwardVariants[0] = gl::buildProgram("gbuffer.vert", "tiled_forward.frag",
                                          defines() + "#define TS_HAS_SHADOWS 0\n");
    variantUniforms[0] = uniformsOf(forwardVariants[0]);
    glUniform1i(glGetUniformLocation(forwardVariants[0], "u_transparent"), 0);
    glUniform1i(glGetUniformLocation(forwardVariants[0], "u_visibleTriangle"),
                kVisibleTriangleUnit);
    glUniform1i(glGetUniformLocation(forwardVariants[0], "u_visibleTriangleMS"),
                kVisibleTriangleMSUnit);
    selectForward(false);
    glGenBuffers(kForwardStorages, storage);
    if (!timer) glGenQueries(1, &timer);
    gl::checkErrors("setting up the forward programs");
  }

  // ---- Shadow maps ------------------------------------------------------------------------

  // The depth pre-pass's shaders (OpenGL 3.3: no storage buffers), their linear depth output
  // (location 1) into the atlas.
  void buildShadow() {
    shadowProgram = gl::buildProgram("gbuffer.vert", "depth_only.frag", defines());
    su = uniformsOf(shadowProgram);
    if (!timer) glGenQueries(1, &timer);
    gl::checkErrors("setting up the shadow-map program");
  }

  // The atlas bound, its only colour target fed by output location 1, the G-buffer pass's
  // fixed-function state plus the scissor (each face clears and draws its rectangle only).
  void shadowPassState() {
    glBindFramebuffer(GL_FRAMEBUFFER, shadowTargets.framebuffer);
    const GLenum buffers[2] = {GL_NONE, GL_COLOR_ATTACHMENT0};
    glDrawBuffers(2, buffers);
    glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_GREATER);
    glDepthMask(GL_TRUE);
    glDisable(GL_CULL_FACE);  // nothing is culled, as in the software maps
    glFrontFace(GL_CW);
    glDisable(GL_BLEND);
    glDisable(GL_DITHER);
    glDisable(GL_STENCIL_TEST);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glUseProgram(shadowProgram);
    glBindVertexArray(vao);
  }

  // One face: its rectangle cleared to far (linear depth zfar, window depth of the far plane),
  // then the batches its frustum touches. Returns the triangles drawn.
  uint64_t drawShadowFace(const ShadowFace& f) {
    glViewport(f.x, f.y, f.size, f.size);
    glScissor(f.x, f.y, f.size, f.size);
    const GLfloat far[4] = {GLfloat(f.view.zfar), 0.0f, 0.0f, 0.0f};
    glClearBufferfv(GL_COLOR, 1, far);
    const GLfloat farDepth = farWindowDepth(f.view);
    glClearBufferfv(GL_DEPTH, 0, &farDepth);
    // In float, as the G-buffer's view transform (docs/opengl.md).
    const glm::mat4 viewFromWorld(f.view.viewFromWorld), projection = clipFromFaceView(f.view);
    glUniformMatrix4fv(su.viewFromWorld, 1, GL_FALSE, &viewFromWorld[0][0]);
    glUniformMatrix4fv(su.clipFromView, 1, GL_FALSE, &projection[0][0]);
    uint64_t triangles = 0;
    for (size_t b = 0; b < draws.size(); ++b)
      if (touchesFace(draws[b].bounds, f)) {
        drawBatch(su, b, false, false);
        triangles += draws[b].triangles;
      }
    return triangles;
  }

  // The forward shader with kernels/shadows.h (TS_HAS_SHADOWS), its atlas on kShadowAtlasUnit.
  void buildShadowForward() {
    if (forwardVariants[1]) return;
    forwardVariants[1] = gl::buildProgram("gbuffer.vert", "tiled_forward.frag",
                                          defines() + "#define TS_HAS_SHADOWS 1\n");
    variantUniforms[1] = uniformsOf(forwardVariants[1]);
    glUniform1i(glGetUniformLocation(forwardVariants[1], "u_shadowAtlas"), kShadowAtlasUnit);
    glUniform1i(glGetUniformLocation(forwardVariants[1], "u_visibleTriangle"),
                kVisibleTriangleUnit);
    glUniform1i(glGetUniformLocation(forwardVariants[1], "u_visibleTriangleMS"),
                kVisibleTriangleMSUnit);
    glGenTextures(1, &shadowAtlas);
    gl::checkErrors("setting up the forward program with shadows");
  }

  void selectForward(bool shadows) {
    forwardProgram = forwardVariants[shadows ? 1 : 0];
    fu = variantUniforms[shadows ? 1 : 0];
  }

  // The forward shader as the capture pass (TS_CAPTURE), built on first use.
  void buildCapture() {
    if (captureProgram) return;
    captureProgram = gl::buildProgram("gbuffer.vert", "tiled_forward.frag",
                                      defines(true) + "#define TS_HAS_SHADOWS 0\n");
    cu = uniformsOf(captureProgram);
    // Unused here, but no two sampler types may share a unit (the material textures' 0..).
    glUniform1i(glGetUniformLocation(captureProgram, "u_visibleTriangle"), kVisibleTriangleUnit);
    glUniform1i(glGetUniformLocation(captureProgram, "u_visibleTriangleMS"),
                kVisibleTriangleMSUnit);
    gl::checkErrors("setting up the capture program");
  }

  // Colour 0: the shaded image (RGBA32F); colour 1: the pre-pass's linear depth (R32F); colour 2:
  // the draw batch of each pixel's surface (R32I, forward and forward-single); colour 3: its
  // triangle (R32I, forward's base pass); the reversed float depth buffer of the G-buffer pass.
  // samples > 1 (--msaa): all of them multisampled, shaded per fragment, resolved by readForward.
  void ensureForwardFramebuffer(int w, int h, int samples) {
    forwardTargets.ensure(w, h, {GL_RGBA32F, GL_R32F, GL_R32I, GL_R32I},
                          "forward framebuffer (RGBA32F, R32F, R32I, R32I, float depth)", samples);
  }

  // The base pass's triangle per pixel into visibleTriangles, bound for the light passes: a
  // texture they do not draw into (sampling an attached one would be a feedback loop).
  // With --msaa the texture is multisampled as the target (one triangle per sample), read by
  // u_visibleTriangleMS.
  void keepVisibleTriangles(int w, int h) {
    const int samples = forwardTargets.samples;
    const GLenum target = forwardTargets.textureTarget();
    if (!visibleTriangles || visibleWidth != w || visibleHeight != h || visibleSamples != samples) {
      if (visibleTriangles) glDeleteTextures(1, &visibleTriangles);
      glGenTextures(1, &visibleTriangles);
      glBindTexture(target, visibleTriangles);
      if (samples > 1) {
        glTexStorage2DMultisample(target, samples, GL_R32I, w, h, GL_TRUE);
      } else {
        glTexStorage2D(GL_TEXTURE_2D, 1, GL_R32I, w, h);
        // An integer texture is complete only with NEAREST filters.
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
      }
      visibleWidth = w;
      visibleHeight = h;
      visibleSamples = samples;
    }
    glCopyImageSubData(forwardTargets.colour[3], target, 0, 0, 0, 0, visibleTriangles, target, 0, 0,
                       0, 0, w, h, 1);
    glActiveTexture(
        GLenum(GL_TEXTURE0 + (samples > 1 ? kVisibleTriangleMSUnit : kVisibleTriangleUnit)));
    glBindTexture(target, visibleTriangles);
    glActiveTexture(GL_TEXTURE0);  // the unit every other texture binding assumes
  }

  // The fixed-function state of a pass over the scene (as draw() sets it for the G-buffer).
  void passState(const CameraIntrinsics& in) {
    glBindFramebuffer(GL_FRAMEBUFFER, forwardTargets.framebuffer);
    glViewport(0, 0, in.width, in.height);
    glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    glEnable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glFrontFace(GL_CW);
    glDisable(GL_BLEND);
    glDisable(GL_DITHER);
    glDisable(GL_SCISSOR_TEST);
    glDisable(GL_STENCIL_TEST);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  }

  void clearDepth(const CameraIntrinsics& in) {
    const GLfloat farDepth = in.znear / in.zfar;
    glDepthMask(GL_TRUE);
    glClearBufferfv(GL_DEPTH, 0, &farDepth);
  }

  // A pass's time: the host's wall clock from an idle pipeline to the pass's completion (glFinish
  // on both sides), and the GL timer query of the same commands. On llvmpipe the query measured
  // the submission only (30 ms for a pass that took seconds: it rasterizes later, at the flush),
  // so the wall time is the pass's row; queryMs is kept beside it (a GPU's own clock).
  double timed(const std::function<void()>& pass, double& queryMs) {
    glFinish();
    const auto t0 = Clock::now();
    glBeginQuery(GL_TIME_ELAPSED, timer);
    pass();
    glEndQuery(GL_TIME_ELAPSED);
    glFinish();
    const double wallMs = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    GLuint64 ns = 0;
    glGetQueryObjectui64v(timer, GL_QUERY_RESULT, &ns);
    queryMs = double(ns) * 1e-6;
    return wallMs;
  }

  void storageData(int binding, const void* data, size_t bytes) {
    static const uint32_t kZero[4] = {0, 0, 0, 0};
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, storage[binding]);
    // An empty array is one zero element, never read (an SSBO may not be empty).
    glBufferData(GL_SHADER_STORAGE_BUFFER, GLsizeiptr(bytes ? bytes : sizeof kZero),
                 bytes ? data : kZero, GL_STREAM_DRAW);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, GLuint(binding), storage[binding]);
  }
  template <typename T>
  void storeVector(int binding, const std::vector<T>& v) {
    storageData(binding, v.data(), v.size() * sizeof(T));
  }
  // Into buffer `buffer`, bound at `binding` (a buffer that is not a binding's own).
  template <typename T>
  void storeVectorAt(int buffer, int binding, const std::vector<T>& v) {
    static const uint32_t kZero[4] = {0, 0, 0, 0};
    const size_t bytes = v.size() * sizeof(T);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, storage[buffer]);
    glBufferData(GL_SHADER_STORAGE_BUFFER, GLsizeiptr(bytes ? bytes : sizeof kZero),
                 bytes ? static_cast<const void*>(v.data()) : kZero, GL_STREAM_DRAW);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, GLuint(binding), storage[buffer]);
  }

  // The frame's lights into shader storage (the directional ones where the features shade them);
  // returns the directional count.
  int uploadLights(const ForwardLighting& lighting) {
    const ViewLights& lights = *lighting.lights;
    storeVector(kPosRange, lights.positionRange);
    storeVector(kColor, lights.color);
    storeVector(kSpot, lights.spot);
    std::vector<glm::vec4> directional;
    if (lighting.features.directional)
      for (size_t k = 0; k < lights.directionalCount(); ++k) {
        directional.push_back(lights.directionalDir[k]);
        directional.push_back(lights.directionalColor[k]);
      }
    storeVector(kDirectional, directional);
    return int(directional.size() / 2);
  }

  // A frame with shadow-casting lights (the TS_HAS_SHADOWS variant in use): the lights' first
  // faces, the face table and the atlas, as DeviceFrame::upload gives them to the kernels.
  // Returns the upload's time (host clock, glFinish after it), 0 without shadows.
  double uploadShadows(const ViewLights& lights) {
    if (!lights.hasShadows()) return 0.0;
    const auto t0 = Clock::now();
    std::vector<int32_t> first(lights.size()), directionalFirst(lights.directionalCount());
    for (size_t i = 0; i < first.size(); ++i) first[i] = lights.shadowOf(i);
    for (size_t k = 0; k < directionalFirst.size(); ++k)
      directionalFirst[k] = lights.directionalShadowOf(k);
    storeVector(kLightShadow, first);
    storeVector(kDirectionalShadow, directionalFirst);
    storeVector(kShadowFaces, lights.shadowFaces);
    const size_t texels = lights.shadowAtlas ? lights.shadowAtlas->size() : 0;
    const int width = lights.shadowAtlasWidth;
    if (width < 1 || texels == 0 || texels % size_t(width) != 0)
      throw Error("the shadow atlas does not match its width " + std::to_string(width));
    const size_t height = texels / size_t(width);
    GLint maxTexture = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxTexture);
    if (width > maxTexture || height > size_t(maxTexture))
      throw Error("the shadow atlas is " + std::to_string(width) + "x" + std::to_string(height) +
                  " texels, beyond this OpenGL implementation's texture limit " +
                  std::to_string(maxTexture) + " (lower --shadow-budget or --shadow-map-size)");
    glActiveTexture(GLenum(GL_TEXTURE0 + kShadowAtlasUnit));
    glBindTexture(GL_TEXTURE_2D, shadowAtlas);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    // Row 0 of the atlas is texture row 0: texelFetch's (x, y) is the kernels' y * width + x.
    glTexImage2D(GL_TEXTURE_2D, 0, GL_R32F, width, GLsizei(height), 0, GL_RED, GL_FLOAT,
                 lights.shadowAtlas->data());
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_BASE_LEVEL, 0);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);
    glActiveTexture(GL_TEXTURE0);  // the unit every other texture binding assumes
    glFinish();                    // the copy is done before the draw's clock starts
    gl::checkErrors("uploading the shadow maps");
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  }

  // Where the lists are the draws', the tiles only spread the work counters: bins unused (0),
  // counters cleared. Returns the tile count.
  size_t uploadWorkTiles(int w, int h) {
    const size_t tiles =
        size_t((w + kWorkTile - 1) / kWorkTile) * ((h + kWorkTile - 1) / kWorkTile);
    storeVector(kTileBins, std::vector<glm::uvec2>(tiles, glm::uvec2(0)));
    storeVector(kTileWork, std::vector<uint32_t>(tiles, 0));
    return tiles;
  }

  GLint forwardUniform(const char* name) const {
    return glGetUniformLocation(forwardProgram, name);
  }

  // The forward program in use with the uniforms every forward pass shares. tiles: the tile
  // width, height and tiles per row of the light grid (or of the work counters).
  void setForwardUniforms(const ForwardLighting& lighting, int directionals, glm::ivec3 tiles) {
    glUseProgram(forwardProgram);
    const SceneFeatures& f = lighting.features;
    const bool metallicRoughness = f.model == ShadingModel::MetallicRoughness;
    glUniform3fv(forwardUniform("u_ambient"), 1, &lighting.ambient.x);
    glUniform1i(forwardUniform("u_dirLightCount"), GLint(directionals));
    glUniform3i(forwardUniform("u_tiles"), tiles.x, tiles.y, tiles.z);
    glUniform1i(forwardUniform("u_model"), lighting.rangeModel);
    glUniform1i(forwardUniform("u_shading"), int(f.model));
    glUniform1i(forwardUniform("u_specularOn"), f.specular || metallicRoughness ? 1 : 0);
    glUniform1i(forwardUniform("u_spotOn"), f.spot ? 1 : 0);
    glUniform1i(forwardUniform("u_emissiveOn"), f.emissive ? 1 : 0);
    glUniform1i(forwardUniform("u_visibleOnly"), 0);
    glUniform1i(forwardUniform("u_samples"), forwardTargets.samples);
    glUniform3f(forwardUniform("u_slicing"), 1.0f, 1.0f, 0.0f);  // tile lists (tiledForward sets)
  }

  // The image target drawn and cleared to 0 (the background); with batchIds also the batch
  // target, with triangleIds also the triangle target, cleared to -1 (no surface).
  void clearImage(bool batchIds = false, bool triangleIds = false) {
    const GLenum buffers[4] = {GL_COLOR_ATTACHMENT0, GL_NONE, GL_COLOR_ATTACHMENT2,
                               GL_COLOR_ATTACHMENT3};
    glDrawBuffers(triangleIds ? 4 : batchIds ? 3 : 1, buffers);
    const GLfloat zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    glClearBufferfv(GL_COLOR, 0, zero);
    const GLint none[4] = {-1, -1, -1, -1};
    if (batchIds || triangleIds) glClearBufferiv(GL_COLOR, 2, none);
    if (triangleIds) glClearBufferiv(GL_COLOR, 3, none);
  }

  // The forward image and the shader's lighting computations (its per-tile counters) back; with
  // batchIds the batch of each pixel's surface too.
  // With --msaa the image resolved by OpenGL (glBlitFramebuffer, the implementation's resolve)
  // and the batch ids per sample (ForwardImage::pixelBatch).
  void readForward(ForwardImage& out, int w, int h, size_t tiles, bool batchIds = false) {
    const size_t n = size_t(w) * size_t(h);
    const int samples = forwardTargets.samples;
    out.image.resize(n);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    if (samples > 1) {
      ensureResolveFramebuffer(w, h);
      glBindFramebuffer(GL_READ_FRAMEBUFFER, forwardTargets.framebuffer);
      glReadBuffer(GL_COLOR_ATTACHMENT0);
      glBindFramebuffer(GL_DRAW_FRAMEBUFFER, resolveTargets.framebuffer);
      const GLenum image[1] = {GL_COLOR_ATTACHMENT0};
      glDrawBuffers(1, image);
      glBlitFramebuffer(0, 0, w, h, 0, 0, w, h, GL_COLOR_BUFFER_BIT, GL_NEAREST);
      glBindFramebuffer(GL_FRAMEBUFFER, resolveTargets.framebuffer);
      gl::checkErrors("resolving the multisampled forward image");
    }
    glBindTexture(GL_TEXTURE_2D, (samples > 1 ? resolveTargets : forwardTargets).colour[0]);
    glGetTexImage(GL_TEXTURE_2D, 0, GL_RGBA, GL_FLOAT, out.image.data());
    if (batchIds) {
      out.pixelBatch.resize(n * size_t(samples));
      for (int k = 0; k < samples; ++k) {
        if (samples > 1) fetchSample(forwardTargets, 2, true, k, resolveTargets, 2);
        glBindTexture(GL_TEXTURE_2D, (samples > 1 ? resolveTargets : forwardTargets).colour[2]);
        glGetTexImage(GL_TEXTURE_2D, 0, GL_RED_INTEGER, GL_INT, out.pixelBatch.data() + n * k);
      }
    }
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<uint32_t> counted(tiles);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, storage[kTileWork]);
    glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, GLsizeiptr(tiles * 4), counted.data());
    for (uint32_t c : counted) out.lightingComputations += c;
    gl::checkErrors("reading back the forward image");
  }

  // Lists whose entries index `targets` things, packed as IndexLists says.
  static void checkLists(const IndexLists& lists, size_t targets, const char* what) {
    if (lists.offsets.size() != lists.size())
      throw Error(std::string(what) + "s: offsets and counts differ in length");
    for (size_t o = 0; o < lists.size(); ++o) {
      if (size_t(lists.offsets[o]) + lists.counts[o] > lists.items.size())
        throw Error(std::string(what) + " runs past the packed lists");
      for (uint32_t k = 0; k < lists.counts[o]; ++k)
        if (lists.items[lists.offsets[o] + k] >= targets)
          throw Error(std::string(what) + " names entry " +
                      std::to_string(lists.items[lists.offsets[o] + k]) + " of " +
                      std::to_string(targets));
    }
  }

  template <typename T>
  void readTarget(int target, GLenum format, GLenum type, std::vector<T>& out) {
    // glGetTexImage of the attachment: on llvmpipe ~8x faster than glReadPixels (which takes a
    // generic conversion path for float formats), and the same bytes.
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glBindTexture(GL_TEXTURE_2D, gbufferTargets.colour[size_t(target)]);
    glGetTexImage(GL_TEXTURE_2D, 0, format, type, out.data());
  }

  void readBack(GBuffer& g, const RasterOptions& options) {
    readTarget(kDepth, GL_RED, GL_FLOAT, g.depth);
    readTarget(kNormal, GL_RGBA, GL_FLOAT, g.normal);
    readTarget(kDiffuse, GL_RGBA, GL_FLOAT, g.diffuse);
    readTarget(kSpecular, GL_RGBA, GL_FLOAT, g.specular);
    readTarget(kEmissive, GL_RGBA, GL_FLOAT, g.emissive);
    if (options.triangleIds) {
      g.triangleId.assign(g.pixelCount(), -1);
      readTarget(kTriangle, GL_RED_INTEGER, GL_INT, g.triangleId);
    }
    gl::checkErrors("reading back the G-buffer");
  }
};

GlRasterizer::GlRasterizer(const Scene& scene) : state_(std::make_unique<State>(scene)) {
  const auto t0 = Clock::now();
  validateForRaster(scene);
  EglContext& context = EglContext::shared();
  context.makeCurrent();
  gl::checkErrors("making the context current");  // clears errors left by anyone else
  GLint viewport[2] = {0, 0}, renderbuffer = 0, texture = 0;
  glGetIntegerv(GL_MAX_VIEWPORT_DIMS, viewport);
  glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &renderbuffer);
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &texture);
  state_->maxSize = std::min({viewport[0], viewport[1], renderbuffer, texture});
  state_->draws = drawBatches(scene);
  if (!scene.tangents.empty())
    for (const DrawBatch& d : state_->draws) state_->normalMaps |= d.material->normalTexture >= 0;
  try {
    state_->buildProgram();
    state_->upload();
    // A first small frame: drivers compile shader variants on first use (llvmpipe's JIT takes
    // ~100 ms), which belongs to setup, not to the first frame's time.
    SceneCamera warmup;
    rasterize(warmup, 8, 8, RasterOptions{});
  } catch (...) {
    state_.reset();
    throw;
  }
  setupMs_ = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

GlRasterizer::~GlRasterizer() = default;

void GlRasterizer::warmUpForward(bool shadows) {
  if (!state_->forwardVariants[0]) {
    state_->buildForward();
    warmUpPasses(ViewLights{});
  }
  if (shadows && !state_->forwardVariants[1]) {
    state_->buildShadowForward();
    // The same frames with one 1-texel face (never sampled: the light is out of reach), so the
    // TS_HAS_SHADOWS variant is selected and compiled.
    ViewLights shadowed;
    shadowed.shadowFaces.assign(TS_SHADOW_FACE_RECORDS, glm::vec4(0.0f));
    shadowed.shadowFaces.back() = glm::vec4(1.0f, 1.0f, 0.0f, 0.0f);  // one tap, one face
    shadowed.shadowAtlas = std::make_shared<const std::vector<float>>(1, 0.0f);
    shadowed.shadowAtlasWidth = 1;
    warmUpPasses(shadowed);
  }
}

void GlRasterizer::warmUpPasses(const ViewLights& none) {
  // First small frames of each pass: drivers compile shader variants on first use (llvmpipe's
  // JIT: hundreds of ms for the forward shader, again for the EQUAL variant), which belongs to
  // setup, not to the first frame's pass times.
  SceneCamera warmup;
  ForwardLighting lighting;
  lighting.lights = &none;
  ForwardLightGrid grid;
  grid.tileW = grid.tileH = 8;
  grid.tilesX = grid.tilesY = 1;
  grid.offsets = grid.counts = {0};
  double ms = 0.0;
  depthPrepass(warmup, 8, 8, 1, ms);
  tiledForward(warmup, 8, 8, lighting, grid, true, nullptr);
  tiledForward(warmup, 8, 8, lighting, grid, false, nullptr);
  // forward's blended light pass (a light far away, drawn with the first batch) and
  // forward-single's draw lists.
  ViewLights one = none;
  one.addPoint(glm::vec3(0.0f, 0.0f, 1e6f), 1.0f, glm::vec3(1.0f));
  if (none.hasShadows()) one.shadow.back() = 0;
  lighting.lights = &one;
  IndexLists lists;
  lists.offsets = {0};
  lists.counts = {state_->draws.empty() ? 0u : 1u};
  lists.items.assign(lists.counts[0], 0);
  multiPassForward(warmup, 8, 8, lighting, lists);
  IndexLists emptyLists;
  emptyLists.offsets.assign(state_->draws.size(), 0);
  emptyLists.counts.assign(state_->draws.size(), 0);
  lighting.lights = &none;
  singlePassForward(warmup, 8, 8, lighting, emptyLists);
}

void GlRasterizer::warmUpShadows() {
  State& s = *state_;
  if (s.shadowProgram) return;
  s.buildShadow();
  // A first small face (the scene seen from its centre): llvmpipe compiles the program's variants
  // on first use, which belongs to setup, not to the first frame's map time.
  s.shadowTargets.ensure(kShadowMinFaceSize, kShadowMinFaceSize, {GL_R32F},
                         "shadow atlas framebuffer (R32F, float depth)");
  s.shadowPassState();
  glEnable(GL_SCISSOR_TEST);
  ShadowFace face;
  face.size = kShadowMinFaceSize;
  const Bounds b = s.scene.bounds();
  const glm::dvec3 centre =
      b.min.x <= b.max.x ? (glm::dvec3(b.min) + glm::dvec3(b.max)) * 0.5 : glm::dvec3(0.0);
  face.view.viewFromWorld = glm::translate(glm::dmat4(1.0), -centre);
  s.drawShadowFace(face);
  glDisable(GL_SCISSOR_TEST);
  glBindVertexArray(0);
  glFinish();
  gl::checkErrors("warming up the shadow-map program");
}

ShadowAtlas GlRasterizer::drawShadowAtlas(ShadowAtlasLayout layout) {
  ShadowAtlas atlas;
  atlas.rasterizer = "gl";
  atlas.layout = std::move(layout);
  const ShadowAtlasLayout& l = atlas.layout;
  atlas.depth.assign(size_t(l.width) * size_t(l.height), 0.0f);
  atlas.faceTriangles.assign(l.faces.size(), 0);
  if (l.faces.empty()) return atlas;
  State& s = *state_;
  if (l.width > s.maxSize || l.height > s.maxSize)
    throw Error("--raster gl: the " + std::to_string(l.width) + "x" + std::to_string(l.height) +
                " shadow atlas exceeds this OpenGL implementation's limit of " +
                std::to_string(s.maxSize) +
                " texels per side (lower --shadow-budget or --shadow-map-size, or use --raster "
                "software)");
  EglContext::shared().makeCurrent();
  warmUpShadows();
  s.shadowTargets.ensure(l.width, l.height, {GL_R32F},
                         "shadow atlas framebuffer (R32F, float depth)");
  s.shadowPassState();
  double queryMs = 0.0;
  atlas.drawMs = s.timed(
      [&] {
        glDisable(GL_SCISSOR_TEST);
        const GLfloat zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
        glClearBufferfv(GL_COLOR, 1, zero);  // texels of no face hold 0
        glEnable(GL_SCISSOR_TEST);
        for (size_t k = 0; k < l.faces.size(); ++k)
          atlas.faceTriangles[k] = s.drawShadowFace(l.faces[k]);
        glDisable(GL_SCISSOR_TEST);
      },
      queryMs);
  glBindVertexArray(0);
  gl::checkErrors("drawing the shadow maps of scene '" + s.scene.name + "'");
  const auto t0 = Clock::now();
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glBindTexture(GL_TEXTURE_2D, s.shadowTargets.colour[0]);
  glGetTexImage(GL_TEXTURE_2D, 0, GL_RED, GL_FLOAT, atlas.depth.data());
  gl::checkErrors("reading back the shadow atlas");
  atlas.readMs = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  return atlas;
}

std::vector<float> GlRasterizer::depthPrepass(const SceneCamera& camera, int width, int height,
                                              int samples, double& ms) {
  const CameraIntrinsics in = CameraIntrinsics::from(camera, width, height);
  if (width > state_->maxSize || height > state_->maxSize)
    throw Error("--raster gl: " + std::to_string(width) + "x" + std::to_string(height) +
                " exceeds this OpenGL implementation's limit");
  EglContext::shared().makeCurrent();
  State& s = *state_;
  warmUpForward(false);
  s.ensureForwardFramebuffer(width, height, samples);
  s.passState(in);
  // Colour 1: the linear depth; colour 3: each pixel's visible triangle (-1: none), which the
  // forward pass's u_visibleOnly reads.
  const GLenum buffers[4] = {GL_NONE, GL_COLOR_ATTACHMENT1, GL_NONE, GL_COLOR_ATTACHMENT3};
  glDrawBuffers(4, buffers);
  const GLfloat zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
  glClearBufferfv(GL_COLOR, 1, zero);
  const GLint none[4] = {-1, -1, -1, -1};
  glClearBufferiv(GL_COLOR, 3, none);
  s.clearDepth(in);
  glDepthFunc(GL_GREATER);
  glUseProgram(s.depthProgram);
  double queryMs = 0.0;
  ms = s.timed([&] { s.drawScene(s.du, camera, in, false, false); }, queryMs);
  gl::checkErrors("the depth pre-pass of scene '" + s.scene.name + "'");
  // Sample-major with --msaa: plane k is sample k's depth (the fragment's, at its interpolation
  // point: what the forward pass shades that sample's surface at).
  const size_t n = size_t(width) * size_t(height);
  std::vector<float> depth(n * size_t(samples));
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  if (samples > 1) s.ensureResolveFramebuffer(width, height);
  for (int k = 0; k < samples; ++k) {
    if (samples > 1) s.fetchSample(s.forwardTargets, 1, false, k, s.resolveTargets, 1);
    glBindTexture(GL_TEXTURE_2D, (samples > 1 ? s.resolveTargets : s.forwardTargets).colour[1]);
    glGetTexImage(GL_TEXTURE_2D, 0, GL_RED, GL_FLOAT, depth.data() + n * size_t(k));
  }
  gl::checkErrors("reading back the pre-pass depth");
  return depth;
}

// Throws ts::Error unless `grid` tiles a width x height frame.
static void checkGrid(const ForwardLightGrid& grid, int width, int height) {
  const size_t bins = size_t(grid.tilesX) * size_t(grid.tilesY) * size_t(std::max(grid.slices, 0));
  if (grid.tileW < 1 || grid.tileH < 1 || grid.slices < 1 ||
      grid.tilesX != (width + grid.tileW - 1) / grid.tileW ||
      grid.tilesY != (height + grid.tileH - 1) / grid.tileH || grid.offsets.size() != bins ||
      grid.counts.size() != bins)
    throw Error("tiled forward: the light grid does not match the " + std::to_string(width) + "x" +
                std::to_string(height) + " frame");
}

ForwardImage GlRasterizer::tiledForward(const SceneCamera& camera, int width, int height,
                                        const ForwardLighting& lighting,
                                        const ForwardLightGrid& grid, bool depthEqual,
                                        const ForwardLightGrid* transparentGrid) {
  const CameraIntrinsics in = CameraIntrinsics::from(camera, width, height);
  const size_t tiles = size_t(grid.tilesX) * size_t(grid.tilesY);
  if (!lighting.lights) throw Error("tiled forward: no lights");
  checkGrid(grid, width, height);
  if (transparentGrid) {
    checkGrid(*transparentGrid, width, height);
    if (transparentGrid->tileW != grid.tileW || transparentGrid->tileH != grid.tileH)
      throw Error("tiled forward: the transparent pass's grid has other tiles than the opaque's");
  }
  State& s = beginForward(width, height, lighting.lights->hasShadows());
  if (depthEqual && (s.forwardTargets.width != width || s.forwardTargets.height != height ||
                     s.forwardTargets.samples != lighting.samples))
    throw Error(
        "tiled forward with depth EQUAL needs a depth pre-pass of the same size and samples "
        "first");
  s.ensureForwardFramebuffer(width, height, lighting.samples);

  ForwardImage out;
  const auto t0 = Clock::now();
  const int directionals = s.uploadLights(lighting);
  std::vector<glm::uvec2> bins(grid.offsets.size());  // tiles, or clusters
  for (size_t t = 0; t < bins.size(); ++t) bins[t] = {grid.offsets[t], grid.counts[t]};
  s.storeVector(kTileBins, bins);
  s.storeVector(kTileLights, grid.lights);
  if (transparentGrid) {
    if (transparentGrid->slices != grid.slices)
      throw Error("tiled forward: the transparent pass's grid has other slices than the opaque's");
    for (size_t t = 0; t < bins.size(); ++t)
      bins[t] = {transparentGrid->offsets[t], transparentGrid->counts[t]};
    s.storeVectorAt(kGlassBins, kTileBins, bins);
    s.storeVectorAt(kGlassLights, kTileLights, transparentGrid->lights);
    // The opaque pass's grid bound again (storeVectorAt bound the transparent one).
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kTileBins, s.storage[kTileBins]);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kTileLights, s.storage[kTileLights]);
  }
  const std::vector<uint32_t> work(tiles, 0);
  s.storeVector(kTileWork, work);
  gl::checkErrors("uploading the lights and the light grid");
  out.uploadMs = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  out.shadowUploadMs = s.uploadShadows(*lighting.lights);

  s.setForwardUniforms(lighting, directionals, {grid.tileW, grid.tileH, grid.tilesX});
  glUniform3f(s.forwardUniform("u_slicing"), float(grid.slices), grid.sliceNear, grid.sliceScale);
  glUniform1i(s.forwardUniform("u_drawList"), 0);
  glUniform1i(s.forwardUniform("u_baseTerms"), 1);
  const bool metallicRoughness = lighting.features.model == ShadingModel::MetallicRoughness;

  s.passState(in);
  s.clearImage();
  if (depthEqual) {
    // EQUAL and the pre-pass's triangle: coplanar faces drawn twice pass EQUAL both, and the
    // later would overwrite the one the pre-pass (and the G-buffer pass) kept.
    glDepthFunc(GL_EQUAL);
    glDepthMask(GL_FALSE);
    s.keepVisibleTriangles(width, height);
    glUniform1i(s.forwardUniform("u_visibleOnly"), 1);
  } else {
    s.clearDepth(in);
    glDepthFunc(GL_GREATER);
  }
  out.drawMs = s.timed(
      [&] { s.drawScene(s.fu, camera, in, metallicRoughness, lighting.features.normalMaps); },
      out.queryMs);
  out.draws = s.draws.size() - s.backToFront(camera).size();
  glDepthMask(GL_TRUE);
  glUniform1i(s.forwardUniform("u_visibleOnly"), 0);
  gl::checkErrors("the tiled forward pass of scene '" + s.scene.name + "'");
  if (transparentGrid) {
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kTileBins, s.storage[kGlassBins]);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kTileLights, s.storage[kGlassLights]);
  }
  s.drawTransparent(camera, in, lighting, directionals, {}, out);
  s.readForward(out, width, height, tiles);
  return out;
}

ForwardImage GlRasterizer::transparentOver(const SceneCamera& camera, int width, int height,
                                           const ForwardLighting& lighting,
                                           const std::vector<glm::vec4>& opaque,
                                           const ForwardLightGrid& grid) {
  const CameraIntrinsics in = CameraIntrinsics::from(camera, width, height);
  if (!lighting.lights) throw Error("the transparent pass: no lights");
  if (lighting.samples != 1)
    throw Error("the transparent pass over a deferred image is not done with --msaa " +
                std::to_string(lighting.samples));
  checkGrid(grid, width, height);
  if (opaque.size() != size_t(width) * size_t(height))
    throw Error("the transparent pass: the opaque image does not match the " +
                std::to_string(width) + "x" + std::to_string(height) + " frame");
  State& s = beginForward(width, height, lighting.lights->hasShadows());
  s.ensureForwardFramebuffer(width, height, 1);

  ForwardImage out;
  glFinish();
  auto t0 = Clock::now();
  out.depthRedrawn = s.opaqueBackground(camera, in, opaque);
  glFinish();
  out.imageCopyMs = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();

  t0 = Clock::now();
  const int directionals = s.uploadLights(lighting);
  const size_t tiles = size_t(grid.tilesX) * size_t(grid.tilesY);
  std::vector<glm::uvec2> bins(tiles);
  for (size_t t = 0; t < tiles; ++t) bins[t] = {grid.offsets[t], grid.counts[t]};
  s.storeVector(kTileBins, bins);
  s.storeVector(kTileLights, grid.lights);
  s.storeVector(kTileWork, std::vector<uint32_t>(tiles, 0));
  gl::checkErrors("uploading the lights and the transparent pass's light grid");
  out.uploadMs = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  out.shadowUploadMs = s.uploadShadows(*lighting.lights);

  s.setForwardUniforms(lighting, directionals, {grid.tileW, grid.tileH, grid.tilesX});
  glUniform1i(s.forwardUniform("u_drawList"), 0);
  s.passState(in);
  s.drawTransparent(camera, in, lighting, directionals, {}, out);
  s.readForward(out, width, height, tiles);
  return out;
}

ForwardImage GlRasterizer::multiPassForward(const SceneCamera& camera, int width, int height,
                                            const ForwardLighting& lighting,
                                            const IndexLists& lightBatches) {
  const CameraIntrinsics in = CameraIntrinsics::from(camera, width, height);
  if (!lighting.lights || lightBatches.size() != lighting.lights->size())
    throw Error("forward: the lights' batch lists do not match the frame's lights");
  State& s = beginForward(width, height, lighting.lights->hasShadows());
  s.checkLists(lightBatches, s.draws.size(), "a light's batch list");
  s.ensureForwardFramebuffer(width, height, lighting.samples);

  ForwardImage out;
  const auto t0 = Clock::now();
  const int directionals = s.uploadLights(lighting);
  // The lights that have a pass, in index order: pass p shades passLights[p] (u_list = (p, 1)).
  std::vector<uint32_t> passLights;
  for (size_t i = 0; i < lightBatches.size(); ++i)
    if (lightBatches.counts[i] > 0) passLights.push_back(uint32_t(i));
  s.storeVector(kTileLights, passLights);
  const size_t tiles = s.uploadWorkTiles(width, height);
  gl::checkErrors("uploading the lights");
  out.uploadMs = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  out.shadowUploadMs = s.uploadShadows(*lighting.lights);

  const int workTilesX = (width + kWorkTile - 1) / kWorkTile;
  s.setForwardUniforms(lighting, directionals, {kWorkTile, kWorkTile, workTilesX});
  const GLint drawList = s.forwardUniform("u_drawList"), list = s.forwardUniform("u_list"),
              baseTerms = s.forwardUniform("u_baseTerms"),
              dirCount = s.forwardUniform("u_dirLightCount");
  glUniform1i(drawList, 1);
  const bool metallicRoughness = lighting.features.model == ShadingModel::MetallicRoughness;

  // The base pass: ambient, emission and the directional lights, every batch, the depth test of
  // the G-buffer pass (its depth is what the light passes test EQUAL against), each pixel's
  // visible triangle kept.
  s.passState(in);
  s.clearImage(true, true);
  s.clearDepth(in);
  glDepthFunc(GL_GREATER);
  glUniform1i(baseTerms, 1);
  glUniform2ui(list, 0, 0);
  out.baseMs = s.timed(
      [&] { s.drawScene(s.fu, camera, in, metallicRoughness, lighting.features.normalMaps); },
      out.baseQueryMs);
  out.draws = s.draws.size() - s.backToFront(camera).size();
  gl::checkErrors("the forward base pass of scene '" + s.scene.name + "'");

  // One additive pass per light over the batches its sphere touches; EQUAL and the base pass's
  // triangle (u_visibleOnly): only the visible surface of the base pass is shaded, once per pixel
  // and light. EQUAL alone passes every fragment at the visible depth: coplanar faces drawn
  // twice, which the additive blend would sum (issue #17, docs/techniques.md).
  const GLenum image[1] = {GL_COLOR_ATTACHMENT0};
  glDrawBuffers(1, image);
  glDepthFunc(GL_EQUAL);
  glDepthMask(GL_FALSE);
  glEnable(GL_BLEND);
  glBlendEquation(GL_FUNC_ADD);
  glBlendFunc(GL_ONE, GL_ONE);
  glUniform1i(baseTerms, 0);
  glUniform1i(dirCount, 0);
  glUniform1i(s.forwardUniform("u_visibleOnly"), 1);
  out.drawMs = s.timed(
      [&] {
        s.keepVisibleTriangles(width, height);
        s.setCamera(s.fu, camera, in);
        glBindVertexArray(s.vao);
        for (size_t p = 0; p < passLights.size(); ++p) {
          glUniform2ui(list, GLuint(p), 1);
          const uint32_t light = passLights[p];
          for (uint32_t k = 0; k < lightBatches.counts[light]; ++k) {
            const uint32_t b = lightBatches.items[lightBatches.offsets[light] + k];
            if (!s.transparent(b))  // the transparent pass shades those with all their lights
              s.drawBatch(s.fu, b, metallicRoughness, lighting.features.normalMaps);
          }
        }
        glBindVertexArray(0);
      },
      out.queryMs);
  out.passes = passLights.size();
  for (size_t k = 0; k < lightBatches.items.size(); ++k)
    out.draws += s.transparent(lightBatches.items[k]) ? 0 : 1;
  glUniform1i(s.forwardUniform("u_visibleOnly"), 0);
  glDisable(GL_BLEND);
  glDepthMask(GL_TRUE);
  gl::checkErrors("the forward light passes of scene '" + s.scene.name + "'");
  // A blended surface cannot take one additive pass per light (each pass would blend "over"
  // again): each transparent draw is one pass with all the lights its batch touches (the
  // batch lists of batchLights, found per light for the light passes, transposed back).
  if (!s.backToFront(camera).empty()) {
    const IndexLists batchLights = transposeLists(lightBatches, s.draws.size());
    s.storeVector(kTileLights, batchLights.items);
    s.drawTransparent(
        camera, in, lighting, directionals,
        [&](size_t b) { glUniform2ui(list, batchLights.offsets[b], batchLights.counts[b]); }, out);
  }
  s.readForward(out, width, height, tiles, true);
  return out;
}

ForwardImage GlRasterizer::singlePassForward(const SceneCamera& camera, int width, int height,
                                             const ForwardLighting& lighting,
                                             const IndexLists& batchLights) {
  const CameraIntrinsics in = CameraIntrinsics::from(camera, width, height);
  if (!lighting.lights) throw Error("forward-single: no lights given");
  State& s = beginForward(width, height, lighting.lights->hasShadows());
  if (batchLights.size() != s.draws.size())
    throw Error("forward-single: the batches' light lists do not match the scene's " +
                std::to_string(s.draws.size()) + " draw batches");
  s.checkLists(batchLights, lighting.lights->size(), "a batch's light list");
  s.ensureForwardFramebuffer(width, height, lighting.samples);

  ForwardImage out;
  const auto t0 = Clock::now();
  const int directionals = s.uploadLights(lighting);
  s.storeVector(kTileLights, batchLights.items);  // no cap: a list is as long as it is
  const size_t tiles = s.uploadWorkTiles(width, height);
  gl::checkErrors("uploading the lights and the batch lists");
  out.uploadMs = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  out.shadowUploadMs = s.uploadShadows(*lighting.lights);

  const int workTilesX = (width + kWorkTile - 1) / kWorkTile;
  s.setForwardUniforms(lighting, directionals, {kWorkTile, kWorkTile, workTilesX});
  const GLint list = s.forwardUniform("u_list");
  glUniform1i(s.forwardUniform("u_drawList"), 1);
  glUniform1i(s.forwardUniform("u_baseTerms"), 1);
  const bool metallicRoughness = lighting.features.model == ShadingModel::MetallicRoughness;

  s.passState(in);
  s.clearImage(true);
  s.clearDepth(in);
  glDepthFunc(GL_GREATER);
  out.drawMs = s.timed(
      [&] {
        s.setCamera(s.fu, camera, in);
        glBindVertexArray(s.vao);
        for (size_t b = 0; b < s.draws.size(); ++b) {
          if (s.transparent(b)) continue;  // after the opaque ones, back to front
          glUniform2ui(list, batchLights.offsets[b], batchLights.counts[b]);
          s.drawBatch(s.fu, b, metallicRoughness, lighting.features.normalMaps);
        }
        glBindVertexArray(0);
      },
      out.queryMs);
  out.draws = s.draws.size() - s.backToFront(camera).size();
  gl::checkErrors("the forward-single pass of scene '" + s.scene.name + "'");
  // Each transparent draw shades its batch's list, as its opaque neighbours do.
  s.drawTransparent(
      camera, in, lighting, directionals,
      [&](size_t b) { glUniform2ui(list, batchLights.offsets[b], batchLights.counts[b]); }, out);
  s.readForward(out, width, height, tiles, true);
  return out;
}

std::vector<TransparentFragment> GlRasterizer::captureTransparent(const SceneCamera& camera,
                                                                  int width, int height,
                                                                  const SceneFeatures& features,
                                                                  size_t maxFragments) {
  const CameraIntrinsics in = CameraIntrinsics::from(camera, width, height);
  State& s = beginForward(width, height, /*shadows=*/false);  // the capture shades nothing
  const std::vector<uint32_t> order = s.backToFront(camera);
  if (order.empty()) return {};
  s.buildCapture();
  s.ensureForwardFramebuffer(width, height, 1);
  const bool metallicRoughness = features.model == ShadingModel::MetallicRoughness;

  // The opaque depth, as every forward pass leaves it before its transparent pass.
  s.passState(in);
  const GLenum none[1] = {GL_NONE};
  glDrawBuffers(1, none);
  s.clearDepth(in);
  glDepthFunc(GL_GREATER);
  glUseProgram(s.depthProgram);
  s.drawScene(s.du, camera, in, false, false);

  // The transparent draws in their order, depth test on, writes off: nothing drawn, each
  // fragment recorded. A first capacity of two fragments a pixel; an overflow (the counter runs
  // on past it) redraws with room for all, up to the bound.
  glDepthMask(GL_FALSE);
  glUseProgram(s.captureProgram);
  const GLint capacityAt = glGetUniformLocation(s.captureProgram, "u_captureCapacity");
  const GLint orderAt = glGetUniformLocation(s.captureProgram, "u_drawOrder");
  size_t capacity = std::min(maxFragments, std::max<size_t>(1, 2 * size_t(width) * size_t(height)));
  uint32_t count = 0;
  for (;;) {
    const uint32_t zero = 0;
    s.storageData(kCaptureCount, &zero, sizeof zero);
    s.storageData(kCaptured, nullptr, capacity * sizeof(CapturedRecord));
    glUniform1ui(capacityAt, GLuint(capacity));
    s.setCamera(s.cu, camera, in);
    glBindVertexArray(s.vao);
    for (size_t k = 0; k < order.size(); ++k) {
      glUniform1i(orderAt, GLint(k));
      s.drawBatch(s.cu, order[k], metallicRoughness, features.normalMaps);
    }
    glBindVertexArray(0);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, s.storage[kCaptureCount]);
    glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, sizeof count, &count);
    gl::checkErrors("the capture of the transparent fragments of scene '" + s.scene.name + "'");
    if (count <= capacity) break;
    if (count > maxFragments)
      throw Error("the reference's capture of the transparent fragments: " + std::to_string(count) +
                  " fragments pass the depth test, more than its bound of " +
                  std::to_string(maxFragments) + " (" +
                  std::to_string(maxFragments * sizeof(CapturedRecord) >> 20) +
                  " MiB); render a smaller frame");
    capacity = count;
  }
  glDepthMask(GL_TRUE);
  std::vector<CapturedRecord> records(count);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, s.storage[kCaptured]);
  if (count > 0)
    glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, GLsizeiptr(count * sizeof(CapturedRecord)),
                       records.data());
  gl::checkErrors("reading back the transparent fragments");
  std::vector<TransparentFragment> out(count);
  for (size_t i = 0; i < count; ++i) {
    const CapturedRecord& r = records[i];
    TransparentFragment& f = out[i];
    f.x = r.x;
    f.y = r.y;
    f.order = r.order;
    if (r.order < 0 || size_t(r.order) >= order.size())
      throw Error("the capture of the transparent fragments recorded draw " +
                  std::to_string(r.order) + " of " + std::to_string(order.size()));
    f.batch = int(order[size_t(r.order)]);
    f.primitive = r.primitive;
    f.position = glm::vec3(r.position[0], r.position[1], r.position[2]);
    f.alpha = r.position[3];
    f.normal = glm::vec3(r.normal[0], r.normal[1], r.normal[2]);
    f.diffuse = glm::vec4(r.diffuse[0], r.diffuse[1], r.diffuse[2], r.diffuse[3]);
    f.specular = glm::vec4(r.specular[0], r.specular[1], r.specular[2], r.specular[3]);
    f.emissive = glm::vec4(r.emissive[0], r.emissive[1], r.emissive[2], r.emissive[3]);
  }
  return out;
}

std::vector<ViewBox> GlRasterizer::batchBoxes(const SceneCamera& camera) const {
  std::vector<ViewBox> boxes;
  boxes.reserve(state_->draws.size());
  for (const DrawBatch& d : state_->draws) boxes.push_back(viewBox(d.bounds, camera.viewFromWorld));
  return boxes;
}

size_t GlRasterizer::batchCount() const { return state_->draws.size(); }

size_t GlRasterizer::transparentDraws() const {
  size_t n = 0;
  for (size_t b = 0; b < state_->draws.size(); ++b) n += state_->transparent(b) ? 1 : 0;
  return n;
}

GlRasterizer::State& GlRasterizer::beginForward(int width, int height, bool shadows) {
  if (width > state_->maxSize || height > state_->maxSize)
    throw Error("--raster gl: " + std::to_string(width) + "x" + std::to_string(height) +
                " exceeds this OpenGL implementation's limit");
  EglContext::shared().makeCurrent();
  warmUpForward(shadows);
  // The frame's variant: with kernels/shadows.h only when a light casts a shadow.
  state_->selectForward(shadows);
  return *state_;
}

std::string GlRasterizer::renderer() const { return EglContext::shared().renderer(); }

void GlRasterizer::checkTarget(int width, int height, const RasterOptions& options) const {
  if (options.fragmentCounts)
    throw Error("fragment counts (overdraw) come from the software rasterizer only");
  if (width > state_->maxSize || height > state_->maxSize)
    throw Error("--raster gl: " + std::to_string(width) + "x" + std::to_string(height) +
                " exceeds this OpenGL implementation's limit of " +
                std::to_string(state_->maxSize) + " pixels per side");
}

GBuffer GlRasterizer::rasterize(const SceneCamera& camera, int width, int height,
                                const RasterOptions& options) {
  checkTarget(width, height, options);
  const CameraIntrinsics in = CameraIntrinsics::from(camera, width, height);
  EglContext::shared().makeCurrent();
  state_->ensureFramebuffer(width, height);
  state_->draw(camera, in, options, state_->gbufferTargets);
  GBuffer g;
  g.resize(width, height);
  g.model = options.model;
  state_->readBack(g, options);
  return g;
}

int GlRasterizer::maxSamples() const {
  EglContext::shared().makeCurrent();
  // Every target of a pass has the same count: the least of the colour, integer and
  // renderbuffer limits.
  GLint samples = 0, colour = 0, integer = 0;
  glGetIntegerv(GL_MAX_SAMPLES, &samples);
  glGetIntegerv(GL_MAX_COLOR_TEXTURE_SAMPLES, &colour);
  glGetIntegerv(GL_MAX_INTEGER_SAMPLES, &integer);
  return std::min({samples, colour, integer});
}

void GlRasterizer::checkSamples(int samples) const {
  const int most = maxSamples();
  if (samples > most)
    throw Error("--msaa " + std::to_string(samples) + ": this OpenGL implementation (" +
                renderer() + ") renders at most " + std::to_string(most) +
                " samples a pixel (GL_MAX_SAMPLES, GL_MAX_COLOR_TEXTURE_SAMPLES, "
                "GL_MAX_INTEGER_SAMPLES)");
}

std::vector<GBuffer> GlRasterizer::rasterizeSamples(const SceneCamera& camera, int width,
                                                    int height, int samples,
                                                    const RasterOptions& options) {
  if (samples <= 1) return {rasterize(camera, width, height, options)};
  checkTarget(width, height, options);
  checkSamples(samples);
  const CameraIntrinsics in = CameraIntrinsics::from(camera, width, height);
  EglContext::shared().makeCurrent();
  State& s = *state_;
  s.ensureSampleFramebuffer(width, height, samples);
  s.draw(camera, in, options, s.gbufferSampleTargets);
  s.ensureFramebuffer(width, height);
  std::vector<GBuffer> out(static_cast<size_t>(samples));
  for (int k = 0; k < samples; ++k) {
    for (int t = kDepth; t <= kEmissive; ++t)
      s.fetchSample(s.gbufferSampleTargets, t, false, k, s.gbufferTargets, t);
    if (options.triangleIds)
      s.fetchSample(s.gbufferSampleTargets, kTriangle, true, k, s.gbufferTargets, kTriangle);
    GBuffer& g = out[size_t(k)];
    g.resize(width, height);
    g.model = options.model;
    s.readBack(g, options);
  }
  return out;
}

}  // namespace ts
