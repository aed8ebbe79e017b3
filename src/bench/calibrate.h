#pragma once
// Device calibration for the benchmark's limit estimate: copy bandwidth and peak arithmetic rate,
// measured with the small kernels of kernels/calibrate.cl on the benchmarked device in the same
// run (profiling-event times). One round is the median of several launches of each kernel (after
// one warm-up before the first round); rounds repeat until the best two agree
// (bench/calibration_rounds.h) and the best round is the rate, its spread recorded beside it.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/calibration_rounds.h"
#include "cl/cl_context.h"

namespace ts {

struct CalibrationOptions {
  size_t copyBytes = size_t(256) << 20;  // per buffer (read once, written once per launch)
  int repeats = 7;                       // timed launches of each kernel per round
  double minFmaMs = 20.0;                // the FMA launch is lengthened until it takes this long
  CalibrationRoundsOptions rounds;
};

struct Calibration {
  double bandwidthGBs = 0.0;    // best round of (bytes read + written) / median time, 1e9 bytes/s
  double peakGflops = 0.0;      // best round of 2 x multiply-adds / median time, 1e9 FLOP/s
  RoundSpread bandwidth, peak;  // every round's value, their best and spread
  bool settled = false;         // the best two rounds agreed (else: maxRounds were measured)
  double agreement = 0.0;       // the tolerance they were held to
  size_t copyBytes = 0;         // per buffer
  int vectorWidth = 1, chains = 8;
  size_t fmaWorkItems = 0;
  int fmaIterations = 0;
  std::vector<double> copyMs, fmaMs;  // every timed launch, round after round

  nlohmann::json toJson() const;
};

// Throws ts::Error (build failure) or cl::Error (device failure).
Calibration calibrate(ClContext& cl, const CalibrationOptions& options = {});

// The time a frame could not beat on this device: bytes / bandwidth or flops / peak, whichever is
// larger (ms). 0 when the calibration is missing.
double limitMs(const Calibration& c, double bytes, double flops);

}  // namespace ts
