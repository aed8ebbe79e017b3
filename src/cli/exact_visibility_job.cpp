#include "cli/exact_visibility_job.h"

#include <algorithm>
#include <chrono>
#include <iomanip>
#include <sstream>

#include "api/api_internal.h"
#include "util/error.h"
#include "visibility/exact_visibility.h"

namespace ts {

ExactVisibilityResult exactVisibility(const Frame& frame) {
  const Frame::Impl& f = *frame.impl();
  if (!f.scene)
    throw Error(
        "--exact-visibility needs the scene's triangles: an imported G-buffer "
        "(--gbuffer-in) has none");
  const Scene& scene = *f.scene;
  std::vector<size_t> casters;
  for (size_t i = 0; i < scene.lights.size(); ++i)
    if (scene.lights[i].castsShadow) casters.push_back(i);
  if (casters.empty())
    throw Error(
        "--exact-visibility: no light casts a shadow (--shadows all|N, or glTF extras "
        "castsShadow)");
  const SurfacePoints points = surfacePoints(f.prepared.gbuffer, f.prepared.camera);
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
  for (size_t c = 0; c < casters.size(); ++c) {
    const SceneLight& light = scene.lights[casters[c]];
    const auto t0 = std::chrono::steady_clock::now();
    const std::vector<uint8_t> v = ev.visibility(points, light);
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
  r.stats = {{"library", "embree 3"},       {"triangles", ev.triangles()},
             {"build_ms", ev.buildMs()},    {"query_ms", queryMs},
             {"applicable", applicableAll}, {"occluded", occludedAll},
             {"image_lights", channels},    {"lights", lights}};
  std::ostringstream s;
  s << "exact visibility: " << casters.size() << " shadow-casting light(s), " << applicableAll
    << " applicable (pixel, light) pairs, " << occludedAll << " occluded; BVH " << std::fixed
    << std::setprecision(1) << ev.buildMs() << " ms, queries " << queryMs << " ms (Embree)";
  r.summary = s.str();
  return r;
}

}  // namespace ts
