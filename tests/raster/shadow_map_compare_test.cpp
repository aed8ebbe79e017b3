// compareShadowAtlases (src/raster/shadow_map_compare.h) on hand-made atlases: what it calls a
// silhouette, a moved edge between two surfaces, a hole, a depth beyond the bound (float rounding
// plus the snapped edges' move times the slope), and texels of no face.
#include <gtest/gtest.h>

#include <functional>

#include "raster/shadow_map_compare.h"
#include "util/error.h"

namespace ts {
namespace {

constexpr int kSize = 16;
constexpr float kFar = 10.0f;

// One 16x16 face in the left half of a 32x16 atlas (the right half belongs to no face), every
// texel from `depth(x, y)` (kFar: empty).
ShadowAtlas atlasOf(const std::function<float(int, int)>& depth) {
  ShadowAtlas a;
  a.layout.width = 2 * kSize;
  a.layout.height = kSize;
  ShadowFace f;
  f.size = kSize;
  f.view.zfar = kFar;
  a.layout.faces.push_back(f);
  a.depth.assign(size_t(2 * kSize * kSize), 0.0f);
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) a.depth[size_t(y * 2 * kSize + x)] = depth(x, y);
  return a;
}

// A square at depth 5 over [x0, x0 + 6) x [4, 10), over `floor` (kFar: nothing).
ShadowAtlas square(int x0, float floor = kFar) {
  return atlasOf(
      [=](int x, int y) { return x >= x0 && x < x0 + 6 && y >= 4 && y < 10 ? 5.0f : floor; });
}

const Scene kNoVertices;

TEST(ShadowMapCompare, IdenticalMapsAgreeEverywhere) {
  const ShadowAtlas a = square(4);
  const ShadowAtlasComparison c = compareShadowAtlases(a, a, kNoVertices);
  EXPECT_EQ(c.texels, uint64_t(kSize * kSize));
  EXPECT_EQ(c.bothCovered, 36u);
  EXPECT_EQ(c.onlyA + c.onlyB + c.depthDiffers + c.unusedNonZero, 0u);
  EXPECT_EQ(c.silhouetteA, 64u - 16u);  // the 8x8 ring around and inside the square's outline
  EXPECT_EQ(c.maxDepthRel, 0.0);
}

TEST(ShadowMapCompare, AnEdgeMovedByATexelIsOnTheSilhouette) {
  const ShadowAtlasComparison c = compareShadowAtlases(square(4), square(5), kNoVertices);
  EXPECT_EQ(c.onlyA, 6u);
  EXPECT_EQ(c.onlyB, 6u);
  EXPECT_EQ(c.mismatchesOffSilhouette, 0u);
  // Over a floor: the square's edge moved, another surface on 12 texels, all on the edge.
  const ShadowAtlasComparison f =
      compareShadowAtlases(square(4, 8.0f), square(5, 8.0f), kNoVertices);
  EXPECT_EQ(f.onlyA + f.onlyB, 0u);
  EXPECT_EQ(f.depthDiffers, 12u);
  EXPECT_EQ(f.depthDiffersOffEdge, 0u);
  EXPECT_EQ(f.maxDepthRel, 0.0);
}

TEST(ShadowMapCompare, AHoleAndASurfaceJumpAreOffTheSilhouette) {
  ShadowAtlas holed = square(4), raised = square(4, 8.0f);
  holed.depth[size_t(6 * 2 * kSize + 6)] = kFar;  // inside the square
  raised.depth[size_t(6 * 2 * kSize + 6)] = 2.0f;
  const ShadowAtlasComparison h = compareShadowAtlases(square(4), holed, kNoVertices);
  EXPECT_EQ(h.onlyA, 1u);
  EXPECT_EQ(h.mismatchesOffSilhouette, 1u);
  const ShadowAtlasComparison r = compareShadowAtlases(square(4, 8.0f), raised, kNoVertices);
  EXPECT_EQ(r.depthDiffers, 1u);
  EXPECT_EQ(r.depthDiffersOffEdge, 1u);
  EXPECT_GT(r.worstRatio, 1.0);
  EXPECT_EQ(r.worstX, 6);
  EXPECT_EQ(r.worstY, 6);
}

TEST(ShadowMapCompare, TheBoundIsFloatRoundingPlusTheSnapMoveTimesTheSlope) {
  // A ramp along x: slope 0.25 per texel, depth 2 + 0.25 x.
  auto ramp = [](double offset) {
    return atlasOf([=](int x, int) { return float(2.0 + 0.25 * x + offset); });
  };
  // Within the snap term at the ramp's far end (2 * kShadowSnapMove * 0.25 / 5.75 ~ 8.7e-4
  // relative), beyond it near its start.
  const ShadowAtlasComparison in =
      compareShadowAtlases(ramp(0.0), ramp(0.5 * kShadowSnapMove * 0.25), kNoVertices);
  EXPECT_EQ(in.depthDiffers, 0u) << in.summary();
  EXPECT_LE(in.worstRatio, 1.0);
  EXPECT_GT(in.maxDepthRel, 0.0);
  const ShadowAtlasComparison out =
      compareShadowAtlases(ramp(0.0), ramp(3.0 * kShadowSnapMove * 0.25), kNoVertices);
  EXPECT_EQ(out.depthDiffers, uint64_t(kSize * kSize));
  // No neighbour holds both depths (the ramp moves by a quarter a texel): no edge explains it.
  EXPECT_EQ(out.depthDiffersOffEdge, uint64_t(kSize * kSize));
  EXPECT_GT(out.worstRatio, 1.0);
  // Flat: float rounding only. One float ulp at 4 agrees, 32 ulps do not.
  auto flat = [](float d) { return atlasOf([=](int, int) { return d; }); };
  EXPECT_EQ(
      compareShadowAtlases(flat(4.0f), flat(std::nextafter(4.0f, 5.0f)), kNoVertices).depthDiffers,
      0u);
  const ShadowAtlasComparison far =
      compareShadowAtlases(flat(4.0f), flat(4.0f * (1.0f + 32 * 1.1920929e-7f)), kNoVertices);
  EXPECT_EQ(far.depthDiffersOffEdge, uint64_t(kSize * kSize));
  // A larger world (W) widens it: the same 32 ulps agree where coordinates reach 100.
  Scene big;
  big.vertices.resize(1);
  big.vertices[0].position = glm::vec3(0.0f, -100.0f, 0.0f);
  EXPECT_EQ(
      compareShadowAtlases(flat(4.0f), flat(4.0f * (1.0f + 32 * 1.1920929e-7f)), big).depthDiffers,
      0u);
}

TEST(ShadowMapCompare, ASliverOneTexelThinIsCountedApart) {
  // A column one texel wide (x = 7, rows 2..11) over nothing: its slope across is not in the map.
  auto column = [](float d) {
    return atlasOf([=](int x, int y) { return x == 7 && y >= 2 && y < 12 ? d : kFar; });
  };
  const ShadowAtlasComparison c = compareShadowAtlases(column(5.0f), column(5.01f), kNoVertices);
  EXPECT_EQ(c.thinDiffers, 10u);
  EXPECT_NEAR(c.maxThinDepthRel, 0.002, 1e-6);
  EXPECT_EQ(c.depthDiffersOffEdge, 0u);
  EXPECT_EQ(c.maxDepthRel, 0.0);
  // Two texels wide: the same difference is off the bound, not thin.
  auto wide = [](float d) {
    return atlasOf([=](int x, int y) { return (x == 7 || x == 8) && y >= 2 && y < 12 ? d : kFar; });
  };
  const ShadowAtlasComparison w = compareShadowAtlases(wide(5.0f), wide(5.01f), kNoVertices);
  EXPECT_EQ(w.thinDiffers, 0u);
  EXPECT_EQ(w.depthDiffersOffEdge, 20u);
}

TEST(ShadowMapCompare, UnusedTexelsMustBeZeroAndLayoutsMustMatch) {
  ShadowAtlas a = square(4), b = square(4);
  b.depth[size_t(3 * 2 * kSize + 20)] = 1.0f;  // the right half: no face
  EXPECT_EQ(compareShadowAtlases(a, b, kNoVertices).unusedNonZero, 1u);
  b.layout.faces[0].x = 16;
  EXPECT_THROW(compareShadowAtlases(a, b, kNoVertices), Error);
}

}  // namespace
}  // namespace ts
