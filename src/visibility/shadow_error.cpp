#include "visibility/shadow_error.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <map>
#include <sstream>

#include "reference/error_metrics.h"
#include "render/stats.h"
#include "util/error.h"
#include "visibility/exact_visibility.h"

namespace ts {
namespace {

// Wrong pairs of the maps against exact visibility, over the pairs where both count: exact
// applicable (0 or 1) and the reference sampled the map (the light's unshadowed contribution is
// non-zero: N.L > 0, inside range and cone; factor not NaN).
struct WrongPairs {
  uint64_t pairs = 0, falseShadow = 0, lightLeak = 0;
  double absError = 0.0;
  void add(double factor, uint8_t exact) {
    if (exact > 1 || std::isnan(factor)) return;
    ++pairs;
    falseShadow += factor < 0.5 && exact == 1;  // acne, aliasing
    lightLeak += factor >= 0.5 && exact == 0;   // peter-panning, aliasing
    absError += std::abs(factor - double(exact));
  }
  void add(const WrongPairs& o) {
    pairs += o.pairs;
    falseShadow += o.falseShadow;
    lightLeak += o.lightLeak;
    absError += o.absError;
  }
  double fraction() const { return pairs ? double(falseShadow + lightLeak) / double(pairs) : 0.0; }
  nlohmann::json json() const {
    const double n = pairs ? double(pairs) : 1.0;
    return {{"pairs", pairs},
            {"false_shadow", falseShadow},
            {"light_leak", lightLeak},
            {"false_shadow_fraction", double(falseShadow) / n},
            {"light_leak_fraction", double(lightLeak) / n},
            {"fraction", fraction()},
            {"mean_abs_factor_error", absError / n}};
  }
};

// The hook's slot of each scene light: ViewLights keeps punctual lights in scene order, then
// the directional ones after them (scene/view_space_lights.cpp).
std::vector<size_t> referenceSlots(const Scene& scene) {
  size_t punctual = 0;
  for (const SceneLight& l : scene.lights) punctual += l.type != SceneLightType::Directional;
  std::vector<size_t> slots;
  size_t p = 0, d = 0;
  for (const SceneLight& l : scene.lights)
    slots.push_back(l.type == SceneLightType::Directional ? punctual + d++ : p++);
  return slots;
}

}  // namespace

ExactVisibilityResult measureAgainstExactVisibility(const Scene& scene, const PreparedFrame& p,
                                                    const EncodedGBuffer& planes) {
  std::vector<size_t> casters;
  for (size_t i = 0; i < scene.lights.size(); ++i)
    if (scene.lights[i].castsShadow) casters.push_back(i);
  if (casters.empty())
    throw Error(
        "--exact-visibility: no light casts a shadow (--shadows all|N, or glTF extras "
        "castsShadow)");
  const uint64_t pixels = uint64_t(p.gbuffer.width) * uint64_t(p.gbuffer.height);
  const uint64_t pairBytes = uint64_t(casters.size()) * pixels * (sizeof(uint8_t) + sizeof(double));
  if (pairBytes > kExactVisibilityMaxPairBytes)
    throw Error("--exact-visibility: " + std::to_string(casters.size()) +
                " shadow-casting light(s) x " + std::to_string(pixels) + " pixels need " +
                std::to_string(pairBytes >> 20) + " MB of per-pair planes, over its " +
                std::to_string(kExactVisibilityMaxPairBytes >> 20) +
                " MB: cast fewer shadows (--shadows N) or render a smaller frame");
  const SurfacePoints points = surfacePoints(p.gbuffer, p.camera);
  const ExactVisibility ev(scene);

  ExactVisibilityResult r;
  r.width = points.width;
  r.height = points.height;
  const size_t channels = std::min(casters.size(), kExactVisibilityChannels);
  for (size_t c = 0; c < channels; ++c) r.channels.push_back("light" + std::to_string(casters[c]));
  r.image.assign(points.size() * channels, 0.0f);
  nlohmann::json lights = nlohmann::json::array();
  double queryMs = 0.0;
  uint64_t applicableAll = 0, occludedAll = 0;
  const std::vector<size_t> slots = referenceSlots(scene);
  ReferenceShadowHook exactHook;
  exactHook.visibility.resize(p.lights.size() + p.lights.directionalCount());
  for (size_t c = 0; c < casters.size(); ++c) {
    const SceneLight& light = scene.lights[casters[c]];
    const auto t0 = std::chrono::steady_clock::now();
    std::vector<uint8_t>& v = exactHook.visibility.at(slots[casters[c]]);
    v = ev.visibility(points, light);
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    queryMs += ms;
    uint64_t applicable = 0, occluded = 0;
    for (size_t i = 0; i < v.size(); ++i) {
      applicable += v[i] != kVisibilityNotApplicable;
      occluded += v[i] == kVisibilityOccluded;
      if (c < channels) r.image[i * channels + c] = float(v[i]);
    }
    applicableAll += applicable;
    occludedAll += occluded;
    lights.push_back({{"light", casters[c]},
                      {"type", toString(light.type)},
                      {"applicable", applicable},
                      {"occluded", occluded},
                      {"query_ms", ms}});
  }
  // The double reference twice: with the maps (recording their factors), then with exact
  // visibility in their place; the same planes, lights and shading code.
  const int model = int(RangeModel::Windowed);
  ReferenceShadowHook mapHook;
  const ReferenceImage mapped = shadeReference(planes, p.intrinsics, p.lights, p.ambient, model, 0,
                                               {}, ReferencePositions::FromDepth, &mapHook);
  r.exactReference = shadeReference(planes, p.intrinsics, p.lights, p.ambient, model, 0, {},
                                    ReferencePositions::FromDepth, &exactHook);
  WrongPairs total;
  std::map<std::string, WrongPairs> perType;
  for (size_t c = 0; c < casters.size(); ++c) {
    const size_t slot = slots[casters[c]];
    const std::vector<uint8_t>& v = exactHook.visibility[slot];
    const std::vector<double>& factor = mapHook.factors.at(slot);
    if (factor.size() != v.size())
      throw Error("light " + std::to_string(casters[c]) +
                  " casts a shadow but the reference has no shadow map for it");
    WrongPairs w;
    r.wrongPairs.resize(v.size(), 0.0f);
    for (size_t i = 0; i < v.size(); ++i) {
      const uint64_t before = w.falseShadow + w.lightLeak;
      w.add(factor[i], v[i]);
      r.wrongPairs[i] += float(w.falseShadow + w.lightLeak - before);
    }
    lights[c]["wrong_pairs"] = w.json();
    total.add(w);
    perType[toString(scene.lights[casters[c]].type)].add(w);
  }
  nlohmann::json wrong = total.json();
  for (const auto& [type, w] : perType) wrong["per_type"][type] = w.json();
  const ErrorStats image =
      compareReferences(mapped, r.exactReference, 1e-4 * r.exactReference.peak);
  r.shadowError.assign(mapped.rgb.size(), 0.0f);
  for (size_t i = 0; i < mapped.rgb.size(); ++i) {
    const glm::dvec3 d = glm::abs(mapped.rgb[i] - r.exactReference.rgb[i]);
    r.shadowError[i] = float(std::max({d.x, d.y, d.z}));
  }

  nlohmann::json imageError = errorJson(image);
  // p99 of the per-pixel error relative to the peak, as max_rel_peak is.
  imageError["p99_rel_peak"] = image.peak > 0.0 ? image.p99 / image.peak : image.p99;
  r.stats = {{"library", "embree 3"},       {"triangles", ev.triangles()},
             {"build_ms", ev.buildMs()},    {"query_ms", queryMs},
             {"applicable", applicableAll}, {"occluded", occludedAll},
             {"image_lights", channels},    {"lights", lights},
             {"wrong_pairs", wrong},        {"image_error", imageError}};
  std::ostringstream s;
  s << "exact visibility: " << casters.size() << " shadow-casting light(s), " << applicableAll
    << " applicable (pixel, light) pairs, " << occludedAll << " occluded; BVH " << std::fixed
    << std::setprecision(1) << ev.buildMs() << " ms, queries " << queryMs << " ms (Embree)\n"
    << "shadow maps vs exact: " << total.falseShadow << " false shadow, " << total.lightLeak
    << " light leak of " << total.pairs << " pairs (" << std::setprecision(3)
    << 100.0 * total.fraction() << "% wrong), mean |factor - exact| " << std::scientific
    << std::setprecision(2) << (total.pairs ? total.absError / double(total.pairs) : 0.0)
    << "; image max " << image.maxRelPeak << " rmse " << image.rmse << " p99 "
    << imageError["p99_rel_peak"].get<double>() << " of the peak";
  r.summary = s.str();
  return r;
}

}  // namespace ts
