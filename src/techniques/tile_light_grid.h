#pragma once
// The light grid of the techniques built on kernels/tiled.cl (`tiled`, `tiled-forward`,
// `tiled-forward-prez`): Olsson & Assarsson's per-tile depth range, per-tile (count, offset) and
// tile light index list. One copy of the launches, so every technique on this grid clears, bounds
// and bins it the same way, and a change to the binning is made once.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "shading/forward_grid.h"
#include "techniques/tile_grid.h"

namespace ts {

class TileLightGrid {
 public:
  // `program`: kernels/tiled.cl built with the technique's TILE_W and TILE_H.
  TileLightGrid(ClContext& cl, const cl::Program& program);

  // (Re)allocates the per-tile buffers for a frame of this size; false when they already fit.
  bool allocate(int width, int height, int tileW, int tileH);
  // Grows the list to the frame's upper bound (tileListBound): saves a first frame's rerun.
  void presize(const DeviceFrame& frame, int spotCulling);

  // One frame's grid, in launch order: clear the per-tile counters, give every tile a depth range
  // (from a linear depth plane, or the camera's whole range), then bin the lights.
  void enqueueClear(FrameTimer& timer);
  // linearDepth: `samples` planes of width x height (sample-major: --msaa's pre-pass); each
  // tile's range covers all of them.
  void enqueueDepthBounds(const cl::Buffer& linearDepth, int width, int height, FrameTimer& timer,
                          int samples = 1);
  void enqueueWholeDepthRange(float znear, float zfar, FrameTimer& timer);
  // The transparent surfaces' ranges from the opaque ones of enqueueDepthBounds (Olsson &
  // Assarsson, Section 4: a transparent fragment in front of the opaque surface is still drawn,
  // so only the far bound may cull): each tile's [znear, its opaque far bound], an empty tile's
  // [znear, zfar]. Reads the opaque ranges back (waits for them), writes these in their place.
  void enqueueTransparentRanges(float znear, float zfar, FrameTimer& timer);
  void enqueueBinning(const DeviceFrame& frame, FrameTimer& timer);

  // Lights whose tile rectangle holds more than `tiles` tiles are binned by a whole work-group
  // each, the others by one work-item each (kernels/tiled.cl). The default: on a GPU
  // kGpuAloneTiles, so a big light does not hold up a wave; on a CPU none (kNoBigLights), where a
  // work-group's items run one after another anyway and the work-group path cost 3x the binning
  // of street with 64k lights (bench/RESULTS.md). The lists are the same whichever path a light
  // takes.
  static constexpr int kGpuAloneTiles = 32;
  static constexpr int kNoBigLights = INT32_MAX;
  void setAloneTiles(int tiles) { aloneTiles_ = tiles; }

  // runUntilListFits on this grid's list: `enqueueFrame` clears the timer and enqueues the whole
  // frame, grid included. Returns the list's total entries.
  uint32_t runUntilListFits(const std::function<void()>& enqueueFrame,
                            std::vector<std::string>& notes);

  // The transparent surfaces' grid (the tiled forward pass over the opaque one: tiled-forward-prez,
  // and tiled's hybrid), after enqueueDepthBounds of the opaque depth has run: the ranges of
  // enqueueTransparentRanges, binned again (grown and rerun until the list fits), then read to
  // the host. `row`: its kernels summed as one row, transparent_grid; readMs: the read-back.
  // Leaves the transparent grid on the device in place of the opaque one.
  ForwardLightGrid binForTransparency(const DeviceFrame& frame, std::vector<std::string>& notes,
                                      KernelTime& row, double& readMs);
  // The grid as it stands on the device (the queue finished, `total` entries), to the host.
  ForwardLightGrid toHost(uint32_t total) const;

  const TileGrid& grid() const { return grid_; }
  // The grid as the shading passes read it (kernels/light_lists.h).
  const cl::Buffer& counts() const { return count_; }
  const cl::Buffer& offsets() const { return offset_; }
  const cl::Buffer& lights() const { return lights_; }
  cl_uint capacity() const { return cl_uint(capacity_); }
  // Per tile its depth ranges (zmin, near_max, far_min, zmax; kernels/tiled.cl), what binning
  // tested the lights against.
  const cl::Buffer& depthBounds() const { return depth_; }

  // Host copies, after the queue has finished the frame.
  std::vector<uint32_t> readCounts() const;
  std::vector<uint32_t> readOffsets() const;
  std::vector<uint32_t> readLights(uint32_t total) const;

 private:
  ClContext& cl_;
  cl::Kernel depthBounds_, rects_, bin_, binBig_, scan_, sort_;
  TileGrid grid_;
  cl::Buffer depth_, count_, offset_, cursor_, total_, lights_;
  size_t capacity_ = 0;
  // Per light its tile rectangle (light_tile_rects), and the lights binned by whole work-groups.
  cl::Buffer rect_, bigLights_, bigCount_;
  size_t lightCapacity_ = 0;
  int aloneTiles_;
};

}  // namespace ts
