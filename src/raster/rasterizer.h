#pragma once
// The software rasterizer's entry point and the options every rasterizer takes (the OpenGL one:
// src/raster/gl_rasterizer.h; both behind src/raster/raster_backend.h). What they produce, the
// G-buffer, is src/gbuffer/gbuffer.h.
#include <cstdint>
#include <vector>

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

// One view of a depth-only rasterization (the shadow maps of raster/shadow_maps.h).
struct DepthView {
  glm::dmat4 viewFromWorld{1.0};  // the eye at the origin looking down -Z, +Y up
  bool orthographic = false;
  double halfX = 1.0, halfY = 1.0;   // perspective: tangents of the half angles; orthographic:
                                     // the half extents in world units
  double znear = 0.1, zfar = 100.0;  // the linear depth (-Z of view space) kept
};

// Draws `triangles` (indices of the scene's triangles) seen by `view` into a width x height
// rectangle of `target` (row r at target + r * rowStride; row 0 = the top, NDC y = +1): per pixel
// the nearest fragment's linear depth -Z_view in [znear, zfar], `clear` where none covers it.
// The same triangle setup, clipping, fill rule and alpha test (alphaMode MASK) as rasterize (so
// a G-buffer and a shadow map of one view cover the same pixels); the scene must have passed
// validateForRaster (the caller checks once for all its views). threads: 0 = all hardware threads;
// same output for any count.
void rasterizeDepth(const Scene& scene, const DepthView& view,
                    const std::vector<uint32_t>& triangles, int width, int height, float* target,
                    size_t rowStride, float clear, int threads = 0);

}  // namespace ts
