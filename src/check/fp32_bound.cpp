#include "check/fp32_bound.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <thread>

#include "reference/shading_cpu.h"

namespace ts {
namespace {

constexpr double kEps = 0x1p-24;  // fp32 unit roundoff
// Rounding of one light term's own arithmetic, relative to the term's scale C*falloff*(kd+ks):
// ~25 roundings (2e-6 at most) and the specular power's ts_pow_unit (< 4e-6 where x^s >= 2^-24,
// kernels/gbuffer.h), with a margin: 170 ulp.
constexpr double kTermRelative = 1e-5;

double maxOf(const glm::dvec3& v) { return std::max({v.x, v.y, v.z}); }

// The bound of one pixel's light terms and their sum.
double pixelBound(const SurfaceD& s, const ViewLights& lights, glm::dvec3 base, int model) {
  const double dmin2 = TS_DMIN * TS_DMIN;
  const double kdks = maxOf(s.kd) + maxOf(s.ks);
  if (!(kdks > 0.0)) return 2.0 * kEps * maxOf(glm::abs(base));  // no light term at all
  // The kernel reconstructs P in float: each coordinate within ~4 ulp of |P|.
  const double positionError = 4.0 * kEps * glm::length(s.P);
  double bound = 0.0, magnitude = maxOf(glm::abs(base));
  size_t terms = 0;
  for (size_t i = 0; i < lights.size(); ++i) {
    glm::dvec3 L(glm::vec3(lights.positionRange[i]));
    double r = double(lights.positionRange[i].w);
    double c = maxOf(glm::abs(glm::dvec3(glm::vec3(lights.color[i]))));
    glm::dvec3 v = L - s.P;
    double d2 = glm::dot(v, v), d = std::sqrt(d2);
    // eta: relative error of the light vector v = L - P (P's rounding, L's, the subtraction).
    double eta = d > 0.0 ? (positionError + kEps * glm::length(L)) / d + 2.0 * kEps
                         : std::numeric_limits<double>::infinity();
    double full = c * kdks / std::max(d2, dmin2);  // the term's largest value with window 1
    double window = 1.0, windowError = 0.0;
    if (model == TS_MODEL_WINDOWED) {
      double q = d2 / (r * r);
      double dq = q * (2.0 * eta + 4.0 * kEps);  // q = d2/r2 as the kernel rounds it
      if (q - dq >= 1.0) continue;             // out of range in float too
      double w = std::max(1.0 - q * q, 0.0);
      window = w * w;
      // d(window)/dq = -4 q (1 - q^2), and near q = 1, where the kernel may still find the light
      // in range, window <= (2 dq)^2.
      windowError = 4.0 * q * w * dq + 16.0 * dq * dq;
    }
    double scale = full * std::min(1.0, window + windowError);
    ++terms;
    glm::dvec3 l = d > 0.0 ? v / d : glm::dvec3(0.0);
    double ndl = std::max(glm::dot(s.N, l), 0.0);
    // ndl moves by up to 2*eta (absolute), the falloff by 2*eta relative.
    double err = full * windowError + scale * (kTermRelative + 4.0 * eta);
    // The specular power: x = N.h with h = (l + V)/|l + V|; h's direction moves by
    // (|dl| + |dV|)/|l + V|, and x^s by s * x^(s-1) times that.
    glm::dvec3 h = l + s.V;
    double hlen = glm::length(h);
    if (ndl + 2.0 * eta > 0.0 && maxOf(s.ks) > 0.0) {
      double dh = hlen > 0.0 ? 2.0 * (2.0 * eta + 4.0 * kEps) / hlen
                             : std::numeric_limits<double>::infinity();
      double x = hlen > 0.0 ? std::max(glm::dot(s.N, h) / hlen, 0.0) : 0.0;
      double dx = std::min(dh, 2.0);
      double sPow = s.gloss * std::pow(std::min(x + dx, 1.0), std::max(s.gloss - 1.0, 0.0));
      err += scale * maxOf(s.ks) / kdks * std::min(sPow * dx, 1.0) * std::min(ndl + 2.0 * eta, 1.0);
    }
    // A term is never off by more than twice its largest value.
    bound += std::min(err, 2.0 * scale);
    magnitude += scale * std::min(ndl + 2.0 * eta, 1.0);
  }
  // The kernels add the terms one by one in float (the deferred techniques onto the base):
  // at most `terms` roundings of the running sum.
  return bound + double(terms + 1) * kEps * magnitude + 2.0 * kEps * maxOf(glm::abs(base));
}

}  // namespace

std::vector<double> fp32ErrorBound(const EncodedGBuffer& gbuffer, const CameraIntrinsics& camera,
                                   const ViewLights& lights, glm::vec3 ambient, int model) {
  std::vector<double> bound(gbuffer.pixelCount(), 0.0);
  const int threads = int(std::max(1u, std::thread::hardware_concurrency()));
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t)
    pool.emplace_back([&, t] {
      for (int y = t; y < gbuffer.height; y += threads)
        for (int x = 0; x < gbuffer.width; ++x) {
          SurfaceD s;
          if (!decodeSurface(gbuffer, camera, x, y, s)) continue;
          glm::dvec3 base = shading_d::ts_surface_base(s.ke, s.cDiff, glm::dvec3(ambient));
          bound[size_t(y) * gbuffer.width + x] = pixelBound(s, lights, base, model);
        }
    });
  for (auto& th : pool) th.join();
  return bound;
}

}  // namespace ts
