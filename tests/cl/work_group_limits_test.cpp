// Launches within the device's and the kernel's work-group limits (src/cl/work_group.h). Issue #12:
// the kernels' work-group sizes were fixed up to 256 while CL_DEVICE_MAX_WORK_GROUP_SIZE was read
// and ignored, so on a device allowing 128 (Oclgrind's --max-wgsize 128) every launch failed with
// CL_INVALID_WORK_GROUP_SIZE. The shapes are tested on their own; then every technique renders, on a
// context capped to a stricter device's limit, what the reference gives. tests/extra_tests.cmake
// also runs these cases with PoCL enforcing the limit itself ($POCL_MAX_WORK_GROUP_SIZE), so a
// launch that ignores it fails there as it would on such a device.
#include <gtest/gtest.h>

#include <memory>

#include "cl/work_group.h"
#include "render/frame_setup.h"
#include "techniques/technique.h"
#include "reference_check.h"
#include "test_support.h"

namespace ts {
namespace {

GroupLimit limitOf(size_t size, size_t items = 1 << 20) {
  GroupLimit l;
  l.size = size;
  l.items = {{items, items}};
  return l;
}

TEST(WorkGroupShapes, FitTheLimitAndKeepThePreferredShapeWhenItFits) {
  for (size_t limit : {1, 2, 3, 7, 32, 48, 64, 100, 128, 255, 256, 1024}) {
    GroupShape g = fitGroup(16, 16, limitOf(limit));
    EXPECT_LE(g.size(), limit);
    EXPECT_GE(g.size() * 4, std::min<size_t>(limit, 256)) << "no more than halved per side";
    size_t p = powerOfTwoGroup(256, limitOf(limit));
    EXPECT_LE(p, limit);
    EXPECT_EQ(p & (p - 1), 0u) << p << " is a power of two";
    EXPECT_GT(p * 2, std::min<size_t>(limit, 256));
  }
  EXPECT_EQ(fitGroup(16, 16, limitOf(256)).size(), 256u);
  EXPECT_EQ(fitGroup(7, 5, limitOf(256)).size(), 35u);
  EXPECT_EQ(fitGroup(16, 16, limitOf(128)).size(), 128u);
  GroupShape perDimension = fitGroup(16, 16, limitOf(256, 8));
  EXPECT_EQ(perDimension.x, 8u);
  EXPECT_EQ(perDimension.y, 8u);
}

TEST(WorkGroupShapes, TileDividingGroupsDivideTheTileWithinTheLimit) {
  for (int tw : {1, 5, 7, 8, 16, 17, 24, 32, 48})
    for (int th : {1, 3, 8, 16, 24})
      for (size_t limit : {1, 6, 32, 64, 128, 256}) {
        GroupShape g = tileDividingGroup(tw, th, limitOf(limit));
        EXPECT_EQ(tw % g.x, 0u) << tw << "x" << th << " limit " << limit;
        EXPECT_EQ(th % g.y, 0u) << tw << "x" << th << " limit " << limit;
        EXPECT_LE(g.size(), limit);
        EXPECT_LE(g.x, 16u);
        EXPECT_LE(g.y, 16u);
      }
  // Unlimited: the largest divisors up to 16, as before limits were read (24 -> 12, 48 -> 16).
  GroupShape g = tileDividingGroup(24, 48, limitOf(1024));
  EXPECT_EQ(g.x, 12u);
  EXPECT_EQ(g.y, 16u);
  EXPECT_EQ(tileDividingGroup(16, 16, limitOf(128)).size(), 128u);
}

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
    for (const auto& name : techniqueNames()) {
      if (c.tileW != 16 && (name == "brute" || name.rfind("deferred", 0) == 0)) continue;  // no tiles
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
