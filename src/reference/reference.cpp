#include "reference/reference.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <mutex>
#include <thread>

#include "shading/shading_cpu.h"
#include "util/error.h"

namespace ts {
namespace {

// Runs body(y) for every row on `threads` threads (0 = all cores), rows handed out dynamically;
// reports each finished row to `progress` (serialised).
template <typename Body>
void parallelRows(int height, int threads, const RowProgress& progress, Body body) {
  int n = threads > 0 ? threads : int(std::max(1u, std::thread::hardware_concurrency()));
  std::atomic<int> next{0};
  int done = 0;
  std::mutex progressMutex;
  std::vector<std::thread> pool;
  for (int t = 0; t < n; ++t)
    pool.emplace_back([&] {
      for (int y; (y = next++) < height;) {
        body(y);
        if (progress) {
          std::lock_guard<std::mutex> lock(progressMutex);
          progress(++done, height);
        }
      }
    });
  for (auto& th : pool) th.join();
}

// The light terms as every kernel forms them, in double: the general pipeline (specular and spot
// terms on; a scene without them contributes exactly 0 through them), the G-buffer's shading
// model.
glm::dvec4 widen(const glm::vec4& v) { return glm::dvec4(v); }

bool nonZero(const glm::dvec3& v) { return v.x != 0.0 || v.y != 0.0 || v.z != 0.0; }

shading_d::ts_shading_point shadingPoint(const SurfaceD& s, int shading) {
  shading_d::ts_shading_point p = shading_d::ts_make_shading_point(s.P, s.N, s.V, s.gloss, shading);
  p.view_term = s.viewTerm;  // as decoded (the same formula; kept for one source of truth)
  return p;
}

// The shadow factor of kernels/shadows.h in double, from the same float face table and atlas
// (1 for a light without a shadow; sampled only where the light reaches, as the kernels do).
double shadowFactor(const ViewLights& lights, int first, const SurfaceD& s, glm::dvec3 towards) {
  if (first < 0) return 1.0;
  return shading_d::ts_shadow_factor(lights.shadowFaces.data(), lights.shadowAtlas->data(), first,
                                     s.P, s.N, towards);
}

// The factor a shadowed pair is shaded with: the map's, recorded for the hook, or the hook's
// exact 0/1 in its place. `slot` is the light's index in the hook's planes.
double hookedFactor(ReferenceShadowHook* hook, size_t slot, size_t pixel, double mapFactor) {
  if (!hook) return mapFactor;
  if (slot < hook->factors.size() && !hook->factors[slot].empty())
    hook->factors[slot][pixel] = mapFactor;
  if (slot < hook->visibility.size() && !hook->visibility[slot].empty()) {
    const uint8_t v = hook->visibility[slot][pixel];
    if (v <= 1) return double(v);
  }
  return mapFactor;
}

// The range of a light's factor over the corners of the rounding box around the receiver (and the
// receiver itself): where it is not 0, a receiver within rounding of this one may be decided
// otherwise. The factor is a step function of the tap coordinates and the depth, each nearly
// linear in P across so small a box, so their extremes lie at its corners.
struct FactorRange {
  const ReceiverRounding* rounding = nullptr;
  glm::dvec3 slack{0.0};
  uint64_t ambiguous = 0;

  template <typename Factor>
  void add(const SurfaceD& s, const glm::dvec3& unshadowed, double centre, Factor factor) {
    if (!rounding) return;
    const double h = rounding->halfSide(s.P);
    double lo = centre, hi = centre;
    for (int corner = 0; corner < 8; ++corner) {
      const glm::dvec3 P = s.P + h * glm::dvec3(corner & 1 ? 1.0 : -1.0, corner & 2 ? 1.0 : -1.0,
                                                corner & 4 ? 1.0 : -1.0);
      const double f = factor(P);
      lo = std::min(lo, f);
      hi = std::max(hi, f);
    }
    if (hi > lo) {
      slack += (hi - lo) * glm::abs(unshadowed);
      ++ambiguous;
    }
  }
};

glm::dvec3 lightContribution(const SurfaceD& s, const shading_d::ts_shading_point& p,
                             const ViewLights& lights, size_t i, int model, int shading,
                             ReferenceShadowHook* hook = nullptr, size_t pixel = 0,
                             FactorRange* range = nullptr) {
  glm::dvec3 c = shading_d::ts_punctual_light(&p, s.kd, s.ks, widen(lights.positionRange[i]),
                                              widen(lights.color[i]), widen(lights.spot[i]), model,
                                              shading, 1, 1);
  const int first = lights.shadowOf(i);
  if (first >= 0 && nonZero(c)) {
    const glm::dvec3 at(glm::vec3(lights.positionRange[i]));
    auto factorAt = [&](const glm::dvec3& P) {
      SurfaceD moved = s;
      moved.P = P;
      return shadowFactor(lights, first, moved, glm::normalize(at - P));
    };
    const double f = factorAt(s.P);
    if (range) range->add(s, c, f, factorAt);
    c *= hookedFactor(hook, i, pixel, f);
  }
  return c;
}

glm::dvec3 directionalContribution(const SurfaceD& s, const shading_d::ts_shading_point& p,
                                   const ViewLights& lights, size_t i, int shading,
                                   ReferenceShadowHook* hook, size_t pixel, FactorRange* range) {
  const glm::dvec3 towards(glm::vec3(lights.directionalDir[i]));
  glm::dvec3 c = shading_d::ts_directional_light(
      &p, s.kd, s.ks, towards, glm::dvec3(glm::vec3(lights.directionalColor[i])), shading, 1);
  const int first = lights.directionalShadowOf(i);
  if (first >= 0 && nonZero(c)) {
    auto factorAt = [&](const glm::dvec3& P) {
      SurfaceD moved = s;
      moved.P = P;
      return shadowFactor(lights, first, moved, towards);
    };
    const double f = factorAt(s.P);
    if (range) range->add(s, c, f, factorAt);
    c *= hookedFactor(hook, lights.size() + i, pixel, f);
  }
  return c;
}

// The kernels' own position of pixel (x, y): ts_view_position in float from the stored depth (as
// ts_load_surface calls it), widened; the view vector and the Smith view term follow from it.
void useKernelPosition(SurfaceD& s, const EncodedGBuffer& gbuffer, const CameraIntrinsics& camera,
                       int x, int y) {
  const float depth = gbuffer.depth[size_t(y) * size_t(gbuffer.width) + size_t(x)];
  s.P = glm::dvec3(shading_f::ts_view_position(x, y, depth, camera.tanHalfFovX, camera.tanHalfFovY,
                                               camera.width, camera.height));
  s.V = -s.P / std::sqrt(glm::dot(s.P, s.P));  // as decodeSurface; depth > 0: never zero
  if (gbuffer.model == ShadingModel::MetallicRoughness)
    s.viewTerm = shading_d::ts_smith_view_term(s.N, s.V, s.gloss);
}

}  // namespace

double ReceiverRounding::halfSide(const glm::dvec3& P) const {
  const double eps = std::ldexp(1.0, -23);
  return 8.0 * eps * (std::max({std::abs(P.x), std::abs(P.y), std::abs(P.z)}) + worldMagnitude);
}

ReferenceImage shadeReference(const EncodedGBuffer& gbuffer, const CameraIntrinsics& camera,
                              const ViewLights& lights, glm::vec3 ambient, int model, int threads,
                              const RowProgress& progress, ReferencePositions positions,
                              ReferenceShadowHook* shadows, const ReceiverRounding* rounding) {
  ReferenceImage ref;
  if (rounding && lights.hasShadows())
    ref.receiverSlack.assign(gbuffer.pixelCount(), glm::dvec3(0.0));
  std::vector<uint64_t> rowAmbiguous(size_t(gbuffer.height), 0);
  if (shadows) {
    const size_t slots = lights.size() + lights.directionalCount();
    shadows->factors.assign(slots, {});
    for (size_t i = 0; i < slots; ++i) {
      const int first =
          i < lights.size() ? lights.shadowOf(i) : lights.directionalShadowOf(i - lights.size());
      if (first >= 0)
        shadows->factors[i].assign(gbuffer.pixelCount(), std::numeric_limits<double>::quiet_NaN());
    }
  }
  ref.width = gbuffer.width;
  ref.height = gbuffer.height;
  ref.rgb.assign(gbuffer.pixelCount(), glm::dvec3(0.0));
  std::vector<uint64_t> rowContributing(size_t(gbuffer.height), 0);
  glm::dvec3 a = glm::dvec3(ambient);
  const int shading = int(gbuffer.model);
  parallelRows(gbuffer.height, threads, progress, [&](int y) {
    for (int x = 0; x < gbuffer.width; ++x) {
      SurfaceD s;
      if (!decodeSurface(gbuffer, camera, x, y, s)) continue;
      if (positions == ReferencePositions::KernelFloat) useKernelPosition(s, gbuffer, camera, x, y);
      shading_d::ts_shading_point p = shadingPoint(s, shading);
      glm::dvec3 sum(0.0);
      const size_t pixel = size_t(y) * size_t(gbuffer.width) + size_t(x);
      FactorRange range;
      range.rounding = ref.receiverSlack.empty() ? nullptr : rounding;
      // Punctual lights in list order, then the directional ones, as the kernels add them.
      for (size_t i = 0; i < lights.size(); ++i) {
        glm::dvec3 c = lightContribution(s, p, lights, i, model, shading, shadows, pixel, &range);
        if (nonZero(c)) {
          sum += c;
          ++rowContributing[size_t(y)];
        }
      }
      for (size_t i = 0; i < lights.directionalCount(); ++i) {
        glm::dvec3 c = directionalContribution(s, p, lights, i, shading, shadows, pixel, &range);
        if (nonZero(c)) {
          sum += c;
          ++rowContributing[size_t(y)];
        }
      }
      ref.rgb[size_t(y) * gbuffer.width + x] = sum + shading_d::ts_surface_base(s.ke, s.cDiff, a);
      if (range.rounding) {
        ref.receiverSlack[pixel] = range.slack;
        rowAmbiguous[size_t(y)] += range.ambiguous;
      }
    }
  });
  for (auto n : rowContributing) ref.contributing += n;
  for (auto n : rowAmbiguous) ref.ambiguousShadowPairs += n;
  for (const auto& c : ref.rgb) ref.peak = std::max({ref.peak, c.x, c.y, c.z});
  return ref;
}

ReferenceImage averageSamples(const std::vector<ReferenceImage>& samples) {
  if (samples.empty()) throw Error("averageSamples: no samples");
  ReferenceImage mean;
  mean.width = samples[0].width;
  mean.height = samples[0].height;
  mean.rgb.assign(samples[0].rgb.size(), glm::dvec3(0.0));
  for (const ReferenceImage& s : samples) {
    if (s.width != mean.width || s.height != mean.height || s.rgb.size() != mean.rgb.size())
      throw Error("averageSamples: the samples' references differ in size");
    for (size_t i = 0; i < s.rgb.size(); ++i) mean.rgb[i] += s.rgb[i];
    mean.contributing += s.contributing;
    // The mean's slack is the mean of the samples' (each bounds its own sample's shadow flips).
    if (!s.receiverSlack.empty()) {
      mean.receiverSlack.resize(s.receiverSlack.size(), glm::dvec3(0.0));
      for (size_t i = 0; i < s.receiverSlack.size(); ++i)
        mean.receiverSlack[i] += s.receiverSlack[i];
    }
    mean.ambiguousShadowPairs += s.ambiguousShadowPairs;
  }
  const double weight = 1.0 / double(samples.size());
  for (glm::dvec3& c : mean.rgb) {
    c *= weight;
    mean.peak = std::max({mean.peak, c.x, c.y, c.z});
  }
  for (glm::dvec3& c : mean.receiverSlack) c *= weight;
  return mean;
}

ReferenceImage shadeSampleAverage(const std::vector<EncodedGBuffer>& samples,
                                  const CameraIntrinsics& camera, const ViewLights& lights,
                                  glm::vec3 ambient, int model, ReferencePositions positions,
                                  const ReceiverRounding* rounding,
                                  const SampleProgress& progress) {
  std::vector<ReferenceImage> shaded;
  for (size_t k = 0; k < samples.size(); ++k)
    shaded.push_back(shadeReference(samples[k], camera, lights, ambient, model, 0,
                                    progress ? progress(k) : RowProgress(), positions, nullptr,
                                    rounding));
  return averageSamples(shaded);
}

uint64_t countMissedContributions(const LightAssignment& assignment, const EncodedGBuffer& gbuffer,
                                  const CameraIntrinsics& camera, const ViewLights& lights,
                                  int model, const RowProgress& progress) {
  // Each bin's lights, sorted for a binary search: memory in proportion to the lists themselves
  // (a bins x lights bitset would need 3.6 GB for 1e6 lights on 3600 tiles).
  size_t bins = assignment.binCount.size(), n = lights.size();
  std::vector<std::vector<uint32_t>> listed(bins);
  for (size_t b = 0; b < bins; ++b) {
    auto first = assignment.binLights.begin() + long(assignment.binOffset[b]);
    listed[b].assign(first, first + long(assignment.binCount[b]));
    std::sort(listed[b].begin(), listed[b].end());
  }
  std::vector<uint64_t> rowMisses(size_t(gbuffer.height), 0);
  parallelRows(gbuffer.height, 0, progress, [&](int y) {
    for (int x = 0; x < gbuffer.width; ++x) {
      SurfaceD s;
      if (!decodeSurface(gbuffer, camera, x, y, s)) continue;
      shading_d::ts_shading_point p = shadingPoint(s, int(gbuffer.model));
      size_t pixel = size_t(y) * gbuffer.width + x;
      int bin = assignment.pixelBin.empty() ? -1 : assignment.pixelBin[pixel];
      for (size_t i = 0; i < n; ++i) {
        if (!nonZero(lightContribution(s, p, lights, i, model, int(gbuffer.model)))) continue;
        bool seen = bin >= 0 && std::binary_search(listed[size_t(bin)].begin(),
                                                   listed[size_t(bin)].end(), uint32_t(i));
        if (!seen && !assignment.lightRect.empty()) {
          const glm::ivec4& r = assignment.lightRect[i];
          seen = x >= r.x && y >= r.y && x < r.z && y < r.w;
        }
        if (!seen) ++rowMisses[size_t(y)];
      }
    }
  });
  uint64_t misses = 0;
  for (auto m : rowMisses) misses += m;
  return misses;
}

uint64_t countMissedOverSamples(const LightAssignment& assignment,
                                const std::vector<EncodedGBuffer>& samples,
                                const CameraIntrinsics& camera, const ViewLights& lights,
                                int model) {
  uint64_t missed = 0;
  const size_t n = size_t(camera.width) * size_t(camera.height);
  const bool perSample = assignment.pixelBin.size() == n * samples.size();
  for (size_t k = 0; k < samples.size(); ++k) {
    if (!perSample) {
      missed += countMissedContributions(assignment, samples[k], camera, lights, model);
      continue;
    }
    LightAssignment one = assignment;
    one.pixelBin.assign(assignment.pixelBin.begin() + long(k * n),
                        assignment.pixelBin.begin() + long((k + 1) * n));
    missed += countMissedContributions(one, samples[k], camera, lights, model);
  }
  return missed;
}

}  // namespace ts
