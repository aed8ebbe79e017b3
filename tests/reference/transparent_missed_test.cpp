// The rule by which the transparent `missed` finds the list a glass fragment shaded
// (reference/transparent_missed.h): its batch's, its tile's, its cluster's from its own depth, and
// the one-line errors where the rule cannot place it; a light left out of that list is counted.
#include <gtest/gtest.h>

#include <cmath>

#include "reference/transparent_missed.h"
#include "util/error.h"

namespace ts {
namespace {

TransparentFragment fragmentAt(int x, int y, float depth, int batch = -1) {
  TransparentFragment f;
  f.x = x;
  f.y = y;
  f.batch = batch;
  f.position = glm::vec3(0.0f, 0.0f, -depth);
  f.alpha = 0.5f;
  f.normal = glm::vec3(0.0f, 0.0f, 1.0f);  // facing the eye
  f.diffuse = glm::vec4(0.8f, 0.8f, 0.8f, 0.0f);
  return f;
}

FragmentLists tiles(int tileW, int tileH, int tilesX, int tilesY, int slices = 1) {
  FragmentLists l;
  l.tileW = tileW;
  l.tileH = tileH;
  l.tilesX = tilesX;
  l.slices = slices;
  const size_t bins = size_t(tilesX) * size_t(tilesY) * size_t(slices);
  l.binOffset.assign(bins, 0);
  l.binCount.assign(bins, 0);
  return l;
}

TEST(TransparentMissed, FragmentFindsItsTileClusterOrBatch) {
  const FragmentLists grid = tiles(16, 8, 5, 3);
  EXPECT_EQ(transparentFragmentBin(grid, fragmentAt(0, 0, 2.0f)), 0u);
  EXPECT_EQ(transparentFragmentBin(grid, fragmentAt(33, 9, 2.0f)), 5u + 2u);
  FragmentLists clustered = tiles(16, 8, 5, 3, 4);
  clustered.sliceNear = 1.0f;
  clustered.sliceScale = 4.0f / std::log(16.0f);  // slices at depths 1, 2, 4, 8, 16
  EXPECT_EQ(transparentFragmentBin(clustered, fragmentAt(17, 0, 3.0f)), 1u * 4u + 1u);
  EXPECT_EQ(transparentFragmentBin(clustered, fragmentAt(17, 0, 0.5f)), 4u);        // clamped
  EXPECT_EQ(transparentFragmentBin(clustered, fragmentAt(17, 0, 99.0f)), 4u + 3u);  // clamped
  FragmentLists batches;
  batches.byBatch = true;
  batches.binOffset.assign(3, 0);
  batches.binCount.assign(3, 0);
  EXPECT_EQ(transparentFragmentBin(batches, fragmentAt(500, 500, 2.0f, 2)), 2u);
}

TEST(TransparentMissed, UnplaceableFragmentIsAnError) {
  const FragmentLists grid = tiles(16, 8, 5, 3);
  EXPECT_THROW(transparentFragmentBin(grid, fragmentAt(80, 0, 2.0f)), Error);  // past tilesX
  EXPECT_THROW(transparentFragmentBin(grid, fragmentAt(0, 24, 2.0f)), Error);  // past the rows
  EXPECT_THROW(transparentFragmentBin(grid, fragmentAt(-1, 0, 2.0f)), Error);
  FragmentLists batches;
  batches.byBatch = true;
  batches.binOffset.assign(1, 0);
  batches.binCount.assign(1, 0);
  EXPECT_THROW(transparentFragmentBin(batches, fragmentAt(0, 0, 2.0f)), Error);  // no batch
  EXPECT_THROW(transparentFragmentBin(batches, fragmentAt(0, 0, 2.0f, 1)), Error);
  EXPECT_THROW(transparentFragmentBin(FragmentLists{}, fragmentAt(0, 0, 2.0f)), Error);
}

// One light in front of the fragment: listed, no miss; left out of its tile's list, one miss
// (whatever other tiles list); out of reach, no contribution and so no miss.
TEST(TransparentMissed, LightLeftOutOfTheFragmentsListIsCounted) {
  const EncodedGBuffer planes;  // Blinn-Phong: the fragment's own terms
  ViewLights lights;
  lights.addPoint(glm::vec3(0.0f, 0.0f, -1.0f), 5.0f, glm::vec3(1.0f));
  const std::vector<TransparentFragment> frags = {fragmentAt(20, 0, 2.0f)};
  FragmentLists grid = tiles(16, 8, 2, 1);
  grid.binLights = {0u};
  grid.binOffset = {0u, 0u};
  grid.binCount = {1u, 0u};  // listed in tile 0, not in the fragment's tile 1
  EXPECT_EQ(countMissedTransparent(grid, frags, lights, 0, planes), 1u);
  grid.binCount = {0u, 1u};
  EXPECT_EQ(countMissedTransparent(grid, frags, lights, 0, planes), 0u);
  ViewLights far;
  far.addPoint(glm::vec3(0.0f, 0.0f, -100.0f), 5.0f, glm::vec3(1.0f));
  grid.binCount = {0u, 0u};
  EXPECT_EQ(countMissedTransparent(grid, frags, far, 0, planes), 0u);
  grid.binCount = {0u, 2u};  // past binLights
  EXPECT_THROW(countMissedTransparent(grid, frags, lights, 0, planes), Error);
}

}  // namespace
}  // namespace ts
