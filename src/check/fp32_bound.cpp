#include "check/fp32_bound.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <thread>

#include "shading/shading_cpu.h"

namespace ts {
namespace {

constexpr double kEps = 0x1p-24;  // fp32 unit roundoff
// Rounding of one light term's own arithmetic, relative to the term's scale C*falloff*(kd+ks):
// ~25 roundings (2e-6 at most) and the specular power's ts_pow_unit (< 4e-6 where x^s >= 2^-24,
// kernels/gbuffer.h), with a margin: 170 ulp.
constexpr double kTermRelative = 1e-5;

double maxOf(const glm::dvec3& v) { return std::max({v.x, v.y, v.z}); }

// The surface as the reference shades it: its shading point for `shading`, recomputed from the
// (possibly perturbed) position and normal.
shading_d::ts_shading_point pointOf(const SurfaceD& s, glm::dvec3 P, glm::dvec3 N, int shading) {
  shading_d::ts_shading_point p =
      shading_d::ts_make_shading_point(P, N, glm::normalize(-P), s.gloss, shading);
  return p;
}

// Spot, directional and metallic-roughness terms: the first-order bound measured instead of
// derived. The term is evaluated in double at the surface and light as the kernel holds them and
// with each input coordinate moved by its fp32 rounding (position ~4 ulp of |P|, normal ~2 ulp,
// light position 1 ulp of |L|); the sum of the largest moves per input, twice, plus the term's
// own arithmetic (kTermRelative, 3x for the longer metallic-roughness evaluation) bounds it.
double numericTermBound(const SurfaceD& s, const ViewLights& lights, size_t i, bool directional,
                        int model, int shading, double positionError, double* magnitude) {
  auto term = [&](glm::dvec3 P, glm::dvec3 N, glm::dvec3 L) {
    shading_d::ts_shading_point p = pointOf(s, P, N, shading);
    if (directional)
      return shading_d::ts_directional_light(&p, s.kd, s.ks, glm::normalize(L),
                                             glm::dvec3(glm::vec3(lights.directionalColor[i])),
                                             shading, 1);
    glm::dvec4 pr(glm::vec4(lights.positionRange[i]));
    return shading_d::ts_punctual_light(
        &p, s.kd, s.ks, glm::dvec4(L, pr.w), glm::dvec4(glm::vec4(lights.color[i])),
        glm::dvec4(glm::vec4(lights.spot[i])), model, shading, 1, 1);
  };
  const glm::dvec3 L = directional ? glm::dvec3(glm::vec3(lights.directionalDir[i]))
                                   : glm::dvec3(glm::vec3(lights.positionRange[i]));
  const glm::dvec3 f0 = term(s.P, s.N, L);
  double moved = 0.0, largest = maxOf(glm::abs(f0));
  auto probe = [&](glm::dvec3 P, glm::dvec3 N, glm::dvec3 L2) {
    glm::dvec3 f = term(P, N, L2);
    largest = std::max(largest, maxOf(glm::abs(f)));
    return maxOf(glm::abs(f - f0));
  };
  const double lightError = directional ? 2.0 * kEps : kEps * glm::length(L);
  for (int k = 0; k < 3; ++k) {
    glm::dvec3 e(0.0);
    e[k] = 1.0;
    double dP = 0.0, dN = 0.0, dL = 0.0;
    for (double sign : {-1.0, 1.0}) {
      dP = std::max(dP, probe(s.P + sign * positionError * e, s.N, L));
      dN = std::max(dN, probe(s.P, glm::normalize(s.N + sign * 2.0 * kEps * e), L));
      dL = std::max(dL, probe(s.P, s.N, L + sign * lightError * e));
    }
    moved += dP + dN + dL;
  }
  const double arithmetic = kTermRelative * (shading == TS_SHADING_METALLIC_ROUGHNESS ? 3.0 : 1.0);
  *magnitude += largest;
  return 2.0 * moved + arithmetic * largest;
}

// The bound of one pixel's light terms and their sum.
double pixelBound(const SurfaceD& s, const ViewLights& lights, glm::dvec3 base, int model,
                  int shading) {
  const double dmin2 = TS_DMIN * TS_DMIN;
  const double kdks = maxOf(s.kd) + maxOf(s.ks);
  const bool mr = shading == TS_SHADING_METALLIC_ROUGHNESS;
  if (!(kdks > 0.0) && !mr) return 2.0 * kEps * maxOf(glm::abs(base));  // no light term at all
  // The kernel reconstructs P in float: each coordinate within ~4 ulp of |P|.
  const double positionError = 4.0 * kEps * glm::length(s.P);
  double bound = 0.0, magnitude = maxOf(glm::abs(base));
  size_t terms = 0;
  for (size_t i = 0; i < lights.directionalCount(); ++i, ++terms)
    bound += numericTermBound(s, lights, i, true, model, shading, positionError, &magnitude);
  for (size_t i = 0; i < lights.size(); ++i) {
    if (mr || lights.isSpot(i)) {  // not a Blinn-Phong point light: measured
      ++terms;
      bound += numericTermBound(s, lights, i, false, model, shading, positionError, &magnitude);
      continue;
    }
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
      if (q - dq >= 1.0) continue;               // out of range in float too
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
          bound[size_t(y) * gbuffer.width + x] =
              pixelBound(s, lights, base, model, int(gbuffer.model));
        }
    });
  for (auto& th : pool) th.join();
  return bound;
}

}  // namespace ts
