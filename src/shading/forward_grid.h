#pragma once
// What a tiled forward pass reads and returns (shared by the techniques, which build the grid with
// the OpenCL binning kernels, and the OpenGL rasterizer, which draws with it).
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace ts {

// The tile light grid, copied to the host: tiles of tileW x tileH pixels, row-major from the top
// left; tile t's lights are lights[offsets[t] .. offsets[t] + counts[t]), indices into the
// frame's ViewLights.
// Clustered (clustered-forward): `slices` depth slices per tile, bin = tile * slices + slice, a
// fragment's slice from its view depth z as kernels/clustered.cl has it:
// int(clamp(log(z / sliceNear) * sliceScale, 0, slices - 1)).
struct ForwardLightGrid {
  int tileW = 16, tileH = 16, tilesX = 0, tilesY = 0;
  int slices = 1;
  float sliceNear = 1.0f, sliceScale = 0.0f;
  std::vector<uint32_t> offsets, counts, lights;
};

// A forward pass's output.
struct ForwardImage {
  std::vector<glm::vec4> image;  // rgb, a = 0; row 0 at the top; background 0
  double drawMs = 0.0;           // the draw: host wall clock, glFinish before and after
  double queryMs = 0.0;   // the same draw by an OpenGL timer query (llvmpipe: submission only)
  double uploadMs = 0.0;  // lights and grid into shader storage (host clock)
  // The shadow maps (first faces, face table, atlas texture) into OpenGL: host clock, glFinish
  // after; 0 for a frame without shadow-casting lights.
  double shadowUploadMs = 0.0;
  uint64_t lightingComputations = 0;  // fragment invocations x lights evaluated (an atomic
                                      // counter per tile in the fragment shader)
  // Multi-pass forward: its base pass apart (drawMs and queryMs are then its light passes), and
  // the light passes drawn.
  double baseMs = 0.0, baseQueryMs = 0.0;
  size_t passes = 0;
  size_t draws = 0;  // draw calls, all passes
  // The transparent pass (--blend blend; in drawMs of none): its wall clock and timer query, and
  // its draws (in `draws` too); 0 without transparent draws.
  double transparentMs = 0.0, transparentQueryMs = 0.0;
  size_t transparentDraws = 0;
  // The hybrid's transparent pass over a G-buffer technique's image (transparentOver): that image
  // and the opaque depth into the OpenGL target (host clock, glFinish after), and whether the
  // depth had to be drawn again (the G-buffer pass's was of another frame) instead of copied.
  double imageCopyMs = 0.0;
  bool depthRedrawn = false;
  // forward, forward-single: the draw batch of each pixel's surface (-1: background), row 0 at
  // the top; with --msaa one such plane per sample, sample-major (each sample's surface).
  std::vector<int32_t> pixelBatch;
};

}  // namespace ts
