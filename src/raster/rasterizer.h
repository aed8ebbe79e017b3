#pragma once
// The software rasterizer's entry point and the options every rasterizer takes (the OpenGL one:
// src/raster/gl_rasterizer.h; both behind src/raster/raster_backend.h). What they produce, the
// G-buffer, is src/gbuffer/gbuffer.h.
#include "gbuffer/gbuffer.h"
#include "scene/scene.h"

namespace ts {

struct RasterOptions {
  ShadingModel model = ShadingModel::BlinnPhong;  // whose material terms the planes hold
  int threads = 0;              // 0 = all hardware threads (at most 256); same output for any
                                // count
  bool normalMaps = true;       // apply the materials' normal maps (SceneFeatures::normalMaps);
                                // false: the interpolated normals, no tangent work
  bool triangleIds = false;     // fill GBuffer::triangleId
  bool fragmentCounts = false;  // fill GBuffer::fragmentCount
};

// Renders the scene from `camera` into a G-buffer of width x height (1 to 65536 per side; throws
// ts::Error otherwise, or for a scene with out-of-range vertex/material/texture indices).
// Design notes (fill rule, clipping, precision, threading): src/raster/rasterizer.cpp.
GBuffer rasterize(const Scene& scene, const SceneCamera& camera, int width, int height,
                  const RasterOptions& options = {});

}  // namespace ts
