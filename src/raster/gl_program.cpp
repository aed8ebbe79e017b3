#include "raster/gl_program.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <regex>
#include <sstream>
#include <vector>

#include "cl/cl_context.h"
#include "util/data_dir.h"
#include "util/error.h"
#include "util/file_read.h"

namespace ts::gl {
namespace {

std::string readFile(const std::string& path) {
  if (!std::filesystem::exists(path))
    throw Error("cannot read shader source " + path + " (set TILESHADE_SHADER_DIR?)");
  return readTextFile(path, "shader source");
}

// A driver's multi-line log as one line.
std::string oneLine(std::string log) {
  while (!log.empty() && (log.back() == '\n' || log.back() == ' ' || log.back() == '\0'))
    log.pop_back();
  std::string out;
  for (char c : log) {
    if (c == '\n') out += " | ";
    else out += c;
  }
  return out;
}

GLuint compile(GLenum stage, const std::string& file, const std::string& defines) {
  std::string text = shaderSource(file);
  // After the #version line, which must come first.
  if (!defines.empty()) text.insert(std::min(text.find('\n'), text.size() - 1) + 1, defines);
  GLuint shader = glCreateShader(stage);
  const char* src = text.c_str();
  glShaderSource(shader, 1, &src, nullptr);
  glCompileShader(shader);
  GLint ok = GL_FALSE, length = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (ok != GL_TRUE) {
    glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
    std::vector<char> log(size_t(std::max(length, 1)), '\0');
    glGetShaderInfoLog(shader, GLsizei(log.size()), nullptr, log.data());
    glDeleteShader(shader);
    throw Error("OpenGL shader " + shaderDir() + "/" + file +
                " does not compile: " + oneLine(log.data()));
  }
  return shader;
}

const char* errorName(GLenum e) {
  switch (e) {
    case GL_INVALID_ENUM: return "GL_INVALID_ENUM";
    case GL_INVALID_VALUE: return "GL_INVALID_VALUE";
    case GL_INVALID_OPERATION: return "GL_INVALID_OPERATION";
    case GL_INVALID_FRAMEBUFFER_OPERATION: return "GL_INVALID_FRAMEBUFFER_OPERATION";
    case GL_OUT_OF_MEMORY: return "GL_OUT_OF_MEMORY";
    default: return "unknown GL error";
  }
}

// `#include "kernels/x.h"` reads x.h from the OpenCL kernel folder (kernelDir()).
const std::string kKernelPrefix = "kernels/";

}  // namespace

std::string shaderDir() { return dataDir("TILESHADE_SHADER_DIR", "shaders", TILESHADE_SHADER_DIR); }

std::string shaderSource(const std::string& name) {
  const std::string text = readFile(shaderDir() + "/" + name);
  static const std::regex include(R"re(^[ \t]*#[ \t]*include[ \t]*"([^"]+)"[ \t]*$)re");
  std::istringstream in(text);
  std::string line, out;
  while (std::getline(in, line)) {
    std::smatch m;
    if (!std::regex_match(line, m, include)) out += line;
    else if (m[1].str().rfind(kKernelPrefix, 0) == 0)
      out += readFile(kernelDir() + "/" + m[1].str().substr(kKernelPrefix.size()));
    else out += readFile(shaderDir() + "/" + m[1].str());
    out += "\n";
  }
  return out;
}

GLuint buildProgram(const std::string& vertexFile, const std::string& fragmentFile,
                    const std::string& defines) {
  GLuint vs = compile(GL_VERTEX_SHADER, vertexFile, defines);
  GLuint fs = 0;
  try {
    fs = compile(GL_FRAGMENT_SHADER, fragmentFile, defines);
  } catch (...) {
    glDeleteShader(vs);
    throw;
  }
  GLuint program = glCreateProgram();
  glAttachShader(program, vs);
  glAttachShader(program, fs);
  glLinkProgram(program);
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLint ok = GL_FALSE, length = 0;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (ok != GL_TRUE) {
    glGetProgramiv(program, GL_INFO_LOG_LENGTH, &length);
    std::vector<char> log(size_t(std::max(length, 1)), '\0');
    glGetProgramInfoLog(program, GLsizei(log.size()), nullptr, log.data());
    glDeleteProgram(program);
    throw Error("OpenGL program " + vertexFile + " + " + fragmentFile +
                " does not link: " + oneLine(log.data()));
  }
  checkErrors("building " + vertexFile + " + " + fragmentFile);
  return program;
}

void checkErrors(const std::string& where) {
  std::string names;
  for (int i = 0; i < 16; ++i) {  // a lost context can report errors forever
    GLenum e = glGetError();
    if (e == GL_NO_ERROR) break;
    names += (names.empty() ? "" : ", ") + std::string(errorName(e));
  }
  if (!names.empty()) throw Error("OpenGL error " + names + " after " + where);
}

}  // namespace ts::gl
