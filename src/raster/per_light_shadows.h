#pragma once
// --shadow-storage per-light (issue #18; docs/shadows.md): traditional deferred shades one light
// per launch, so it needs only that light's shadow maps resident. The frame's atlas plan
// (shadow_atlas.h: the same faces, sizes and views, so the same texels) is split into passes:
// the directional lights' faces together (the base pass shades them all), then one pass per point
// or spot light. A pass's faces lie side by side in a small atlas of their own (a strip from the
// top left, as tall as its largest face), drawn just before its light's launch into one buffer
// that every pass reuses. Sampling reads a face's texels relative to its rectangle, so the image
// is the atlas path's, bit for bit.
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "raster/draw_batches.h"
#include "raster/shadow_maps.h"
#include "scene/scene.h"

namespace ts {

struct ShadowPass {
  std::vector<size_t> faces;  // indices into the frame's layout.faces (its face table's order)
  ShadowAtlasLayout layout;   // those faces side by side from (0, 0), in the same order
};

class PerLightShadowMaps {
 public:
  // `atlas`: the frame's plan (planShadowAtlas). The scene must outlive this; throws ts::Error
  // for a scene the rasterizer refuses.
  PerLightShadowMaps(const Scene& scene, const ShadowAtlasLayout& atlas);

  // The pass of the point or spot light whose first face is `firstFace` (ViewLights::shadow);
  // ts::Error for a face that starts no such pass.
  const ShadowPass& passOf(int firstFace) const;
  // The directional lights' pass; null when none casts.
  const ShadowPass* directionalPass() const;
  // The frame's face table (attachShadowMaps, kernels/shadows.h) with each face's rectangle and
  // atlas width those of its pass: what the kernels sample a pass's atlas with.
  std::vector<glm::vec4> passFaceTable(const std::vector<glm::vec4>& atlasTable) const;
  // Draws the pass's faces (drawShadowAtlas; threads 0 = every hardware thread).
  ShadowAtlas draw(const ShadowPass& pass, int threads = 0) const;
  // The reused atlas: the largest pass's bytes.
  uint64_t residentBytes() const;

 private:
  const Scene& scene_;
  std::vector<DrawBatch> batches_;
  std::vector<ShadowPass> passes_;
  std::vector<int> passOfFace_;  // per face of the frame's layout: its pass
  int directional_ = -1;         // the directional lights' pass, -1: none
};

}  // namespace ts
