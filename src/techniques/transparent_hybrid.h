#pragma once
// The hybrid of Olsson & Assarsson (2011, Section 4) for the G-buffer techniques with a tile grid
// (`tiled`): the opaque surfaces shaded from the G-buffer by the technique's kernels, then the
// transparent ones (--blend blend) in a tiled forward pass over the same grid, re-binned per tile
// against [znear, the opaque far bound] (TileLightGrid::binForTransparency, tiled-forward-prez's
// binning), drawn in OpenGL back to front over the shaded image (ForwardScene::transparentOver).
#include "techniques/technique.h"
#include "techniques/tile_light_grid.h"

namespace ts {

// Whether `frame` has transparent surfaces for the hybrid to draw.
bool hasTransparentDraws(const DeviceFrame& frame);

// After the technique's opaque frame (its kernels finished, its own counters and light lists
// read: the re-binning overwrites `grid`): reads `opaqueImage` back, draws the transparent
// surfaces over it and puts the composite in result.image. Rows: transparent_grid (the
// re-binning's kernels), grid_copy (the grid to the host and into OpenGL), image_copy (the image
// from the device into OpenGL and the opaque depth copied there), shadow_upload where lights cast
// shadows, transparent (the pass; launches = draws); totalMs their sum with the kernels'. The
// transparent fragments' lights are added to the lighting computations and evaluations; a kept
// assignment (result.assignment) gets the re-binned lists the glass shaded (its `transparent`).
void shadeTransparentOver(ClContext& cl, const cl::Buffer& opaqueImage, DeviceFrame& frame,
                          TileLightGrid& grid, const TechniqueConfig& config, FrameResult& result);

}  // namespace ts
