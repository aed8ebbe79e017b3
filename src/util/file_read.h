#pragma once
// Reading the files a user names (scenes, G-buffer descriptors, lights, bench configs and
// results, kernel and shader sources): one place that turns a missing file, a directory or a read
// error into one line naming the file, instead of a stream's "basic_filebuf::underflow ...".
#include <string>

namespace ts {

// The whole file. Throws ts::Error "cannot read WHAT PATH: it is a directory" (or "no such
// file", "cannot open it: REASON", "read error").
std::string readTextFile(const std::string& path, const std::string& what);

// The same check alone, for files another library opens (OpenImageIO): throws the same errors.
void checkReadableFile(const std::string& path, const std::string& what);

}  // namespace ts
