#pragma once
// A framebuffer of colour textures (attachments 0..n-1, one internal format each) and a float depth
// renderbuffer, all of one size: the OpenGL rasterizer's G-buffer targets and its forward passes'
// targets are two of these, made the same way.
#include <string>
#include <vector>

#include <epoxy/gl.h>

namespace ts::gl {

struct Targets {
  GLuint framebuffer = 0, depth = 0;
  std::vector<GLuint> colour;
  int width = 0, height = 0;  // of the attachments; 0 before ensure()

  // Makes them for w x h (and binds the framebuffer) unless they already have that size. `what`
  // names the framebuffer in errors: an OpenGL error, or an incomplete framebuffer (its status).
  void ensure(int w, int h, const std::vector<GLenum>& formats, const std::string& what);
  void release();
};

}  // namespace ts::gl
