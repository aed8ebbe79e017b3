#include "util/stderr_capture.h"

#include <unistd.h>

#include <cstdio>

namespace ts {
namespace {
std::mutex& captureMutex() {
  static std::mutex m;
  return m;
}
}  // namespace

StderrCapture::StderrCapture() : lock_(captureMutex()) {
  std::fflush(stderr);
  file_ = std::tmpfile();
  if (!file_) return;  // no temporary file: leave stderr as it is
  savedFd_ = ::dup(STDERR_FILENO);
  if (savedFd_ < 0 || ::dup2(fileno(file_), STDERR_FILENO) < 0) {
    if (savedFd_ >= 0) ::close(savedFd_);
    savedFd_ = -1;
    std::fclose(file_);
    file_ = nullptr;
  }
}

StderrCapture::~StderrCapture() {
  restore();
  if (file_) std::fclose(file_);
}

void StderrCapture::restore() {
  if (savedFd_ < 0) return;
  std::fflush(stderr);
  ::dup2(savedFd_, STDERR_FILENO);
  ::close(savedFd_);
  savedFd_ = -1;
}

std::string StderrCapture::text() {
  restore();
  if (!file_) return "";
  std::string all;
  std::rewind(file_);
  char buf[4096];
  for (size_t n; (n = std::fread(buf, 1, sizeof buf, file_)) > 0;) all.append(buf, n);
  std::fclose(file_);
  file_ = nullptr;
  std::string joined, line;
  for (size_t i = 0; i <= all.size(); ++i) {
    if (i < all.size() && all[i] != '\n' && all[i] != '\r') {
      line += all[i];
      continue;
    }
    if (!line.empty()) joined += (joined.empty() ? "" : "; ") + line;
    line.clear();
  }
  return joined;
}

}  // namespace ts
