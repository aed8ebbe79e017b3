#pragma once
// The OpenGL tests' guard: a test that needs a context skips, saying why, where none can be made
// (no EGL, no Mesa), instead of failing on a machine that cannot run OpenGL at all.
#include <gtest/gtest.h>

#include "raster/egl_context.h"
#include "util/error.h"

// Skips the calling test with the context's error when EglContext::shared() cannot be made.
#define REQUIRE_GL()                 \
  do {                               \
    try {                            \
      ::ts::EglContext::shared();    \
    } catch (const ::ts::Error& e) { \
      GTEST_SKIP() << e.what();      \
    }                                \
  } while (0)
