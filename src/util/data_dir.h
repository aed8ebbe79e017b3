#pragma once
// Where the binary's data folders (kernels/, shaders/) are, so that an installed tileshade works
// without its source tree: $TILESHADE_KERNEL_DIR-style override, else the install tree beside the
// executable (<exe>/../share/tileshade/<name>), else the source tree, but only for a binary run
// from a build folder (one with a CMakeCache.txt at or above it) or when the executable is unknown.
#include <filesystem>
#include <string>

namespace ts {

// The choice itself, for a given override (empty: none) and executable path.
std::string resolveDataDir(const std::string& override, const std::filesystem::path& executable,
                           const std::string& name, const std::string& sourceDir);

// resolveDataDir with $envVar and this code's file: libtileshade.so when linked from it (its
// <lib>/../share/tileshade), else the process's executable (/proc/self/exe).
std::string dataDir(const char* envVar, const std::string& name, const std::string& sourceDir);

}  // namespace ts
