#pragma once
// `tileshade check`: every hard case (src/check/hard_cases.h) through every technique, G-buffer
// layout and lanes width, against the double reference. A run passes with no NaN or inf pixel,
// no missed light contribution and every pixel within the fp32 rounding bound
// (src/check/fp32_bound.h). docs/hard-cases.md.
#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

#include "gbuffer/gbuffer_layout.h"

namespace ts {

struct CheckOptions {
  std::vector<std::string> cases;       // names; empty = every case
  std::vector<std::string> techniques;  // names; empty = every technique
  std::vector<GBufferFormat> formats{GBufferFormat::FP32, GBufferFormat::FP16,
                                     GBufferFormat::PACKED};
  std::vector<int> lanes{1, 16};  // widths requested (a case may ask for others)
  std::string device;             // ClContext spec
};

struct CheckRow {
  std::string caseName, technique;
  GBufferFormat format = GBufferFormat::FP32;
  int lanes = 1;              // as the technique ran
  double maxRelPeak = 0.0;    // largest finite |image - reference| over the reference's peak
  double worstOfBound = 0.0;  // largest |image - reference| / the pixel's fp32 bound
  uint64_t nonFinite = 0;     // pixels with a NaN or inf channel
  uint64_t missed = 0;        // reference contributions the technique's lists left out
  bool pass() const { return nonFinite == 0 && missed == 0 && worstOfBound <= 1.0; }
};

// Runs the selection, printing the table to `out` row by row; throws ts::Error for an unknown case
// or technique (before any work).
std::vector<CheckRow> runHardCases(const CheckOptions& options, std::ostream& out);

}  // namespace ts
