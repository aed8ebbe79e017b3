// tiled-single shades a tile whose list outgrows its local-memory list in chunks. These cases
// chunk in every lanes width on frames whose last tiles cross the frame's edge, the sizes at which
// PoCL 3.1 miscompiled the chunk loop (issue #12): the on-screen test of a group's last work-item
// decided for the whole group, so a tile crossing the edge wrote past the end of the image (heap
// corruption, with PoCL's default `loopvec` work-group method) or wrote no pixel at all (`loops`);
// the cause is explained in kernels/tiled_single.cl. CMakeLists.txt also runs these cases with
// PoCL's `loops` method (and its kernel cache off, as the cache does not key on the method), where
// the bug shows as an error, not only as a crash.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "render/frame_setup.h"
#include "scene/scene_loader.h"
#include "techniques/technique.h"
#include "reference_check.h"
#include "test_support.h"

namespace ts {
namespace {

using test::Checked;

struct ChunkCase {
  std::string label;
  PreparedFrame frame;
  TechniqueConfig config;
  uint32_t listMax;  // lights the fullest tile lists (all of them)
};

// The issue's reproduction: street, 257 lights of range 1000 at 160x90 (90 = 5 tiles + 10 rows),
// default 16x16 tiles with a 256-light list (the default then): every tile lists 257 lights, two
// chunks.
ChunkCase issueFrame() {
  SceneOptions options;
  options.lightCount = 257;
  options.lightRange = 1000.0f;
  Scene scene = loadScene("builtin:street", options);
  TechniqueConfig config;
  config.localListCapacity = 256;
  return {"street 160x90, 257 lights", prepareFrame(scene, 0, 160, 90, GBufferFormat::FP32), config,
          257};
}

// Several light tests per work-item: 8x8 tiles (64 work-items) with a 256-light list test 4
// lights each per batch of 256; 600 lights take three batches and three chunks.
ChunkCase severalTestsPerItemFrame() {
  SceneOptions options;
  options.lightCount = 600;
  options.lightRange = 1000.0f;
  Scene scene = loadScene("builtin:street", options);
  TechniqueConfig config;
  config.tileWidth = 8;
  config.tileHeight = 8;
  config.localListCapacity = 256;
  return {"street 67x37, 8x8 tiles, 600 lights, 4 tests per work-item",
          prepareFrame(scene, 0, 67, 37, GBufferFormat::FP32), config, 600};
}

// Many chunks in odd tiles: 7x5 tiles (35 work-items, no whole number of vectors) with a 64-light
// list and 300 lights (5 chunks) on a 97x61 frame (neither size a multiple of the tile's).
ChunkCase oddTileFrame() {
  Scene scene = test::atriumLatticeLights(300);
  TechniqueConfig config;
  config.tileWidth = 7;
  config.tileHeight = 5;
  config.localListCapacity = 64;
  return {"atrium 97x61, 7x5 tiles, 300 lights in 64-light chunks",
          prepareFrame(scene, 0, 97, 61, GBufferFormat::FP32), config, 300};
}

// One pixel: a single tile that is almost entirely off screen, with one light more than the
// default 1024-light list (and batch) holds.
ChunkCase onePixelFrame() {
  SceneOptions options;
  options.lightCount = 1025;
  options.lightRange = 1000.0f;
  Scene scene = loadScene("builtin:street", options);
  return {"street 1x1, 1025 lights", prepareFrame(scene, 0, 1, 1, GBufferFormat::FP32), {}, 1025};
}

size_t nonFinitePixels(const std::vector<glm::vec4>& image) {
  size_t n = 0;
  for (const auto& p : image)
    n += !(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));
  return n;
}

void expectChunkedTilesCorrect(const ChunkCase& c) {
  ReferenceImage ref =
      shadeReference(c.frame.encoded, c.frame.intrinsics, c.frame.lights, c.frame.ambient, 0);
  for (int lanes : {1, 2, 4, 8, 16}) {
    TechniqueConfig config = c.config;
    config.lanes = lanes;
    auto technique = createTechnique("tiled-single", test::context(), config);
    ASSERT_EQ(technique->lanes(), lanes) << "the tile must fit local memory in lanes";
    Checked r = test::renderAndCheck(c.frame, *technique, ref);
    std::string where = c.label + ", lanes " + std::to_string(lanes);
    EXPECT_EQ(r.result.counters.listMax, c.listMax) << where << ": the list must chunk";
    EXPECT_EQ(nonFinitePixels(r.result.image), 0u) << where;
    EXPECT_EQ(r.missed, 0u) << where;
    EXPECT_LE(r.error.maxRelPeak, test::kFp32RelativeTolerance) << where;
  }
}

TEST(TiledSingleChunks, IssueFrameInEveryLanesWidth) { expectChunkedTilesCorrect(issueFrame()); }

TEST(TiledSingleChunks, ManyChunksInOddTilesInEveryLanesWidth) {
  expectChunkedTilesCorrect(oddTileFrame());
}

TEST(TiledSingleChunks, SeveralTestsPerWorkItemInEveryLanesWidth) {
  expectChunkedTilesCorrect(severalTestsPerItemFrame());
}

TEST(TiledSingleChunks, OnePixelFrameInEveryLanesWidth) {
  expectChunkedTilesCorrect(onePixelFrame());
}

}  // namespace
}  // namespace ts
