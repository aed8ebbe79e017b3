#pragma once
// Routes what a third-party library prints straight to the process's stderr (libpng's
// "libpng error: IHDR: CRC error" from inside OpenImageIO, which has no hook for it) into
// tileshade's own one-line messages. While a StderrCapture lives, file descriptor 2 writes to a
// temporary file; text() ends the capture and returns what was written. Captures are serialised
// process-wide (one at a time), so wrap only the library call, not long work.
#include <memory>
#include <mutex>
#include <string>

namespace ts {

class StderrCapture {
 public:
  StderrCapture();
  ~StderrCapture();  // restores stderr (dropping anything captured) if text() was not called
  StderrCapture(const StderrCapture&) = delete;
  StderrCapture& operator=(const StderrCapture&) = delete;

  // Restores stderr and returns the captured text on one line ("; " between lines, "" if none).
  std::string text();

 private:
  void restore();
  std::unique_lock<std::mutex> lock_;
  int savedFd_ = -1;
  std::FILE* file_ = nullptr;
};

}  // namespace ts
