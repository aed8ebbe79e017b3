#pragma once
// Error of a rendered image against the double reference, on the linear image.
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "reference/reference.h"

namespace ts {

// A pixel whose image (or reference) value is NaN or inf has an infinite error: it is counted in
// nonfinitePixels and makes maxAbs, rmse and maxRelPeak +inf and psnr -inf, so such an image is
// never reported as exact (psnr +inf means rmse is exactly 0 and every pixel finite).
struct ErrorStats {
  double maxAbs = 0.0;      // largest channel difference
  double rmse = 0.0;        // over all pixels and channels
  double psnr = 0.0;        // 20 log10(peak / rmse), peak = the reference's peak; +inf if exact
  double maxRelPeak = 0.0;  // maxAbs / peak
  double p50 = 0.0, p99 = 0.0, p999 = 0.0;  // quantiles of the per-pixel max channel error
  double tolerance = 0.0;                   // the threshold counted below
  uint64_t pixelsAboveTolerance = 0;        // non-finite pixels included
  uint64_t nonfinitePixels = 0;             // pixels with a NaN or inf channel (image or reference)
  double peak = 0.0;                        // largest finite channel value of the reference
  // With ReceiverSlack::Allow: pixels whose difference the reference's receiverSlack reduced (the
  // error is what lies beyond it), and the reference's ambiguous (pixel, light) pairs.
  bool receiverSlack = false;
  uint64_t slackPixels = 0;
  uint64_t ambiguousShadowPairs = 0;
};

// Whether a comparison allows the reference's receiverSlack (reference.h, ReceiverRounding): the
// images of every technique (render --check, bench's error columns) are compared with it.
enum class ReceiverSlack { Ignore, Allow };

// Pixels of an image with a NaN or inf colour channel.
uint64_t countNonFinitePixels(const std::vector<glm::vec4>& image);

// `tolerance` is absolute; pass e.g. 1e-4 * ref.peak.
ErrorStats compareToReference(const std::vector<glm::vec4>& image, const ReferenceImage& ref,
                              double tolerance, ReceiverSlack slack = ReceiverSlack::Ignore);

// The same for a double image (one reference against another), without rounding it to float.
ErrorStats compareReferences(const ReferenceImage& image, const ReferenceImage& ref,
                             double tolerance);

// Per-pixel max channel error (for heat maps).
std::vector<float> errorMap(const std::vector<glm::vec4>& image, const ReferenceImage& ref);

}  // namespace ts
