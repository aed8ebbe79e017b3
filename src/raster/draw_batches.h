#pragma once
// The scene's draw batches, the "objects" of forward shading: runs of consecutive triangles that
// share a material, cut every kBatchTriangles (one draw call each, in scene order: the OpenGL
// rasterizer's draws), each with its world-space bounding box. The forward techniques test the
// lights' volumes against these boxes each frame (raster/batch_lights.h) to choose what each light
// pass draws (`forward`) or which lights a batch's draw shades (`forward-single`).
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "scene/scene.h"

namespace ts {

// The longest batch. A Scene keeps no meshes, only triangles in file order; a file with one
// material (the Sponza of ../shared/scenes: 262k triangles) would be one batch that every light
// touches. Consecutive triangles of a mesh lie together, so cutting the runs gives batches with
// boxes that cull; the draws keep the scene's order, so the images do not change.
constexpr uint32_t kBatchTriangles = 1024;

struct DrawBatch {
  uint32_t firstTriangle = 0;
  uint32_t triangles = 0;
  const Material* material = nullptr;  // into the scene (or a default material: none there)
  Bounds bounds;                       // world space, of the batch's vertices
};

// The batches of a scene that passed validateForRaster (raster/scene_validation.h).
std::vector<DrawBatch> drawBatches(const Scene& scene);

// An axis-aligned box in view space.
struct ViewBox {
  glm::vec3 min{0.0f}, max{0.0f};
};

// The view-space box around a world box: its eight corners transformed in double, widened by the
// rounding of the float vertex transform the vertex shader does (a few ulps of the world
// coordinates and the view translation), so no fragment of the batch falls outside it.
ViewBox viewBox(const Bounds& world, const glm::dmat4& viewFromWorld);

}  // namespace ts
