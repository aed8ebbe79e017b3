#include "util/file_write.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "util/error.h"

namespace ts {
namespace {

[[noreturn]] void failed(const std::string& path, int error) {
  throw Error("cannot write " + path + ": " + std::strerror(error));
}

}  // namespace

void writeFile(const std::string& path, const void* data, size_t size) {
  int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) failed(path, errno);
  const char* p = static_cast<const char*>(data);
  while (size > 0) {
    ssize_t n = ::write(fd, p, size);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      int error = n < 0 ? errno : ENOSPC;  // a write of 0 bytes: nothing more fits
      ::close(fd);
      failed(path, error);
    }
    p += n;
    size -= size_t(n);
  }
  if (::close(fd) != 0) failed(path, errno);  // e.g. a network file system's delayed error
}

void writeFile(const std::string& path, const std::string& text) {
  writeFile(path, text.data(), text.size());
}

void writeFileAtomically(const std::string& path, const std::string& text) {
  std::string tmp = path + ".tmp";
  writeFile(tmp, text);
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    int error = errno;
    std::remove(tmp.c_str());
    failed(path, error);
  }
}

void flushChecked(std::ostream& out, const std::string& path) {
  errno = 0;
  out.flush();
  if (!out) failed(path, errno ? errno : EIO);
}

}  // namespace ts
