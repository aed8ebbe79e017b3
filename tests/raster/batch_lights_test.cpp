// The forward techniques' draw batches and their light lists (src/raster/draw_batches.h,
// batch_lights.h): batches cover the scene's triangles in order, each box holds its vertices in
// view space, the sphere test agrees with a brute-force distance to the batch's vertices, and
// the transposed lists hold the same pairs.
#include <gtest/gtest.h>

#include <random>
#include <set>
#include <utility>

#include "raster/batch_lights.h"
#include "raster/draw_batches.h"
#include "scene/scene_loader.h"
#include "scene/view_space_lights.h"

namespace ts {
namespace {

const Scene& street() {
  static const Scene scene = makeBuiltinScene("street", "few", 1);
  return scene;
}

TEST(DrawBatches, CoverTheTrianglesInOrderOneMaterialEach) {
  const Scene& scene = street();
  const std::vector<DrawBatch> batches = drawBatches(scene);
  ASSERT_GT(batches.size(), 10u);  // the street interleaves its materials: many small batches
  uint32_t next = 0;
  for (size_t b = 0; b < batches.size(); ++b) {
    const DrawBatch& d = batches[b];
    EXPECT_EQ(d.firstTriangle, next);
    ASSERT_GT(d.triangles, 0u);
    EXPECT_LE(d.triangles, kBatchTriangles);
    for (uint32_t t = d.firstTriangle; t < d.firstTriangle + d.triangles; ++t)
      EXPECT_EQ(d.material, &scene.materials[scene.triangleMaterial[t]]);
    // A batch ends where the material changes or at the longest batch.
    if (b + 1 < batches.size() && d.triangles < kBatchTriangles) {
      EXPECT_NE(d.material, batches[b + 1].material);
    }
    next += d.triangles;
  }
  EXPECT_EQ(next, scene.triangleCount());
}

// One material over 2500 triangles along x: three batches, each boxing only its own stretch.
TEST(DrawBatches, LongRunsAreCutIntoBatchesThatCull) {
  Scene scene;
  scene.materials.resize(1);
  for (uint32_t t = 0; t < 2500; ++t) {
    const float x = float(t);
    for (glm::vec3 p : {glm::vec3(x, 0, 0), glm::vec3(x + 1, 0, 0), glm::vec3(x, 1, 0)}) {
      scene.indices.push_back(uint32_t(scene.vertices.size()));
      scene.vertices.push_back({p, glm::vec3(0, 0, 1), glm::vec2(0)});
    }
    scene.triangleMaterial.push_back(0);
  }
  const std::vector<DrawBatch> batches = drawBatches(scene);
  ASSERT_EQ(batches.size(), 3u);
  EXPECT_EQ(batches[0].triangles, kBatchTriangles);
  EXPECT_EQ(batches[1].firstTriangle, kBatchTriangles);
  EXPECT_EQ(batches[2].triangles, 2500u - 2 * kBatchTriangles);
  EXPECT_EQ(batches[1].bounds.min.x, float(kBatchTriangles));
  EXPECT_EQ(batches[1].bounds.max.x, float(2 * kBatchTriangles));
}

// Every vertex of a batch, transformed as the vertex shader does (float), lies in its view box.
TEST(DrawBatches, ViewBoxesHoldTheFloatTransformedVertices) {
  const Scene& scene = street();
  const std::vector<DrawBatch> batches = drawBatches(scene);
  for (int c = 0; c < 3; ++c) {
    const SceneCamera& camera = scene.camera(c * 7);
    const glm::mat4 viewFromWorld(camera.viewFromWorld);
    for (const DrawBatch& d : batches) {
      const ViewBox box = viewBox(d.bounds, camera.viewFromWorld);
      for (uint32_t t = d.firstTriangle; t < d.firstTriangle + d.triangles; ++t)
        for (int k = 0; k < 3; ++k) {
          const glm::vec3 p = glm::vec3(
              viewFromWorld * glm::vec4(scene.vertices[scene.indices[3 * t + k]].position, 1.0f));
          for (int a = 0; a < 3; ++a) {
            EXPECT_GE(p[a], box.min[a]);
            EXPECT_LE(p[a], box.max[a]);
          }
        }
    }
  }
}

TEST(BatchLights, SphereTestIsTheDistanceToTheBox) {
  const ViewBox box{glm::vec3(-1.0f, -2.0f, -3.0f), glm::vec3(1.0f, 2.0f, 3.0f)};
  EXPECT_TRUE(sphereTouchesBox(glm::vec4(0.0f, 0.0f, 0.0f, 0.1f), box));   // inside
  EXPECT_TRUE(sphereTouchesBox(glm::vec4(2.0f, 0.0f, 0.0f, 1.01f), box));  // 1 from a face
  EXPECT_FALSE(sphereTouchesBox(glm::vec4(2.0f, 0.0f, 0.0f, 0.99f), box));
  // 1 from a corner along each axis: distance sqrt(3).
  EXPECT_TRUE(sphereTouchesBox(glm::vec4(2.0f, 3.0f, 4.0f, 1.7330f), box));
  EXPECT_FALSE(sphereTouchesBox(glm::vec4(2.0f, 3.0f, 4.0f, 1.7300f), box));
}

// On the street's lights and batches: a light is in a batch's list exactly where the sphere
// reaches the batch's box, and every light that reaches one of the batch's vertices is listed.
TEST(BatchLights, ListsHoldEveryLightThatReachesABatch) {
  const Scene& scene = makeBuiltinScene("street", "many", 1);
  const SceneCamera& camera = scene.camera(0);
  const ViewLights lights = toViewSpace(scene.lights, camera.viewFromWorld);
  ASSERT_GT(lights.size(), 100u);
  const std::vector<DrawBatch> batches = drawBatches(scene);
  std::vector<ViewBox> boxes;
  for (const DrawBatch& d : batches) boxes.push_back(viewBox(d.bounds, camera.viewFromWorld));
  const IndexLists lists = batchLightLists(boxes, lights);
  ASSERT_EQ(lists.size(), batches.size());
  const glm::mat4 viewFromWorld(camera.viewFromWorld);
  size_t reached = 0;
  for (size_t b = 0; b < batches.size(); ++b) {
    const std::set<uint32_t> listed(lists.items.begin() + lists.offsets[b],
                                    lists.items.begin() + lists.offsets[b] + lists.counts[b]);
    EXPECT_TRUE(std::is_sorted(lists.items.begin() + lists.offsets[b],
                               lists.items.begin() + lists.offsets[b] + lists.counts[b]));
    for (uint32_t i = 0; i < lights.size(); ++i)
      EXPECT_EQ(listed.count(i) > 0, sphereTouchesBox(lights.positionRange[i], boxes[b]));
    const DrawBatch& d = batches[b];
    for (uint32_t t = d.firstTriangle; t < d.firstTriangle + d.triangles; ++t)
      for (int k = 0; k < 3; ++k) {
        const glm::vec3 p = glm::vec3(
            viewFromWorld * glm::vec4(scene.vertices[scene.indices[3 * t + k]].position, 1.0f));
        for (uint32_t i = 0; i < lights.size(); ++i) {
          const glm::vec4 l = lights.positionRange[i];
          if (glm::length(glm::vec3(l) - p) < l.w) {
            ++reached;
            EXPECT_EQ(listed.count(i), 1u) << "batch " << b << " light " << i;
          }
        }
      }
  }
  EXPECT_GT(reached, 0u);
  EXPECT_LT(lists.items.size(), size_t(lights.size()) * batches.size());  // it culls
}

TEST(BatchLights, TransposedListsHoldTheSamePairs) {
  std::mt19937 rng(5);
  IndexLists lists;
  std::set<std::pair<uint32_t, uint32_t>> pairs;
  const uint32_t owners = 40, targets = 25;
  for (uint32_t o = 0; o < owners; ++o) {
    lists.offsets.push_back(uint32_t(lists.items.size()));
    for (uint32_t t = 0; t < targets; ++t)
      if (rng() % 3 == 0) {
        lists.items.push_back(t);
        pairs.insert({o, t});
      }
    lists.counts.push_back(uint32_t(lists.items.size()) - lists.offsets.back());
  }
  const IndexLists back = transposeLists(lists, targets);
  ASSERT_EQ(back.size(), targets);
  EXPECT_EQ(back.items.size(), pairs.size());
  std::set<std::pair<uint32_t, uint32_t>> seen;
  for (uint32_t t = 0; t < targets; ++t)
    for (uint32_t k = 0; k < back.counts[t]; ++k) {
      const uint32_t o = back.items[back.offsets[t] + k];
      if (k > 0) {
        EXPECT_LT(back.items[back.offsets[t] + k - 1], o);
      }
      seen.insert({o, t});
    }
  EXPECT_EQ(seen, pairs);
  EXPECT_EQ(transposeLists(back, owners).items, lists.items);
}

}  // namespace
}  // namespace ts
