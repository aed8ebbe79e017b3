#pragma once
// OpenGL plumbing for the OpenGL rasterizer: shader sources from shaders/ (with a one-level
// `#include "file"` of the same folder, which GLSL itself lacks), program builds whose compile
// and link logs become one-line ts::Error messages, and glGetError checks.
#include <string>

#include <epoxy/gl.h>

namespace ts::gl {

// $TILESHADE_SHADER_DIR, else the installed or source tree's shaders/ (as kernels/ for OpenCL).
std::string shaderDir();

// The text of shaderDir()/name with each `#include "other"` line replaced by that file's text;
// `#include "kernels/other"` takes the file from the OpenCL kernels' folder (cl/cl_context.h,
// kernelDir()), so a shader compiles the very header the kernels do (kernels/shading.h).
std::string shaderSource(const std::string& name);

// Compiles and links a vertex + fragment program from shaderDir() files, with `defines` (lines
// such as "#define TS_NORMAL_MAPS 1\n") after each one's #version line. Throws ts::Error naming
// the file and quoting the log on one line.
GLuint buildProgram(const std::string& vertexFile, const std::string& fragmentFile,
                    const std::string& defines = "");

// Throws ts::Error "OpenGL error GL_INVALID_OPERATION (and …) after WHERE" when glGetError
// reports any.
void checkErrors(const std::string& where);

}  // namespace ts::gl
