// Work-group shapes within a device's and a kernel's limits (src/cl/work_group.h), on their own;
// work_group_limits_test.cpp renders every technique under such limits (issue #12).
#include <gtest/gtest.h>

#include <algorithm>

#include "cl/work_group.h"

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

}  // namespace
}  // namespace ts
