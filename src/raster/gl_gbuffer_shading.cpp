#include "raster/gl_gbuffer_shading.h"

#include <epoxy/gl.h>

#include "raster/egl_context.h"
#include "raster/gl_program.h"
#include "util/error.h"

namespace ts {
namespace {

enum Plane { kDepth, kNormal, kDiffuse, kSpecular, kEmissive, kPlanes };
enum Storage { kPosRange, kColor, kSpot, kDirectional, kStorages };

const char* const kVertexFile = "fullscreen.vert";
const char* const kFragmentFile = "shade_gbuffer.frag";

}  // namespace

struct GlGBufferShading::State {
  GLuint program = 0, vao = 0, framebuffer = 0, colour = 0;
  GLuint planes[kPlanes] = {};
  GLuint storage[kStorages] = {};
  int width = 0, height = 0;

  ~State() {
    try {
      EglContext::shared().makeCurrent();
    } catch (const Error&) {
      return;
    }
    releaseTargets();
    glDeleteBuffers(kStorages, storage);
    glDeleteVertexArrays(1, &vao);
    glDeleteProgram(program);
  }

  void releaseTargets() {
    if (!framebuffer) return;
    glDeleteFramebuffers(1, &framebuffer);
    glDeleteTextures(1, &colour);
    glDeleteTextures(kPlanes, planes);
    framebuffer = colour = 0;
    width = height = 0;
  }

  void ensureTargets(int w, int h) {
    if (framebuffer && w == width && h == height) return;
    releaseTargets();
    glGenTextures(kPlanes, planes);
    for (int p = 0; p < kPlanes; ++p) {
      glBindTexture(GL_TEXTURE_2D, planes[p]);
      glTexStorage2D(GL_TEXTURE_2D, 1, p == kDepth ? GL_R32F : GL_RGBA32F, w, h);
    }
    glGenTextures(1, &colour);
    glBindTexture(GL_TEXTURE_2D, colour);
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA32F, w, h);
    glGenFramebuffers(1, &framebuffer);
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, colour, 0);
    gl::checkErrors("creating the " + std::to_string(w) + "x" + std::to_string(h) +
                    " G-buffer shading targets");
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
      releaseTargets();
      throw Error("OpenGL framebuffer of one RGBA32F target is incomplete");
    }
    width = w;
    height = h;
  }

  // Texel (x, y) of a plane is pixel (x, y): row 0 of the texture is image row 0, and so is row 0
  // of the framebuffer (gl_FragCoord.y - 0.5), as in the OpenGL rasterizer.
  void uploadPlane(int plane, const void* data, GLenum format) {
    glBindTexture(GL_TEXTURE_2D, planes[plane]);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    if (data) glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width, height, format, GL_FLOAT, data);
  }

  // An SSBO may not be empty: an absent array is one zero element, never read.
  void uploadStorage(int binding, const std::vector<glm::vec4>& data) {
    static const glm::vec4 kZero(0.0f);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, storage[binding]);
    glBufferData(GL_SHADER_STORAGE_BUFFER, GLsizeiptr(std::max<size_t>(data.size(), 1) * 16),
                 data.empty() ? &kZero : data.data(), GL_STREAM_DRAW);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, GLuint(binding), storage[binding]);
  }

  GLint at(const char* name) const { return glGetUniformLocation(program, name); }
};

GlGBufferShading::GlGBufferShading() : state_(std::make_unique<State>()) {
  EglContext::shared().makeCurrent();
  gl::checkErrors("making the context current");
  if (epoxy_gl_version() < 43)
    throw Error("OpenGL " + EglContext::shared().version() +
                " has no shader storage buffers (OpenGL 4.3), which the forward shading needs");
  state_->program = gl::buildProgram(kVertexFile, kFragmentFile);
  glGenVertexArrays(1, &state_->vao);
  glGenBuffers(kStorages, state_->storage);
  glUseProgram(state_->program);
  const char* samplers[kPlanes] = {"u_depth", "u_normal", "u_diffuse", "u_specular", "u_emissive"};
  for (int p = 0; p < kPlanes; ++p) glUniform1i(state_->at(samplers[p]), p);
  gl::checkErrors("setting up the G-buffer shading program");
}

GlGBufferShading::~GlGBufferShading() = default;

std::string GlGBufferShading::fragmentSource() { return gl::shaderSource(kFragmentFile); }

std::vector<glm::vec4> GlGBufferShading::shade(const EncodedGBuffer& gbuffer,
                                               const CameraIntrinsics& camera,
                                               const ViewLights& lights, glm::vec3 ambient,
                                               const SceneFeatures& features, int model) {
  if (gbuffer.format != GBufferFormat::FP32)
    throw Error("OpenGL G-buffer shading reads the fp32 layout only, not " +
                toString(gbuffer.format));
  if (gbuffer.width != camera.width || gbuffer.height != camera.height)
    throw Error("OpenGL G-buffer shading: the G-buffer is not the camera's size");
  State& s = *state_;
  EglContext::shared().makeCurrent();
  s.ensureTargets(gbuffer.width, gbuffer.height);
  s.uploadPlane(kDepth, gbuffer.depth.data(), GL_RED);
  s.uploadPlane(kNormal, gbuffer.normal.data(), GL_RGBA);
  s.uploadPlane(kDiffuse, gbuffer.diffuse.data(), GL_RGBA);
  s.uploadPlane(kSpecular, gbuffer.specular.empty() ? nullptr : gbuffer.specular.data(), GL_RGBA);
  s.uploadPlane(kEmissive, gbuffer.emissive.empty() ? nullptr : gbuffer.emissive.data(), GL_RGBA);
  s.uploadStorage(kPosRange, lights.positionRange);
  s.uploadStorage(kColor, lights.color);
  s.uploadStorage(kSpot, lights.spot);
  std::vector<glm::vec4> directional;
  for (size_t k = 0; k < lights.directionalCount(); ++k) {
    directional.push_back(lights.directionalDir[k]);
    directional.push_back(lights.directionalColor[k]);
  }
  s.uploadStorage(kDirectional, directional);
  gl::checkErrors("uploading the G-buffer and the lights");

  glUseProgram(s.program);
  const glm::vec4 cam = camera.kernelCamera();
  glUniform4fv(s.at("u_camera"), 1, &cam.x);
  glUniform3fv(s.at("u_ambient"), 1, &ambient.x);
  glUniform1i(s.at("u_lightCount"), GLint(lights.size()));
  glUniform1i(s.at("u_dirLightCount"), features.directional ? GLint(lights.directionalCount()) : 0);
  glUniform1i(s.at("u_model"), model);
  glUniform1i(s.at("u_shading"), int(gbuffer.model));
  // Metallic-roughness always has its specular term (its roughness is in the normal's w in fp32);
  // Blinn-Phong's needs the specular plane.
  const bool specular = gbuffer.model == ShadingModel::MetallicRoughness ||
                        (features.specular && !gbuffer.specular.empty());
  glUniform1i(s.at("u_specularOn"), specular ? 1 : 0);
  glUniform1i(s.at("u_spotOn"), features.spot ? 1 : 0);
  glUniform1i(s.at("u_emissiveOn"), features.emissive && !gbuffer.emissive.empty() ? 1 : 0);
  for (int p = 0; p < kPlanes; ++p) {
    glActiveTexture(GLenum(GL_TEXTURE0 + p));
    glBindTexture(GL_TEXTURE_2D, s.planes[p]);
  }

  glBindFramebuffer(GL_FRAMEBUFFER, s.framebuffer);
  const GLenum target = GL_COLOR_ATTACHMENT0;
  glDrawBuffers(1, &target);
  glViewport(0, 0, gbuffer.width, gbuffer.height);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);
  glDisable(GL_SCISSOR_TEST);
  glDisable(GL_STENCIL_TEST);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glBindVertexArray(s.vao);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  gl::checkErrors("shading the G-buffer");

  std::vector<glm::vec4> image(gbuffer.pixelCount());
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glBindTexture(GL_TEXTURE_2D, s.colour);
  glGetTexImage(GL_TEXTURE_2D, 0, GL_RGBA, GL_FLOAT, image.data());
  gl::checkErrors("reading back the shaded image");
  return image;
}

}  // namespace ts
