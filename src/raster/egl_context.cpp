#include "raster/egl_context.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <epoxy/egl.h>
#include <epoxy/gl.h>

#include "util/error.h"
#include "util/short_text.h"

namespace ts {
namespace {

std::string eglErrorText(EGLint e) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "0x%04x", unsigned(e));
  return buf;
}

bool hasClientExtension(const char* name) { return epoxy_has_egl_extension(EGL_NO_DISPLAY, name); }

// An initialised display with a current OpenGL core context, or a reason why not.
struct Attempt {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;
  std::string failure;  // empty on success
};

Attempt tryDisplay(EGLDisplay display, const std::string& what) {
  Attempt a;
  if (display == EGL_NO_DISPLAY) {
    a.failure = what + ": no display (EGL error " + eglErrorText(eglGetError()) + ")";
    return a;
  }
  EGLint major = 0, minor = 0;
  if (!eglInitialize(display, &major, &minor)) {
    a.failure = what + ": eglInitialize failed (EGL error " + eglErrorText(eglGetError()) + ")";
    return a;
  }
  auto fail = [&](const std::string& why) {
    eglTerminate(display);
    a.failure = what + ": " + why;
    return a;
  };
  if (!epoxy_has_egl_extension(display, "EGL_KHR_surfaceless_context"))
    return fail("no EGL_KHR_surfaceless_context (needed to render without a window)");
  if (!epoxy_has_egl_extension(display, "EGL_KHR_no_config_context"))
    return fail("no EGL_KHR_no_config_context");
  if (!eglBindAPI(EGL_OPENGL_API)) return fail("the display has no desktop OpenGL API");
  const EGLint attributes[] = {EGL_CONTEXT_MAJOR_VERSION,
                               3,
                               EGL_CONTEXT_MINOR_VERSION,
                               3,
                               EGL_CONTEXT_OPENGL_PROFILE_MASK,
                               EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                               EGL_NONE};
  EGLContext context = eglCreateContext(display, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attributes);
  if (context == EGL_NO_CONTEXT)
    return fail("no OpenGL 3.3 core context (EGL error " + eglErrorText(eglGetError()) + ")");
  if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
    eglDestroyContext(display, context);
    return fail("eglMakeCurrent failed (EGL error " + eglErrorText(eglGetError()) + ")");
  }
  if (epoxy_gl_version() < 45 && !epoxy_has_gl_extension("GL_ARB_clip_control")) {
    std::string version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
    eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(display, context);
    return fail("OpenGL " + version + " has no ARB_clip_control (core in 4.5)");
  }
  a.display = display;
  a.context = context;
  return a;
}

// The first non-software EGL device, or EGL_NO_DISPLAY with `why` filled in.
EGLDisplay hardwareDeviceDisplay(std::string& why) {
  if (!hasClientExtension("EGL_EXT_platform_device") ||
      !hasClientExtension("EGL_EXT_device_enumeration") ||
      !hasClientExtension("EGL_EXT_device_query")) {
    why = "no EGL_EXT_platform_device";
    return EGL_NO_DISPLAY;
  }
  EGLint count = 0;
  if (!eglQueryDevicesEXT(0, nullptr, &count) || count <= 0) {
    why = "no EGL device";
    return EGL_NO_DISPLAY;
  }
  std::vector<EGLDeviceEXT> devices(static_cast<size_t>(count));
  eglQueryDevicesEXT(count, devices.data(), &count);
  for (int i = 0; i < count; ++i) {
    const char* ext = eglQueryDeviceStringEXT(devices[size_t(i)], EGL_EXTENSIONS);
    if (ext && epoxy_extension_in_string(ext, "EGL_MESA_device_software")) continue;
    return eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, devices[size_t(i)], nullptr);
  }
  why = "only software EGL devices";
  return EGL_NO_DISPLAY;
}

}  // namespace

EglContext& EglContext::shared() {
  // Never destroyed: tearing EGL down from a static destructor races the drivers' own exit
  // handlers, and the process is ending anyway.
  static EglContext* context = new EglContext();
  return *context;
}

EglContext::EglContext() {
  const auto t0 = std::chrono::steady_clock::now();
  const std::string missing = "no OpenGL context for --raster gl: ";
  const std::string install =
      " (install Mesa's EGL and llvmpipe: libegl1 libegl-mesa0 libgl1-mesa-dri, or a GPU "
      "driver's EGL)";
  if (!epoxy_has_egl()) throw Error(missing + "libEGL.so.1 cannot be loaded" + install);
  if (!hasClientExtension("EGL_EXT_platform_base"))
    throw Error(missing + "EGL has no EGL_EXT_platform_base" + install);

  std::string want;
  if (const char* env = std::getenv("TILESHADE_EGL_PLATFORM"); env && *env) want = env;
  if (!want.empty() && want != "device" && want != "surfaceless")
    throw Error("TILESHADE_EGL_PLATFORM must be 'device' or 'surfaceless', got '" +
                shortText(want) + "'");

  std::vector<std::string> failures;
  Attempt got;
  if (want.empty() || want == "device") {
    std::string why;
    EGLDisplay d = hardwareDeviceDisplay(why);
    if (d != EGL_NO_DISPLAY) {
      got = tryDisplay(d, "EGL device");
      if (got.failure.empty()) platform_ = "device";
      else failures.push_back(got.failure);
    } else {
      failures.push_back("EGL device: " + why);
    }
  }
  if (platform_.empty() && (want.empty() || want == "surfaceless")) {
    if (hasClientExtension("EGL_MESA_platform_surfaceless")) {
      got = tryDisplay(
          eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr),
          "Mesa surfaceless");
      if (got.failure.empty()) platform_ = "surfaceless";
      else failures.push_back(got.failure);
    } else {
      failures.push_back("no EGL_MESA_platform_surfaceless");
    }
  }
  if (platform_.empty()) {
    std::string all;
    for (const auto& f : failures) all += (all.empty() ? "" : "; ") + f;
    throw Error(missing + all + install);
  }
  display_ = got.display;
  context_ = got.context;
  renderer_ = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  version_ = reinterpret_cast<const char*>(glGetString(GL_VERSION));
  createMs_ =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

void EglContext::makeCurrent() const {
  if (eglGetCurrentContext() == static_cast<EGLContext>(context_)) return;
  if (!eglMakeCurrent(static_cast<EGLDisplay>(display_), EGL_NO_SURFACE, EGL_NO_SURFACE,
                      static_cast<EGLContext>(context_)))
    throw Error("eglMakeCurrent failed (EGL error " + eglErrorText(eglGetError()) + ")");
}

}  // namespace ts
