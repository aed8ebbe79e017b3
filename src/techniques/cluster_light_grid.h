#pragma once
// The light grid of the techniques built on kernels/clustered.cl (`clustered`,
// `clustered-forward`): tiles x depth slices (Olsson, Billeter & Assarsson 2012), per cluster its
// view-depth bounds and (count, offset) into one light index list, per tile the slices it holds,
// and the frame's slicing range; binned by bin_clusters, scanned and sorted as every grid is
// (tile_grid.h). The techniques differ in how the cluster bounds are found (`clustered` from its
// G-buffer by its kernels, `clustered-forward` on the host from the scene's depth); this class
// holds what they share, so both allocate, clear and bin the grid the same way and a change to
// the binning is made once.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "techniques/tile_grid.h"

namespace ts {

class ClusterLightGrid {
 public:
  // `program`: kernels/clustered.cl built with the technique's TILE_W, TILE_H and SLICES =
  // `slices`; `technique` names it in the refusal of a grid no buffer can hold.
  ClusterLightGrid(ClContext& cl, const cl::Program& program, int slices, std::string technique);

  // (Re)allocates the per-cluster and per-tile buffers for a frame of this size; false when they
  // already fit. Refuses (ts::Error, before any allocation) a grid whose per-cluster buffers
  // exceed the device's largest allocation (tiny tiles times many slices).
  bool allocate(int width, int height, int tileW, int tileH);
  // Grows the list to every light in every slice of its tile rectangle (tileListBound x slices),
  // capped at 16 Mi entries (runUntilListFits covers a capped bound).
  void presize(const DeviceFrame& frame, int spotCulling);

  // Zeroes the per-cluster counters (two "clear" launches).
  void enqueueClear(FrameTimer& timer);
  // bin_clusters' count and fill passes with the scan and sort between (after the caller has
  // filled depthRange, clusterDepth and tileSlices for this frame).
  void enqueueBinning(const DeviceFrame& frame, FrameTimer& timer);
  // runUntilListFits on this grid's list ("cluster"): `enqueueFrame` clears the timer and
  // enqueues the whole frame, grid included. Returns the list's total entries.
  uint32_t runUntilListFits(const std::function<void()>& enqueueFrame,
                            std::vector<std::string>& notes);

  const TileGrid& tiles() const { return grid_; }
  int slices() const { return slices_; }
  size_t clusterCount() const { return size_t(grid_.count()) * size_t(slices_); }

  // What binning tests a light against, filled by the technique each frame: the slicing's (zn,
  // zf) as float bits (uint2), per cluster its depth bounds (float2), per tile its slice range
  // (int2).
  const cl::Buffer& depthRange() const { return depthRange_; }
  const cl::Buffer& clusterDepth() const { return clusterDepth_; }
  const cl::Buffer& tileSlices() const { return tileSlices_; }
  // The grid as the shading reads it (kernels/light_lists.h).
  const cl::Buffer& counts() const { return count_; }
  const cl::Buffer& offsets() const { return offset_; }
  const cl::Buffer& lights() const { return lights_; }
  cl_uint capacity() const { return cl_uint(capacity_); }

  // Host copies, after the queue has finished the frame.
  std::vector<uint32_t> readCounts() const;
  std::vector<uint32_t> readOffsets() const;
  std::vector<uint32_t> readLights(uint32_t total) const;

 private:
  ClContext& cl_;
  cl::Kernel bin_, scan_, sort_;
  int slices_;
  std::string technique_;
  TileGrid grid_;
  cl::Buffer depthRange_, clusterDepth_, tileSlices_, count_, offset_, cursor_, total_, lights_;
  size_t capacity_ = 0;
};

}  // namespace ts
