#pragma once
// Where the binary's data folders (kernels/, shaders/) are, so that an installed tileshade works
// without its source tree: $TILESHADE_KERNEL_DIR-style override, else the install tree beside the
// file holding tileshade's code (<exe>/../share/tileshade/<name>; the same from
// <prefix>/lib/libtileshade.so, and from the Python module in <prefix>/lib/python3/dist-packages),
// else the source tree, but only for code run from a build folder (one with a CMakeCache.txt at or
// above it) or when that file is unknown.
#include <filesystem>
#include <string>

namespace ts {

// The choice itself, for a given override (empty: none) and path of the file holding the code
// (the executable, or the shared object: the library, the Python module).
std::string resolveDataDir(const std::string& override, const std::filesystem::path& executable,
                           const std::string& name, const std::string& sourceDir);

// resolveDataDir with $envVar and the file this code was loaded from: the shared object holding it
// when tileshade is a library in another program (python3, an engine), whose executable says
// nothing about where tileshade is installed; else this process's executable (/proc/self/exe).
std::string dataDir(const char* envVar, const std::string& name, const std::string& sourceDir);

}  // namespace ts
