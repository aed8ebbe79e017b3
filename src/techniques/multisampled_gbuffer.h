#pragma once
// --msaa for `tiled` (Lauritzen, "Deferred Rendering for Current and Future Rendering
// Pipelines", SIGGRAPH 2010): the frame's G-buffer per sample on the device and its edge mask
// (kernels/msaa_edges.h: a pixel whose samples' stored planes differ in any bit).
// The samples are stored as one buffer per plane holding sample 0's plane, then sample 1's, ...
// (sample-major, "one plane N times as tall"), not N sets of buffers: the shading kernels keep
// DeviceFrame's five plane arguments, shade_tiled shades sample 0 from the same buffers
// unchanged (its first width x height elements), tile_depth_bounds already reads depth that way
// (its `samples`), and a sample is an offset.
#include <cstdint>
#include <string>
#include <tuple>
#include <vector>

#include "cl/cl_context.h"
#include "gbuffer/gbuffer_layout.h"
#include "techniques/tile_grid.h"

namespace ts {

class MultisampledGBuffer {
 public:
  // `program`: kernels/tiled.cl (its msaa_edge_mask), built without lanes.
  MultisampledGBuffer(ClContext& cl, const cl::Program& program);

  // Uploads every sample's planes (samples[k], sample k's: one layout, one size, at least 2).
  // Throws ts::Error (one line) for planes that do not match `frame`'s layout and size.
  void upload(const std::vector<EncodedGBuffer>& samples, const EncodedGBuffer& frame);
  // msaa_edge_mask over the uploaded samples, profiled as msaa_edges.
  void enqueueEdgeMask(FrameTimer& timer);
  // The mask on the host (one byte per pixel, 1 = edge), after the queue finished.
  std::vector<uint8_t> readEdges() const;

  int samples() const { return samples_; }
  // The planes' bytes on the device, every sample (what grows with --msaa).
  uint64_t bytes() const { return bytes_; }
  // Bytes per pixel of the normal, diffuse, specular and emissive planes (0 = absent), for the
  // kernels' sample offsets (TS_SAMPLE_PLANE).
  cl_int4 planeBytes() const { return planeBytes_; }
  const cl::Buffer& depth() const { return depth_; }
  const cl::Buffer& edges() const { return edges_; }
  // The five planes in kernels/gbuffer.h's order (TS_GBUFFER_PARAMS).
  auto gbufferArgs() const { return std::tie(depth_, normal_, diffuse_, specular_, emissive_); }

 private:
  ClContext& cl_;
  cl::Kernel edgeMask_;
  int samples_ = 0, width_ = 0, height_ = 0;
  uint64_t bytes_ = 0;
  cl_int4 planeBytes_{{0, 0, 0, 0}};
  cl::Buffer depth_, normal_, diffuse_, specular_, emissive_, edges_;
};

// The per-sample planes (in the frame's layout) that `technique` shades a multisampled frame
// from. Throws ts::Error (one line) for a frame without them (DeviceFrame::samples) or with
// transparent draws (refused with the frame already, by SceneRasterizer).
const std::vector<EncodedGBuffer>& multisampledPlanes(const DeviceFrame& frame,
                                                      const std::string& technique);

// The work of a frame shaded by tiled with a multisampled G-buffer: every pixel's sample 0 that
// holds geometry, and the samples 1.. of the edge pixels that do, each against its tile's list
// (evaluations; lighting computations: the paper's on-screen tile pixels x list plus the edge
// pixels' further samples x list), plus the directional lights at each sample shaded; the G-buffer
// bytes read estimated from the passes (depth bounds: every sample's depth; edge mask: every
// sample's planes; shading: sample 0's planes, the edges' further samples'). Sets
// edgePixels.
WorkCounters multisampledTileWorkCounters(const TileGrid& grid, const std::vector<uint32_t>& counts,
                                          const std::vector<EncodedGBuffer>& samples,
                                          const std::vector<uint8_t>& edges,
                                          const DeviceFrame& frame);

}  // namespace ts
