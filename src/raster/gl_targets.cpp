#include "raster/gl_targets.h"

#include <cstdio>

#include "raster/gl_program.h"
#include "util/error.h"

namespace ts::gl {

void Targets::ensure(int w, int h, const std::vector<GLenum>& formats, const std::string& what,
                     int n) {
  if (framebuffer && w == width && h == height && n == samples) return;
  release();
  samples = n;
  glGenFramebuffers(1, &framebuffer);
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
  colour.assign(formats.size(), 0);
  glGenTextures(GLsizei(colour.size()), colour.data());
  for (size_t t = 0; t < colour.size(); ++t) {
    glBindTexture(textureTarget(), colour[t]);
    if (n > 1) glTexStorage2DMultisample(GL_TEXTURE_2D_MULTISAMPLE, n, formats[t], w, h, GL_TRUE);
    else glTexStorage2D(GL_TEXTURE_2D, 1, formats[t], w, h);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GLenum(GL_COLOR_ATTACHMENT0 + t), textureTarget(),
                           colour[t], 0);
  }
  glGenRenderbuffers(1, &depth);
  glBindRenderbuffer(GL_RENDERBUFFER, depth);
  if (n > 1) glRenderbufferStorageMultisample(GL_RENDERBUFFER, n, GL_DEPTH_COMPONENT32F, w, h);
  else glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, w, h);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth);
  checkErrors("creating a " + std::to_string(w) + "x" + std::to_string(h) +
              (n > 1 ? " " + std::to_string(n) + "-sample " : " ") + what);
  const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE) {
    char code[16];
    std::snprintf(code, sizeof code, "0x%04x", unsigned(status));
    release();
    throw Error("OpenGL " + what + " is incomplete (status " + code + ")");
  }
  width = w;
  height = h;
}

void Targets::release() {
  if (!framebuffer) return;
  glDeleteFramebuffers(1, &framebuffer);
  glDeleteRenderbuffers(1, &depth);
  glDeleteTextures(GLsizei(colour.size()), colour.data());
  framebuffer = depth = 0;
  colour.clear();
  width = height = 0;
  samples = 1;
}

}  // namespace ts::gl
