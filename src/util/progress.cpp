#include "util/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <utility>

namespace ts {

Progress::Progress(size_t total, bool enabled, std::string name)
    : total_(total),
      name_(std::move(name)),
      enabled_(enabled),
      tty_(isatty(STDERR_FILENO) != 0),
      start_(std::chrono::steady_clock::now()),
      lastLine_(start_) {}

Progress::~Progress() { finish(); }

std::string Progress::duration(double s) {
  if (!(s >= 0) || s > 1e7) return "?";
  long t = long(s + 0.5);
  char buf[32];
  if (t >= 3600) std::snprintf(buf, sizeof buf, "%ldh%02ldm", t / 3600, (t / 60) % 60);
  else if (t >= 60) std::snprintf(buf, sizeof buf, "%ldm%02lds", t / 60, t % 60);
  else std::snprintf(buf, sizeof buf, "%lds", t);
  return buf;
}

void Progress::step(const std::string& label) {
  ++done_;
  if (enabled_) draw(label);
}

void Progress::note(const std::string& line) {
  if (enabled_ && tty_ && drawn_) std::cerr << "\r\033[K";
  std::cerr << line << "\n";
  drawn_ = false;
}

void Progress::draw(const std::string& label) {
  auto now = std::chrono::steady_clock::now();
  double elapsed = std::chrono::duration<double>(now - start_).count();
  double eta = done_ ? elapsed / double(done_) * double(total_ - std::min(done_, total_)) : -1.0;
  int pct = total_ ? int(100.0 * double(done_) / double(total_)) : 100;
  if (tty_) {
    const int width = 30;
    int filled = total_ ? int(width * double(done_) / double(total_)) : width;
    std::string bar(size_t(filled), '#');
    bar += std::string(size_t(width - filled), '.');
    std::string shown = label.size() > 48 ? label.substr(0, 45) + "..." : label;
    std::cerr << "\r\033[K[" << bar << "] " << done_ << "/" << total_ << " " << pct << "% ETA "
              << duration(eta) << "  " << shown << std::flush;
    drawn_ = true;
    return;
  }
  int decile = pct / 10;
  double sinceLine = std::chrono::duration<double>(now - lastLine_).count();
  if (decile != lastDecile_ || sinceLine >= 30.0 || done_ == total_) {
    std::cerr << name_ << ": " << done_ << "/" << total_ << " (" << pct << "%), elapsed "
              << duration(elapsed) << ", ETA " << duration(eta) << " - " << label << "\n";
    lastDecile_ = decile;
    lastLine_ = now;
  }
}

void Progress::finish() {
  if (enabled_ && tty_ && drawn_) std::cerr << "\n";
  drawn_ = false;
}

}  // namespace ts
