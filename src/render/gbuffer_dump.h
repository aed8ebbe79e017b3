#pragma once
// `render --dump`: the frame's G-buffer as the kernels decode it, its lights and a descriptor
// (src/gbuffer/gbuffer_files.h), which `--gbuffer-in` reads back exactly.
// It launches the dump kernel on the frame's DeviceFrame (modules cl, techniques, above gbuffer),
// so it is the render command's device step and stays here; the files' format is the gbuffer
// module's.
#include <string>
#include <vector>

#include "cl/cl_context.h"
#include "raster/shadow_maps.h"
#include "render/frame_setup.h"
#include "techniques/technique.h"

namespace ts {

// dump.cl's decode_gbuffer on `frame`, built for `format` and `features`: per pixel, row by row,
// the dumpKernelChannels() values the kernels shade with.
std::vector<float> decodeOnDevice(ClContext& cl, const DeviceFrame& frame, GBufferFormat format,
                                  const SceneFeatures& features);

// Writes DIR/gbuffer.exr (dump.cl's decoded channels, then the host channels of the field table),
// DIR/lights.json and DIR/gbuffer.json. `frame` is `prepared` uploaded (the dump kernel decodes it
// for prepared's layout and features); `scene` and `raster` are recorded in the descriptor.
void writeGBufferDump(ClContext& cl, const DeviceFrame& frame, const PreparedFrame& prepared,
                      const std::string& scene, const std::string& raster, const std::string& dir);

// Writes DIR/shadow_atlas.exr (one channel "depth": each face's linear depths, docs/shadows.md)
// and DIR/shadow_atlas.json (per face: its rectangle and, in the view space of lights.json, the
// records --gbuffer-in rebuilds the kernels' face table from; with the scene's `atlas`, also its
// light, cube face, depth range and world-to-clip matrix). `lights`: the frame's, with the maps
// attached (lights.hasShadows()).
void writeShadowAtlasDump(const ViewLights& lights, const ShadowAtlas* atlas,
                          const std::string& dir);

}  // namespace ts
