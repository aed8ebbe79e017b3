#pragma once
// The shadow maps of a frame drawn into their atlas (raster/shadow_atlas.h plans it): depth-only
// software rasterization (rasterizeDepth) of each face's triangles, those of the draw batches
// (raster/draw_batches.h) whose boxes touch the face's frustum. Nothing shades with them yet.
#include <cstdint>
#include <vector>

#include "raster/shadow_atlas.h"
#include "scene/scene.h"

namespace ts {

struct ShadowAtlas {
  ShadowAtlasLayout layout;
  // width x height floats, row 0 = the top: each face's linear depths (ShadowFace), 0 in texels
  // that belong to no face.
  std::vector<float> depth;
  std::vector<uint64_t> faceTriangles;  // per face of layout.faces: the triangles drawn
  double drawMs = 0.0;                  // culling and drawing every face (not the planning)

  uint64_t trianglesDrawn() const;
  float at(int x, int y) const { return depth[size_t(y) * size_t(layout.width) + size_t(x)]; }
};

// Draws every face of `layout` (planned for this scene's lights). threads: 0 = all hardware
// threads; the same atlas for any count. Throws ts::Error for a scene the rasterizer refuses.
ShadowAtlas drawShadowAtlas(const Scene& scene, ShadowAtlasLayout layout, int threads = 0);

// Whether a world box may hold something `face` sees (its frustum against the box's view-space
// box; conservative: false only when the box lies wholly outside one plane).
bool touchesFace(const Bounds& world, const ShadowFace& face);

}  // namespace ts
