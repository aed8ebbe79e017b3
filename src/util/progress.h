#pragma once
// Progress of a sweep on stderr: a bar with an ETA redrawn in place when stderr is a terminal,
// otherwise a plain line now and then (every 10% or 30 s) so logs stay readable.
#include <chrono>
#include <cstddef>
#include <string>

namespace ts {

class Progress {
 public:
  // total: units of work (configuration x frame measurements); enabled = false prints no progress;
  // name starts the plain log lines ("bench: 3/40 ...").
  Progress(size_t total, bool enabled, std::string name = "bench");
  ~Progress();
  void step(const std::string& label);  // one unit done
  // A message that must not be overwritten by the bar, printed even when the progress is off
  // (a failure's reason is never hidden).
  void note(const std::string& line);
  void finish();

  static std::string duration(double seconds);  // "1h02m", "3m20s", "12s"

 private:
  void draw(const std::string& label);
  size_t total_, done_ = 0;
  std::string name_;
  bool enabled_, tty_, drawn_ = false;
  int lastDecile_ = -1;
  std::chrono::steady_clock::time_point start_, lastLine_;
};

}  // namespace ts
