#pragma once
// What `forward` and `forward-single` share (and, for the scene to draw, the tiled forward
// techniques): the scene to draw (or the one-line refusal), the
// per-batch light lists found on the host (their own row, batch_lists) and the counters and
// light assignment those lists give.
#include <string>

#include "raster/batch_lights.h"
#include "raster/forward_scene.h"
#include "techniques/technique.h"

namespace ts {

// The frame's scene, or ts::Error: the technique needs a frame rasterized with --raster gl.
ForwardScene& sceneToDraw(const DeviceFrame& frame, const std::string& technique);

// Per draw batch, the lights whose range sphere touches it at the frame's camera
// (raster/batch_lights.h); ms: the host's time for it, view-space boxes included.
IndexLists findBatchLights(ForwardScene& scene, const ViewLights& lights, double& ms);

// The lists' lengths as WorkCounters' list statistics (lights per batch).
void setBatchListCounters(const IndexLists& batchLights, WorkCounters& counters);

// A frame with shadow-casting lights: the maps' upload into OpenGL, its own row (shadow_upload,
// like tiled forward's grid_copy) after the others; nothing without shadows.
void addShadowUploadRow(const ViewLights& lights, const ForwardImage& drawn,
                        std::vector<KernelTime>& kernels);

// A forward pass over an OpenCL light grid (tiled-forward, tiled-forward-prez,
// clustered-forward): its rows after the binning's (grid_copy = the grid's read-back,
// gridReadMs, plus its upload into OpenGL; forward; shadow_upload; transparent with glass), the
// total over every row, and the pass's image.
void addGridForwardPass(const ViewLights& lights, const ForwardImage& drawn, double gridReadMs,
                        FrameResult& result);

// Bins = batches, each pixel in the bin of the batch whose surface it shows; with transparent
// draws, each transparent fragment in its draw's batch (the list its draw shaded).
LightAssignment batchAssignment(const IndexLists& batchLights, const ForwardImage& drawn);

// The lists of a grid a pass shaded transparent fragments with (LightAssignment::transparent):
// each fragment finds its tile's (and, clustered, its slice's) as the fragment shader does.
FragmentLists gridFragmentLists(const ForwardLightGrid& grid);

}  // namespace ts
