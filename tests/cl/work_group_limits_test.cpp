// Launches within the device's and the kernel's work-group limits (src/cl/work_group.h). Issue #12:
// the kernels' work-group sizes were fixed up to 256 while CL_DEVICE_MAX_WORK_GROUP_SIZE was read
// and ignored, so on a device allowing 128 (Oclgrind's --max-wgsize 128) every launch failed with
// CL_INVALID_WORK_GROUP_SIZE. The shapes are tested on their own (work_group_test.cpp); here every
// technique renders, on a context capped to a stricter device's limit, what the reference gives.
// tests/extra_tests.cmake also runs these cases with PoCL enforcing the limit itself
// ($POCL_MAX_WORK_GROUP_SIZE), so a launch that ignores it fails there as it would on such a
// device.
#include <gtest/gtest.h>

#include <memory>

#include "cl/work_group.h"
#include "render/frame_setup.h"
#include "techniques/technique.h"
#include "reference_check.h"
#include "test_support.h"

namespace ts {
namespace {

// Every technique on a device allowing `limit` work-items per group: every launch must fit (PoCL
// enforces it under the extra CTest entry) and the image must be the reference's.
void expectEveryTechniqueWithin(size_t limit) {
  ClContext cl(std::getenv("TILESHADE_DEVICE") ? "" : "cpu");
  cl.capWorkGroupSize(limit);
  PreparedFrame f = test::hugeLightsFrame(40);  // 96x64: 16x16 tiles list all 40 lights
  ReferenceImage ref = shadeReference(f.encoded, f.intrinsics, f.lights, f.ambient, 0);
  struct Config {
    int tileW, tileH, lanes;
  };
  for (Config c : {Config{16, 16, 1}, Config{16, 16, 16}, Config{24, 8, 4}}) {
    for (const auto& name : gbufferTechniqueNames()) {
      if (c.tileW != 16 && (name == "brute" || name.rfind("deferred", 0) == 0))
        continue;  // no tiles
      TechniqueConfig config;
      config.tileWidth = c.tileW;
      config.tileHeight = c.tileH;
      config.lanes = c.lanes;
      config.localListCapacity = 16;  // tiled-single chunks its 40 lights
      std::string where = name + " tile " + std::to_string(c.tileW) + "x" +
                          std::to_string(c.tileH) + " lanes " + std::to_string(c.lanes) +
                          ", work-groups of at most " + std::to_string(limit);
      std::unique_ptr<Technique> t;
      ASSERT_NO_THROW(t = createTechnique(name, cl, config)) << where;
      DeviceFrame frame = f.upload(cl);
      FrameRequest request;
      request.wantAssignment = true;
      FrameResult r;
      ASSERT_NO_THROW(r = t->render(frame, request)) << where;
      ErrorStats e = compareToReference(r.image, ref, test::kFp32RelativeTolerance * ref.peak);
      EXPECT_LE(e.maxRelPeak, test::kFp32RelativeTolerance) << where;
      ASSERT_TRUE(r.assignment.has_value()) << where;
      EXPECT_EQ(countMissedContributions(*r.assignment, f.encoded, f.intrinsics, f.lights, 0), 0u)
          << where;
    }
  }
}

TEST(WorkGroupLimits, EveryTechniqueWithinSixtyFourItems) { expectEveryTechniqueWithin(64); }

// Not a power of two, and smaller than a vector of 16 lanes per work-item.
TEST(WorkGroupLimits, EveryTechniqueWithinTwelveItems) { expectEveryTechniqueWithin(12); }

}  // namespace
}  // namespace ts
