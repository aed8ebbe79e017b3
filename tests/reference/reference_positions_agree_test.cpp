// The two references of `--check` (src/reference/reference.h) on the host: positions from the
// stored depth in double and the kernels' own float positions agree to float rounding where no
// light is ill-conditioned (where one is: reference_positions_test.cpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "reference/reference.h"
#include "render/frame_setup.h"
#include "reference_check.h"

namespace ts {
namespace {

TEST(ReferencePositions, TheSameAwayFromIllConditionedPlaces) {
  const PreparedFrame f =
      prepareFrame(test::builtinScene("street", "many"), 0, 64, 36, GBufferFormat::FP32);
  const ReferenceImage fromDepth = shadeReference(f.encoded, f.intrinsics, f.lights, f.ambient, 0);
  const ReferenceImage kernelFloat = shadeReference(f.encoded, f.intrinsics, f.lights, f.ambient, 0,
                                                    0, {}, ReferencePositions::KernelFloat);
  ASSERT_GT(fromDepth.peak, 0.0);
  double worst = 0.0;
  for (size_t i = 0; i < fromDepth.rgb.size(); ++i)
    for (int c = 0; c < 3; ++c)
      worst = std::max(worst, std::abs(fromDepth.rgb[i][c] - kernelFloat.rgb[i][c]));
  EXPECT_GT(worst, 0.0) << "the float positions should differ from the double ones somewhere";
  EXPECT_LE(worst / fromDepth.peak, 1e-5);
}

}  // namespace
}  // namespace ts
