#include "util/data_dir.h"

#include <dlfcn.h>
#include <link.h>

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

// The folder the install tree's share/ sits beside: the file's own (<prefix>/bin,
// <prefix>/lib), or for a Python module in <prefix>/lib/python3*/{dist,site}-packages,
// <prefix>/lib.
fs::path installBase(const fs::path& file) {
  const fs::path dir = file.parent_path();
  const std::string folder = dir.filename().string();
  if ((folder == "dist-packages" || folder == "site-packages") &&
      dir.parent_path().filename().string().rfind("python3", 0) == 0) {
    return dir.parent_path().parent_path();
  }
  return dir;
}

// The shared object holding this function, absolute; empty when it is the executable itself (the
// dynamic linker's entry for the main program has no name) or unknown.
fs::path sharedObjectPath() {
  Dl_info info;
  link_map* map = nullptr;
  if (dladdr1(reinterpret_cast<void*>(&sharedObjectPath), &info, reinterpret_cast<void**>(&map),
              RTLD_DL_LINKMAP) == 0 ||
      map == nullptr || map->l_name == nullptr || map->l_name[0] == '\0') {
    return {};
  }
  std::error_code ec;
  const fs::path path = fs::absolute(map->l_name, ec);
  return ec ? fs::path() : path;
}

}  // namespace

std::string resolveDataDir(const std::string& override, const fs::path& executable,
                           const std::string& name, const std::string& sourceDir) {
  if (!override.empty()) return override;
  // No /proc (the executable unknown): the source tree, as before there was an install tree.
  if (executable.empty()) return sourceDir;
  const fs::path installed =
      (installBase(executable) / ".." / "share" / "tileshade" / name).lexically_normal();
  if (isDirectory(installed)) return installed.string();
  if (inBuildFolder(executable) && isDirectory(sourceDir)) return sourceDir;
  // Neither: the install path, so that the "cannot read" error names where it was looked for.
  return installed.string();
}

std::string dataDir(const char* envVar, const std::string& name, const std::string& sourceDir) {
  const char* env = std::getenv(envVar);
  fs::path code = sharedObjectPath();
  if (code.empty()) {
    std::error_code ec;
    code = fs::read_symlink("/proc/self/exe", ec);
    if (ec) code.clear();
  }
  return resolveDataDir(env ? env : "", code, name, sourceDir);
}

}  // namespace ts
