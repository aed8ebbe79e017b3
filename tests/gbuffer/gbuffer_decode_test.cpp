// The --dump decode: the dump kernel's values for a rendered scene equal the host decoder's (which
// feeds the reference), in every Blinn-Phong G-buffer layout.
#include <gtest/gtest.h>

#include <cmath>

#include "reference/reference.h"
#include "render/frame_setup.h"
#include "render/gbuffer_dump.h"
#include "reference_check.h"
#include "test_support.h"

namespace ts {
namespace {

using test::builtinScene;

// Decoding: the dump kernel's values equal the host decoder's (which feeds the reference).
TEST(GBufferDecode, KernelMatchesHostDecoder) {
  for (GBufferFormat format : {GBufferFormat::FP32, GBufferFormat::FP16, GBufferFormat::PACKED}) {
    PreparedFrame f = prepareFrame(builtinScene("street", "few"), 10, 120, 72, format);
    DeviceFrame frame = f.upload(test::context());
    const std::vector<float> d =
        decodeOnDevice(test::context(), frame, format, TechniqueConfig().features);
    size_t geometry = 0;
    for (int y = 0; y < 72; ++y)
      for (int x = 0; x < 120; ++x) {
        const float* o = &d[(size_t(y) * 120 + x) * 17];
        SurfaceD s;
        bool valid = decodeSurface(f.encoded, f.intrinsics, x, y, s);
        ASSERT_EQ(o[16], valid ? 1.0f : 0.0f);
        if (!valid) continue;
        ++geometry;
        for (int c = 0; c < 3; ++c) {
          EXPECT_NEAR(o[0 + c], s.P[c], 1e-6 * std::abs(s.P.z) + 1e-7);
          EXPECT_NEAR(o[3 + c], s.N[c], 1e-6);
          EXPECT_EQ(o[6 + c], float(s.kd[c]));  // colours decode exactly
          EXPECT_EQ(o[9 + c], float(s.ks[c]));
          EXPECT_EQ(o[13 + c], float(s.ke[c]));
        }
        // Packed shininess is decoded with exp2, which OpenCL allows 3 ulp; the other layouts
        // store it and must match exactly.
        if (format == GBufferFormat::PACKED)
          EXPECT_NEAR(o[12], s.gloss, 3 * std::ldexp(1.0, std::ilogb(s.gloss) - 23));
        else EXPECT_EQ(o[12], float(s.gloss));
      }
    EXPECT_GT(geometry, 0u);
  }
}

}  // namespace
}  // namespace ts
