#pragma once
// A headless OpenGL context through EGL: no window, no X server. Used by the OpenGL rasterizer
// (src/raster/gl_rasterizer.h); GL entry points are loaded through libepoxy.
//
// Display choice, first that gives an OpenGL 3.3+ core context with ARB_clip_control (core in
// 4.5; the rasterizer's reversed depth needs it):
//  1. an EGL device that is not a software renderer (EGL_EXT_platform_device: a GPU vendor's
//     EGL, e.g. NVIDIA's, or Mesa on a GPU's render node);
//  2. Mesa's surfaceless platform (EGL_MESA_platform_surfaceless: llvmpipe on a machine without
//     a GPU, a Mesa GPU driver otherwise).
// $TILESHADE_EGL_PLATFORM = "device" or "surfaceless" restricts the choice to one of them.
#include <string>

namespace ts {

class EglContext {
 public:
  // The process's context, created on first use (a few hundred ms on llvmpipe) and kept until the
  // process exits. Throws ts::Error with one line naming what is missing when no context can be
  // made (no libEGL, no usable platform, no GL 3.3 core, no ARB_clip_control).
  static EglContext& shared();

  // Makes the context current on the calling thread (GL calls happen on one thread at a time).
  void makeCurrent() const;

  const std::string& renderer() const { return renderer_; }  // GL_RENDERER
  const std::string& version() const { return version_; }    // GL_VERSION
  const std::string& platform() const { return platform_; }  // "device" or "surfaceless"
  double createMs() const { return createMs_; }              // time to create it

  EglContext(const EglContext&) = delete;
  EglContext& operator=(const EglContext&) = delete;

 private:
  EglContext();
  void* display_ = nullptr;  // EGLDisplay
  void* context_ = nullptr;  // EGLContext
  std::string renderer_, version_, platform_;
  double createMs_ = 0.0;
};

}  // namespace ts
