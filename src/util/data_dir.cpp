#include "util/data_dir.h"

#include <dlfcn.h>

#include <cstdlib>
#include <system_error>

namespace ts {
namespace fs = std::filesystem;
namespace {

bool isDirectory(const fs::path& p) {
  std::error_code ec;
  return fs::is_directory(p, ec);
}

// A build folder has CMakeCache.txt at its top; test and fuzz binaries may sit below it.
bool inBuildFolder(const fs::path& executable) {
  std::error_code ec;
  for (fs::path dir = executable.parent_path(); !dir.empty(); dir = dir.parent_path()) {
    if (fs::exists(dir / "CMakeCache.txt", ec)) return true;
    if (dir == dir.root_path()) break;
  }
  return false;
}

// Where this code lives: the shared library (libtileshade.so) when it is one, so that an engine's
// program finds the kernels beside the library's install tree; else the executable.
fs::path codeLocation(std::error_code& ec) {
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&codeLocation), &info) && info.dli_fname) {
    const std::string name = info.dli_fname;
    const size_t so = name.rfind(".so");
    if (so != std::string::npos && (so + 3 == name.size() || name[so + 3] == '.')) {
      fs::path library = fs::canonical(name, ec);
      if (!ec) return library;
    }
  }
  ec.clear();
  return fs::read_symlink("/proc/self/exe", ec);
}

}  // namespace

std::string resolveDataDir(const std::string& override, const fs::path& executable,
                           const std::string& name, const std::string& sourceDir) {
  if (!override.empty()) return override;
  // No /proc (the executable unknown): the source tree, as before there was an install tree.
  if (executable.empty()) return sourceDir;
  const fs::path installed =
      (executable.parent_path() / ".." / "share" / "tileshade" / name).lexically_normal();
  if (isDirectory(installed)) return installed.string();
  if (inBuildFolder(executable) && isDirectory(sourceDir)) return sourceDir;
  // Neither: the install path, so that the "cannot read" error names where it was looked for.
  return installed.string();
}

std::string dataDir(const char* envVar, const std::string& name, const std::string& sourceDir) {
  const char* env = std::getenv(envVar);
  std::error_code ec;
  const fs::path executable = codeLocation(ec);
  return resolveDataDir(env ? env : "", ec ? fs::path() : executable, name, sourceDir);
}

}  // namespace ts
