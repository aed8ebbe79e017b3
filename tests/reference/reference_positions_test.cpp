// The two references of `--check` (src/reference/reference.h): positions from the stored depth in
// double, and the kernels' own float positions. A light just in front of a surface makes the
// float rounding of the position the largest error: only the second reference isolates the
// shading arithmetic there.
#include <gtest/gtest.h>

#include "reference/error_metrics.h"
#include "reference/reference.h"
#include "shading/shading_cpu.h"
#include "reference_check.h"

namespace ts {
namespace {

// Light 0 put 2e-5 units in front of the surface that the frame's centre pixel sees (about 20
// float ulps of its distance), measured from the kernels' float position of that pixel.
PreparedFrame lightOnTheCentrePixel() {
  PreparedFrame f =
      prepareFrame(test::builtinScene("atrium", "small"), 0, 64, 36, GBufferFormat::FP32);
  const int x = 32, y = 18;
  const float depth = f.encoded.depth[size_t(y) * 64 + x];
  EXPECT_GT(depth, 0.0f) << "the centre pixel sees no geometry";
  const glm::vec3 P = shading_f::ts_view_position(x, y, depth, f.intrinsics.tanHalfFovX,
                                                  f.intrinsics.tanHalfFovY, 64, 36);
  const glm::vec3 towardsEye = -P / glm::length(P);
  f.lights.positionRange[0] = glm::vec4(P + 2e-5f * towardsEye, 0.5f);
  return f;
}

TEST(ReferencePositions, KernelFloatPositionsIsolateTheShadingArithmetic) {
  const PreparedFrame f = lightOnTheCentrePixel();
  const ReferenceImage fromDepth = shadeReference(f.encoded, f.intrinsics, f.lights, f.ambient, 0);
  const ReferenceImage kernelFloat = shadeReference(f.encoded, f.intrinsics, f.lights, f.ambient, 0,
                                                    0, {}, ReferencePositions::KernelFloat);
  EXPECT_EQ(kernelFloat.contributing, fromDepth.contributing);
  for (const char* name : {"brute", "tiled"}) {
    SCOPED_TRACE(name);
    const FrameResult r =
        test::renderOnly(f, test::cachedTechnique(name, TechniqueConfig{}), false);
    const ErrorStats vsDepth = compareToReference(r.image, fromDepth, 0.0);
    const ErrorStats vsKernel = compareToReference(r.image, kernelFloat, 0.0);
    // The position's rounding (~1e-6 units against a 2e-5 distance) is percent of the peak ...
    EXPECT_GT(vsDepth.maxRelPeak, 1e-3);
    // ... while the shading of the kernels' own position is within fp32 rounding.
    EXPECT_LE(vsKernel.maxRelPeak, test::kFp32RelativeTolerance);
  }
}

}  // namespace
}  // namespace ts
