#include "reference/error_metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "util/error.h"

namespace ts {

std::vector<float> errorMap(const std::vector<glm::vec4>& image, const ReferenceImage& ref) {
  if (image.size() != ref.rgb.size()) throw Error("image and reference sizes differ");
  std::vector<float> out(image.size());
  for (size_t i = 0; i < image.size(); ++i) {
    glm::dvec3 d = glm::abs(glm::dvec3(glm::vec3(image[i])) - ref.rgb[i]);
    double m = std::max({d.x, d.y, d.z});
    // NaN compares false in max(): a pixel with any non-finite channel is an infinite error.
    bool finite = std::isfinite(d.x) && std::isfinite(d.y) && std::isfinite(d.z);
    out[i] = finite ? float(m) : std::numeric_limits<float>::infinity();
  }
  return out;
}

uint64_t countNonFinitePixels(const std::vector<glm::vec4>& image) {
  uint64_t n = 0;
  for (const auto& p : image)
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) ++n;
  return n;
}

namespace {

glm::dvec3 pixelOf(const glm::vec4& v) { return glm::dvec3(glm::vec3(v)); }
glm::dvec3 pixelOf(const glm::dvec3& v) { return v; }

// One comparison for float images and double ones (no rounding of a double image to float: two
// references that agree compare exactly 0).
template <typename Pixel>
ErrorStats compare(const std::vector<Pixel>& image, const ReferenceImage& ref, double tolerance,
                   ReceiverSlack slack = ReceiverSlack::Ignore) {
  if (image.size() != ref.rgb.size()) throw Error("image and reference sizes differ");
  const bool allow = slack == ReceiverSlack::Allow && !ref.receiverSlack.empty();
  const double inf = std::numeric_limits<double>::infinity();
  ErrorStats e;
  for (const auto& c : ref.rgb)
    for (int k = 0; k < 3; ++k)
      if (std::isfinite(c[k])) e.peak = std::max(e.peak, c[k]);
  e.tolerance = tolerance;
  double sumSq = 0.0;
  std::vector<double> perPixel(image.size());
  for (size_t i = 0; i < image.size(); ++i) {
    glm::dvec3 d = pixelOf(image[i]) - ref.rgb[i];
    if (allow && std::isfinite(d.x) && std::isfinite(d.y) && std::isfinite(d.z)) {
      // What lies beyond the receiver's slack: a shadow test decided within rounding of the
      // fragment's position counts as either answer.
      const glm::dvec3 reduced = glm::max(glm::abs(d) - ref.receiverSlack[i], glm::dvec3(0.0));
      if (reduced != glm::abs(d)) ++e.slackPixels;
      d = glm::sign(d) * reduced;
    }
    if (!std::isfinite(d.x) || !std::isfinite(d.y) || !std::isfinite(d.z)) {
      ++e.nonfinitePixels;
      perPixel[i] = inf;
    } else {
      sumSq += glm::dot(d, d);
      glm::dvec3 a = glm::abs(d);
      perPixel[i] = std::max({a.x, a.y, a.z});
    }
    e.maxAbs = std::max(e.maxAbs, perPixel[i]);
    if (!(perPixel[i] <= tolerance)) ++e.pixelsAboveTolerance;
  }
  size_t n = std::max<size_t>(image.size(), 1);
  e.rmse = e.nonfinitePixels ? inf : std::sqrt(sumSq / double(3 * n));
  if (e.nonfinitePixels) e.psnr = -inf;
  else e.psnr = e.rmse > 0.0 ? 20.0 * std::log10(e.peak / e.rmse) : inf;
  e.maxRelPeak = e.peak > 0.0 ? e.maxAbs / e.peak : e.maxAbs;
  auto quantile = [&](double q) {
    if (perPixel.empty()) return 0.0;
    size_t k = std::min(perPixel.size() - 1, size_t(q * double(perPixel.size() - 1) + 0.5));
    std::nth_element(perPixel.begin(), perPixel.begin() + k, perPixel.end());
    return perPixel[k];
  };
  e.p50 = quantile(0.5);
  e.p99 = quantile(0.99);
  e.p999 = quantile(0.999);
  e.receiverSlack = allow;
  if (allow) e.ambiguousShadowPairs = ref.ambiguousShadowPairs;
  return e;
}

}  // namespace

ErrorStats compareToReference(const std::vector<glm::vec4>& image, const ReferenceImage& ref,
                              double tolerance, ReceiverSlack slack) {
  return compare(image, ref, tolerance, slack);
}

ErrorStats compareReferences(const ReferenceImage& image, const ReferenceImage& ref,
                             double tolerance) {
  return compare(image.rgb, ref, tolerance);
}

}  // namespace ts
