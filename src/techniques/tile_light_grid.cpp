#include "techniques/tile_light_grid.h"

#include <algorithm>
#include <cfloat>
#include <chrono>

#include "cl/kernel_args.h"
#include "cl/work_group.h"

namespace ts {

TileLightGrid::TileLightGrid(ClContext& cl, const cl::Program& program)
    : cl_(cl),
      depthBounds_(program, "tile_depth_bounds"),
      rects_(program, "light_tile_rects"),
      bin_(program, "bin_lights"),
      binBig_(program, "bin_big_lights"),
      scan_(program, "exclusive_scan"),
      sort_(program, "sort_bins"),
      aloneTiles_(cl.isGpu() ? kGpuAloneTiles : kNoBigLights) {}

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
  bigCount_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, sizeof(uint32_t));
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
                                       FrameTimer& timer, int samples) {
  // One work-group per tile, at most 64 work-items each reading several pixels: fewer
  // tree-reduction steps (on PoCL 256-item groups spent more time reducing than reading: 10 -> 3-5
  // ms at 1280x720 with 16x16 tiles).
  const size_t group = powerOfTwoGroup(pow2AtLeast(size_t(grid_.tileW) * grid_.tileH, 64),
                                       groupLimit(cl_, depthBounds_));
  KernelArgs(depthBounds_).add(linearDepth).add(width).add(height).add(samples).add(depth_).done();
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

void TileLightGrid::enqueueTransparentRanges(float znear, float zfar, FrameTimer& timer) {
  std::vector<cl_float4> ranges(size_t(grid_.count()));
  auto& q = cl_.queue();
  q.enqueueReadBuffer(depth_, CL_TRUE, 0, ranges.size() * sizeof(cl_float4), ranges.data());
  for (cl_float4& r : ranges) {
    // (zmin, near_max, far_min, zmax) of kernels/tiled.cl: the far bound is near_max without a
    // split (zmax 0), zmax with one; an empty tile (zmin > near_max) shows the background.
    const bool empty = r.s[0] > r.s[1];
    const float far = empty ? zfar : std::max(r.s[1], r.s[3]);
    r = {{znear, far, FLT_MAX, 0.0f}};
  }
  q.enqueueWriteBuffer(depth_, CL_FALSE, 0, ranges.size() * sizeof(cl_float4), ranges.data(),
                       nullptr, timer.next("transparent_bounds"));
  q.finish();  // `ranges` is read by the non-blocking write
}

void TileLightGrid::enqueueBinning(const DeviceFrame& frame, FrameTimer& timer) {
  const int lights = frame.lightCount();
  const size_t perLight = std::max<size_t>(size_t(lights), 1);
  if (perLight > lightCapacity_) {  // per light: its rectangle, and room to list it as big
    lightCapacity_ = perLight;
    rect_ = cl::Buffer(cl_.context(), CL_MEM_READ_WRITE, perLight * sizeof(cl_int4));
    bigLights_ = cl::Buffer(cl_.context(), CL_MEM_READ_WRITE, perLight * sizeof(uint32_t));
  }
  auto& q = cl_.queue();
  const cl_float4 camera = toCl(frame.camera.kernelCamera());
  const uint32_t zero = 0;
  q.enqueueFillBuffer(bigCount_, zero, 0, sizeof(uint32_t), nullptr, timer.next("clear"));
  // One work-item per light, in groups from the device's limits (the kernels take any size).
  const size_t group = fitGroup(64, 1, groupLimit(cl_, bin_)).x;
  const cl::NDRange perLightRange(roundUp(size_t(lights), group));
  if (lights > 0) {  // OpenCL refuses an empty NDRange
    KernelArgs(rects_)
        .add(frame.lightPositionRange)
        .add(frame.lightSpot)
        .add(lights)
        .add(camera)
        .add(frame.camera.znear)
        .add(cl_int(aloneTiles_))
        .add(rect_)
        .add(bigLights_)
        .add(bigCount_)
        .done();
    const size_t rectGroup = fitGroup(64, 1, groupLimit(cl_, rects_)).x;
    q.enqueueNDRangeKernel(rects_, cl::NullRange, cl::NDRange(roundUp(size_t(lights), rectGroup)),
                           cl::NDRange(rectGroup), nullptr, timer.next("bin_rects"));
  }
  cl_uint fillArg = 0, bigFillArg = 0;
  KernelArgs(bin_)
      .add(frame.lightPositionRange)
      .add(frame.lightSpot)
      .add(lights)
      .add(camera)
      .add(cl_int(aloneTiles_))
      .add(rect_)
      .add(depth_)
      .later(fillArg)
      .add(count_)
      .add(offset_)
      .add(cursor_)
      .add(lights_)
      .add(cl_uint(capacity_))
      .done();
  KernelArgs(binBig_)
      .add(frame.lightPositionRange)
      .add(frame.lightSpot)
      .add(camera)
      .add(rect_)
      .add(bigLights_)
      .add(bigCount_)
      .add(depth_)
      .later(bigFillArg)
      .add(count_)
      .add(offset_)
      .add(cursor_)
      .add(lights_)
      .add(cl_uint(capacity_))
      .done();
  // The big lights' groups stride over their list, whose length only the device knows: a few
  // groups per compute unit keep every unit busy without a read-back.
  const size_t bigGroup = fitGroup(64, 1, groupLimit(cl_, binBig_)).x;
  const size_t bigGroups = size_t(std::max(cl_.info().computeUnits, 1)) * 4;
  auto binPass = [&](int fill, const char* name) {
    bin_.setArg(fillArg, fill);
    q.enqueueNDRangeKernel(bin_, cl::NullRange, perLightRange, cl::NDRange(group), nullptr,
                           timer.next(name));
    if (aloneTiles_ == kNoBigLights) return;  // none listed
    binBig_.setArg(bigFillArg, fill);
    q.enqueueNDRangeKernel(binBig_, cl::NullRange, cl::NDRange(bigGroups * bigGroup),
                           cl::NDRange(bigGroup), nullptr, timer.next(name));
  };
  enqueueBinningPasses(cl_, binPass, scan_, sort_, lights, count_, grid_.count(), offset_, total_,
                       lights_, capacity_, timer);
}

uint32_t TileLightGrid::runUntilListFits(const std::function<void()>& enqueueFrame,
                                         std::vector<std::string>& notes) {
  return ts::runUntilListFits(cl_, lights_, capacity_, total_, enqueueFrame, "tile", notes);
}

ForwardLightGrid TileLightGrid::binForTransparency(const DeviceFrame& frame,
                                                   std::vector<std::string>& notes, KernelTime& row,
                                                   double& readMs) {
  FrameTimer timer;
  // A rerun finds the transparent ranges in place, which enqueueTransparentRanges keeps.
  const uint32_t total = runUntilListFits(
      [&] {
        timer.clear();
        enqueueClear(timer);
        enqueueTransparentRanges(frame.camera.znear, frame.camera.zfar, timer);
        enqueueBinning(frame, timer);
      },
      notes);
  cl_.queue().finish();
  row = {"transparent_grid", 0.0, 0};
  for (const KernelTime& k : timer.kernels()) {
    row.ms += k.ms;
    row.launches += k.launches;
  }
  const auto t0 = std::chrono::steady_clock::now();
  ForwardLightGrid grid = toHost(total);
  readMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return grid;
}

ForwardLightGrid TileLightGrid::toHost(uint32_t total) const {
  ForwardLightGrid grid;
  grid.tileW = grid_.tileW;
  grid.tileH = grid_.tileH;
  grid.tilesX = grid_.tilesX;
  grid.tilesY = grid_.tilesY;
  grid.counts = readCounts();
  grid.offsets = readOffsets();
  grid.lights = readLights(total);
  return grid;
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
