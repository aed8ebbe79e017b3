#pragma once
// Device calibration for the benchmark's limit estimate: copy bandwidth and peak arithmetic rate,
// measured with the small kernels of kernels/calibrate.cl on the benchmarked device in the same
// run (profiling-event times, median of several launches after one warm-up).
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cl/cl_context.h"

namespace ts {

struct CalibrationOptions {
  size_t copyBytes = size_t(256) << 20;  // per buffer (read once, written once per launch)
  int repeats = 7;                       // timed launches (after one warm-up)
  double minFmaMs = 20.0;                // the FMA launch is lengthened until it takes this long
};

struct Calibration {
  double bandwidthGBs = 0.0;  // (bytes read + written) / median time, 1e9 bytes/s
  double peakGflops = 0.0;    // 2 x multiply-adds / median time, 1e9 FLOP/s
  size_t copyBytes = 0;       // per buffer
  int vectorWidth = 1, chains = 8;
  size_t fmaWorkItems = 0;
  int fmaIterations = 0;
  std::vector<double> copyMs, fmaMs;  // every timed launch

  nlohmann::json toJson() const;
};

// Throws ts::Error (build failure) or cl::Error (device failure).
Calibration calibrate(ClContext& cl, const CalibrationOptions& options = {});

// The time a frame could not beat on this device: bytes / bandwidth or flops / peak, whichever is
// larger (ms). 0 when the calibration is missing.
double limitMs(const Calibration& c, double bytes, double flops);

}  // namespace ts
