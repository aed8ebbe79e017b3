#include "util/file_read.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "util/error.h"
#include "util/short_text.h"

namespace ts {

namespace fs = std::filesystem;

void checkReadableFile(const std::string& path, const std::string& what) {
  const std::string name = "cannot read " + what + " " + shortText(path, 200);
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (st.type() == fs::file_type::not_found) throw Error(name + ": no such file");
  if (st.type() == fs::file_type::directory) throw Error(name + ": it is a directory");
  if (ec) throw Error(name + ": " + ec.message());
}

std::string readTextFile(const std::string& path, const std::string& what) {
  checkReadableFile(path, what);
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw Error("cannot read " + what + " " + shortText(path, 200) + ": cannot open it (" +
                std::strerror(errno) + ")");
  std::string text;
  try {
    text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  } catch (const std::ios_base::failure&) {
    in.setstate(std::ios::badbit);
  }
  if (in.bad()) throw Error("cannot read " + what + " " + shortText(path, 200) + ": read error");
  return text;
}

}  // namespace ts
