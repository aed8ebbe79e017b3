#pragma once
// Limits checked on values that have been through a float: tileshade's own files store floats
// (a float of pi/2 is 1.5707963705, 4.4e-8 above pi/2; a float of 0.1 is 0.10000000149011612),
// so a value beyond a limit by no more than a float's rounding is the limit, clamped to it;
// anything further out is refused by the caller with the limit printed in full (fullText).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string>

#include "util/pi.h"

namespace ts {

// The rounding a float of magnitude up to |scale| may carry: one float ulp (2^-23 relative).
inline double floatRounding(double scale) {
  return double(std::numeric_limits<float>::epsilon()) * std::fabs(scale);
}

// True when v lies in [lo, hi] once values within a float's rounding of a bound (of magnitude
// `scale`: the bound's own unless given) are taken as that bound. NaN is never within.
inline bool withinFloatRounding(double v, double lo, double hi) {
  return v >= lo - floatRounding(lo) && v <= hi + floatRounding(hi);
}
inline bool withinFloatRounding(double v, double lo, double hi, double scale) {
  return v >= lo - floatRounding(scale) && v <= hi + floatRounding(scale);
}

// A number in full: the fewest significant digits (up to 17) that read back as the same double
// ("0.1", "1.5707963267948966", "1.5707963705062866"); what messages print for limits and for
// the values they refuse.
inline std::string fullText(double v) {
  char buf[40];
  // At least the integer part's digits, so that 180 is not "1.8e+02".
  const double magnitude = std::fabs(v);
  const int first = magnitude >= 1.0 && magnitude < 1e16 ? int(std::log10(magnitude)) + 1 : 1;
  for (int digits = first; digits <= 17; ++digits) {
    std::snprintf(buf, sizeof buf, "%.*g", digits, v);
    if (std::strtod(buf, nullptr) == v) break;
  }
  return buf;
}

}  // namespace ts
