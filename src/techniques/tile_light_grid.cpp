#include "techniques/tile_light_grid.h"

#include <algorithm>
#include <cfloat>

#include "cl/kernel_args.h"
#include "cl/work_group.h"

namespace ts {

TileLightGrid::TileLightGrid(ClContext& cl, const cl::Program& program)
    : cl_(cl),
      depthBounds_(program, "tile_depth_bounds"),
      bin_(program, "bin_lights"),
      scan_(program, "exclusive_scan"),
      sort_(program, "sort_bins") {}

bool TileLightGrid::allocate(int width, int height, int tileW, int tileH) {
  TileGrid grid(width, height, tileW, tileH);
  if (grid.tilesX == grid_.tilesX && grid.tilesY == grid_.tilesY && grid.width == grid_.width &&
      grid.height == grid_.height)
    return false;
  grid_ = grid;
  const size_t tiles = size_t(grid_.count());
  auto& ctx = cl_.context();
  depth_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, tiles * sizeof(cl_float4));
  count_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, tiles * sizeof(uint32_t));
  offset_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, tiles * sizeof(uint32_t));
  cursor_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, tiles * sizeof(uint32_t));
  total_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, sizeof(uint32_t));
  reserveList(cl_, lights_, capacity_, tiles * 8);
  return true;
}

void TileLightGrid::presize(const DeviceFrame& frame, int spotCulling) {
  reserveList(cl_, lights_, capacity_, tileListBound(grid_, frame, spotCulling));
}

void TileLightGrid::enqueueClear(FrameTimer& timer) {
  auto& q = cl_.queue();
  const size_t tiles = size_t(grid_.count());
  const uint32_t zero = 0;
  q.enqueueFillBuffer(count_, zero, 0, tiles * 4, nullptr, timer.next("clear"));
  q.enqueueFillBuffer(cursor_, zero, 0, tiles * 4, nullptr, timer.next("clear"));
}

void TileLightGrid::enqueueDepthBounds(const cl::Buffer& linearDepth, int width, int height,
                                       FrameTimer& timer) {
  // One work-group per tile, at most 64 work-items each reading several pixels: fewer
  // tree-reduction steps (on PoCL 256-item groups spent more time reducing than reading: 10 -> 3-5
  // ms at 1280x720 with 16x16 tiles).
  const size_t group = powerOfTwoGroup(pow2AtLeast(size_t(grid_.tileW) * grid_.tileH, 64),
                                       groupLimit(cl_, depthBounds_));
  KernelArgs(depthBounds_).add(linearDepth).add(width).add(height).add(depth_).done();
  cl_.queue().enqueueNDRangeKernel(depthBounds_, cl::NullRange,
                                   cl::NDRange(size_t(grid_.count()) * group), cl::NDRange(group),
                                   nullptr, timer.next("depth_bounds"));
}

void TileLightGrid::enqueueWholeDepthRange(float znear, float zfar, FrameTimer& timer) {
  // The camera's [znear, zfar] in every tile, the second range empty (kernels/tiled.cl).
  const cl_float4 whole = {{znear, zfar, FLT_MAX, 0.0f}};
  cl_.queue().enqueueFillBuffer(depth_, whole, 0, size_t(grid_.count()) * sizeof(cl_float4),
                                nullptr, timer.next("clear"));
}

void TileLightGrid::enqueueBinning(const DeviceFrame& frame, FrameTimer& timer) {
  cl_uint fillArg = 0;
  KernelArgs(bin_)
      .add(frame.lightPositionRange)
      .add(frame.lightSpot)
      .add(frame.lightCount())
      .add(toCl(frame.camera.kernelCamera()))
      .add(frame.camera.znear)
      .add(depth_)
      .later(fillArg)
      .add(count_)
      .add(offset_)
      .add(cursor_)
      .add(lights_)
      .add(cl_uint(capacity_))
      .done();
  ts::enqueueBinning(cl_, {bin_, fillArg, scan_, sort_}, frame.lightCount(), count_, grid_.count(),
                     offset_, total_, lights_, capacity_, timer);
}

uint32_t TileLightGrid::runUntilListFits(const std::function<void()>& enqueueFrame,
                                         std::vector<std::string>& notes) {
  return ts::runUntilListFits(cl_, lights_, capacity_, total_, enqueueFrame, "tile", notes);
}

std::vector<uint32_t> TileLightGrid::readCounts() const {
  std::vector<uint32_t> counts(size_t(grid_.count()));
  cl_.queue().enqueueReadBuffer(count_, CL_TRUE, 0, counts.size() * 4, counts.data());
  return counts;
}

std::vector<uint32_t> TileLightGrid::readOffsets() const {
  std::vector<uint32_t> offsets(size_t(grid_.count()));
  cl_.queue().enqueueReadBuffer(offset_, CL_TRUE, 0, offsets.size() * 4, offsets.data());
  return offsets;
}

std::vector<uint32_t> TileLightGrid::readLights(uint32_t total) const {
  // At least one entry: a zero-size read is an error in OpenCL.
  std::vector<uint32_t> lights(std::max<uint32_t>(total, 1));
  cl_.queue().enqueueReadBuffer(lights_, CL_TRUE, 0, lights.size() * 4, lights.data());
  lights.resize(total);
  return lights;
}

}  // namespace ts
