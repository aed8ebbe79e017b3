#include "techniques/cluster_light_grid.h"

#include <algorithm>
#include <utility>

#include "cl/kernel_args.h"
#include "util/error.h"

namespace ts {

ClusterLightGrid::ClusterLightGrid(ClContext& cl, const cl::Program& program, int slices,
                                   std::string technique)
    : cl_(cl),
      bin_(program, "bin_clusters"),
      scan_(program, "exclusive_scan"),
      sort_(program, "sort_bins"),
      slices_(slices),
      technique_(std::move(technique)) {}

bool ClusterLightGrid::allocate(int width, int height, int tileW, int tileH) {
  TileGrid grid(width, height, tileW, tileH);
  if (grid.tilesX == grid_.tilesX && grid.tilesY == grid_.tilesY && grid.width == grid_.width &&
      grid.height == grid_.height)
    return false;
  // Refused before any allocation: tiny tiles times many slices (say 1x1 x 1024 at 640x360) ask
  // for gigabytes of per-cluster buffers, which would fail far later, less clearly.
  const size_t clusters = size_t(grid.count()) * size_t(slices_);
  const size_t maxAlloc = size_t(cl_.device().getInfo<CL_DEVICE_MAX_MEM_ALLOC_SIZE>());
  if (clusters * sizeof(cl_float2) > maxAlloc)
    throw Error(technique_ + ": " + std::to_string(grid.count()) + " tiles x " +
                std::to_string(slices_) + " slices = " + std::to_string(clusters) +
                " clusters need more than the device's largest buffer (" +
                std::to_string(maxAlloc >> 20) + " MiB): use bigger tiles or fewer slices");
  grid_ = grid;
  auto& ctx = cl_.context();
  depthRange_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, 2 * sizeof(cl_uint));
  clusterDepth_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, clusters * sizeof(cl_float2));
  tileSlices_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, size_t(grid_.count()) * sizeof(cl_int2));
  count_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, clusters * sizeof(uint32_t));
  offset_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, clusters * sizeof(uint32_t));
  cursor_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, clusters * sizeof(uint32_t));
  total_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, sizeof(uint32_t));
  // Most clusters hold no light, so size the first list by tiles, not clusters; it grows.
  reserveList(cl_, lights_, capacity_, size_t(grid_.count()) * 8);
  return true;
}

void ClusterLightGrid::presize(const DeviceFrame& frame, int spotCulling) {
  reserveList(
      cl_, lights_, capacity_,
      std::min(tileListBound(grid_, frame, spotCulling) * size_t(slices_), size_t(16) << 20));
}

void ClusterLightGrid::enqueueClear(FrameTimer& timer) {
  auto& q = cl_.queue();
  const size_t clusters = clusterCount();
  const uint32_t zero = 0;
  q.enqueueFillBuffer(count_, zero, 0, clusters * 4, nullptr, timer.next("clear"));
  q.enqueueFillBuffer(cursor_, zero, 0, clusters * 4, nullptr, timer.next("clear"));
}

void ClusterLightGrid::enqueueBinning(const DeviceFrame& frame, FrameTimer& timer) {
  cl_uint fillArg = 0;
  KernelArgs(bin_)
      .add(frame.lightPositionRange)
      .add(frame.lightSpot)
      .add(frame.lightCount())
      .add(toCl(frame.camera.kernelCamera()))
      .add(frame.camera.znear)
      .add(depthRange_)
      .add(clusterDepth_)
      .add(tileSlices_)
      .later(fillArg)
      .add(count_)
      .add(offset_)
      .add(cursor_)
      .add(lights_)
      .add(cl_uint(capacity_))
      .done();
  ts::enqueueBinning(cl_, {bin_, fillArg, scan_, sort_}, frame.lightCount(), count_,
                     int(clusterCount()), offset_, total_, lights_, capacity_, timer);
}

uint32_t ClusterLightGrid::runUntilListFits(const std::function<void()>& enqueueFrame,
                                            std::vector<std::string>& notes) {
  return ts::runUntilListFits(cl_, lights_, capacity_, total_, enqueueFrame, "cluster", notes);
}

std::vector<uint32_t> ClusterLightGrid::readCounts() const {
  std::vector<uint32_t> counts(clusterCount());
  cl_.queue().enqueueReadBuffer(count_, CL_TRUE, 0, counts.size() * 4, counts.data());
  return counts;
}

std::vector<uint32_t> ClusterLightGrid::readOffsets() const {
  std::vector<uint32_t> offsets(clusterCount());
  cl_.queue().enqueueReadBuffer(offset_, CL_TRUE, 0, offsets.size() * 4, offsets.data());
  return offsets;
}

std::vector<uint32_t> ClusterLightGrid::readLights(uint32_t total) const {
  std::vector<uint32_t> lights(std::max<uint32_t>(total, 1));
  cl_.queue().enqueueReadBuffer(lights_, CL_TRUE, 0, lights.size() * 4, lights.data());
  lights.resize(total);
  return lights;
}

}  // namespace ts
