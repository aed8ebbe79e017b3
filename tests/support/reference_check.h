#pragma once
// Rendering a prepared frame with a technique and checking it against the double-precision
// reference: the error, the missed light contributions (culling conservativeness), the
// reference's ideal count. Shared by the technique test suites.
#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "reference/error_metrics.h"
#include "reference/reference.h"
#include "render/frame_setup.h"
#include "scene/scene_loader.h"
#include "techniques/technique.h"
#include "test_support.h"
#include "random_draws.h"

namespace ts::test {

// Largest |a - b| over every channel, relative to the peak of `a`.
inline double relativeDifference(const std::vector<glm::vec4>& a, const std::vector<glm::vec4>& b) {
  double peak = 0.0, diff = 0.0;
  for (size_t i = 0; i < a.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      peak = std::max(peak, double(std::abs(a[i][c])));
      diff = std::max(diff, double(std::abs(a[i][c] - b[i][c])));
    }
  return peak > 0.0 ? diff / peak : diff;
}

// fp32 kernels against the double reference: each pixel sums up to a few hundred light terms,
// each with a relative rounding error of a few float ulps (~1e-7), plus the float position
// reconstruction; 2e-5 of the image peak leaves a margin of ~10x over what we observe while
// catching any missed or doubled light (those are >= 1e-3 of the peak in these scenes).
constexpr double kFp32RelativeTolerance = 2e-5;

// A built-in scene with seed 1, built once per process.
inline const Scene& builtinScene(const std::string& name, const std::string& lights) {
  static std::map<std::string, Scene> cache;
  auto key = name + "/" + lights;
  auto it = cache.find(key);
  if (it == cache.end()) it = cache.emplace(key, makeBuiltinScene(name, lights, 1)).first;
  return it->second;
}

struct Checked {
  ErrorStats error;
  uint64_t missed = 0;        // contributing (pixel, light) pairs the assignment does not hold
  uint64_t contributing = 0;  // the reference's non-zero (pixel, light) pairs
  FrameResult result;
};

inline FrameResult renderOnly(const PreparedFrame& f, Technique& technique, bool wantAssignment) {
  DeviceFrame frame = f.upload(context());
  FrameRequest request;
  request.wantAssignment = wantAssignment;
  return technique.render(frame, request);
}

// Against a reference the caller already shaded (windowed model).
inline Checked renderAndCheck(const PreparedFrame& f, Technique& technique,
                              const ReferenceImage& ref) {
  Checked c;
  c.result = renderOnly(f, technique, true);
  c.contributing = ref.contributing;
  c.error = compareToReference(c.result.image, ref, kFp32RelativeTolerance * ref.peak);
  EXPECT_TRUE(c.result.assignment.has_value()) << technique.name() << " returned no assignment";
  if (c.result.assignment)
    c.missed = countMissedContributions(*c.result.assignment, f.encoded, f.intrinsics, f.lights, 0);
  return c;
}

inline Checked renderAndCheck(const PreparedFrame& f, Technique& technique) {
  return renderAndCheck(f, technique,
                        shadeReference(f.encoded, f.intrinsics, f.lights, f.ambient, 0));
}

// A technique built once per process for each distinct configuration: kernel builds are the slow
// part of these tests. Never destroyed, like the context (test_support.h).
inline Technique& cachedTechnique(const std::string& name, const TechniqueConfig& config) {
  static auto& cache = *new std::map<std::string, std::unique_ptr<Technique>>;
  std::string key =
      name + "|" + config.kernelOptions() + "|" + std::to_string(config.tileWidth) + "x" +
      std::to_string(config.tileHeight) + "|" + std::to_string(config.clusterSlices) + "|" +
      std::to_string(config.localListCapacity) + "|" + std::to_string(config.presizeLists) + "|" +
      std::to_string(config.lanes) + "|" + toString(config.shadowStorage);
  auto& t = cache[key];
  if (!t) t = createTechnique(name, context(), config);
  return *t;
}

// The atrium lit by `count` huge lights (range 1000) on a 7x5x11 lattice through its bounds:
// every tile with geometry lists all of them, more than any local chunk.
inline Scene atriumLatticeLights(int count) {
  Scene scene = makeBuiltinScene("atrium", "big", 1);
  Bounds b = scene.bounds();
  scene.lights.clear();
  for (int i = 0; i < count; ++i) {
    glm::vec3 t(float(i % 7) / 6.0f, float(i % 5) / 4.0f, float(i % 11) / 10.0f);
    scene.lights.push_back(SceneLight::point(b.min + t * b.extent(), glm::vec3(0.05f), 1000.0f));
  }
  return scene;
}

// The atrium at 96x64 lit by `count` huge lights (range 1000, scattered through its bounds):
// every tile and cluster with geometry lists all of them, which overflows any default list.
inline PreparedFrame hugeLightsFrame(int count = 300) {
  Scene scene = makeBuiltinScene("atrium", "big", 1);
  Bounds b = scene.bounds();
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  scene.lights.clear();
  for (int i = 0; i < count; ++i) {
    const auto p = drawnLastFirst<3>([&] { return u(rng); });
    scene.lights.push_back(SceneLight::point(b.min + glm::vec3(p[0], p[1], p[2]) * b.extent(),
                                             glm::vec3(0.05f), 1000.0f));
  }
  return prepareFrame(scene, 0, 96, 64, GBufferFormat::FP32);
}

// Frames (160x96, fp32) from `cameras` random cameras inside street/many and then atrium/mixed:
// looking anywhere, with lights behind and around the camera and the near plane through light
// volumes -- the hard cases for conservative culling.
struct LabelledFrame {
  std::string label;  // "street camera 2"
  PreparedFrame frame;
};
inline std::vector<LabelledFrame> randomCameraFrames(uint32_t seed, int cameras = 4) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<LabelledFrame> frames;
  for (const auto& [name, lights] : {std::pair{"street", "many"}, std::pair{"atrium", "mixed"}}) {
    Scene scene = builtinScene(name, lights);
    Bounds b = scene.bounds();
    for (int i = 0; i < cameras; ++i) {
      auto draw = [&] { return u(rng); };
      const auto e = drawnLastFirst<3>(draw);
      glm::vec3 eye = b.min + glm::vec3(e[0], 0.05f + 0.4f * e[1], e[2]) * b.extent();
      const auto d = drawnLastFirst<3>(draw);
      glm::vec3 dir(d[0] - 0.5f, 0.3f * (d[1] - 0.5f), d[2] - 0.5f);
      scene.cameraPath = {
          SceneCamera::lookAt(eye, eye + dir, {0, 1, 0}, 1.0f + u(rng), 0.1f, 500.0f)};
      frames.push_back({std::string(name) + " camera " + std::to_string(i),
                        prepareFrame(scene, 0, 160, 96, GBufferFormat::FP32)});
    }
  }
  return frames;
}

}  // namespace ts::test
