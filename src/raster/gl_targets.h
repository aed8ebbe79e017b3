#pragma once
// A framebuffer of colour textures (attachments 0..n-1, one internal format each) and a float depth
// renderbuffer, all of one size and sample count: the OpenGL rasterizer's G-buffer targets and its
// forward passes' targets are two of these, made the same way. With samples > 1 (--msaa) the
// textures are GL_TEXTURE_2D_MULTISAMPLE (fixed sample locations) and the depth is multisampled.
#include <string>
#include <vector>

#include <epoxy/gl.h>

namespace ts::gl {

struct Targets {
  GLuint framebuffer = 0, depth = 0;
  std::vector<GLuint> colour;
  int width = 0, height = 0;  // of the attachments; 0 before ensure()
  int samples = 1;

  // Makes them for w x h and `samples` samples a pixel (and binds the framebuffer) unless they
  // already have that size and count. `what` names the framebuffer in errors: an OpenGL error, or
  // an incomplete framebuffer (its status).
  void ensure(int w, int h, const std::vector<GLenum>& formats, const std::string& what,
              int samples = 1);
  GLenum textureTarget() const { return samples > 1 ? GL_TEXTURE_2D_MULTISAMPLE : GL_TEXTURE_2D; }
  void release();
};

}  // namespace ts::gl
