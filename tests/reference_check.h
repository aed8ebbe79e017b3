#pragma once
// Rendering a prepared frame with a technique and checking it against the double-precision
// reference: the error, the missed light contributions (culling conservativeness), the
// reference's ideal count. Shared by the technique test suites.
#include <map>
#include <string>

#include <gtest/gtest.h>

#include "reference/error_metrics.h"
#include "reference/reference.h"
#include "render/frame_setup.h"
#include "scene/scene_loader.h"
#include "techniques/technique.h"
#include "test_support.h"

namespace ts::test {

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

}  // namespace ts::test
