// Single-kernel tiled deferred shading; the kernel is kernels/tiled_single.cl. One launch per
// frame: a work-group per tile reduces depth, tests every light and shades, all in local memory.
// The tile light counts (and, on request, the lists) come back for the counters and the
// conservativeness checks; they are the same quantities the multi-kernel `tiled` reports.
#include <algorithm>

#include "cl/kernel_args.h"
#include "cl/work_group.h"
#include "techniques/tile_grid.h"
#include "techniques/techniques.h"
#include "util/error.h"

namespace ts {
namespace {

class TiledSingleTechnique : public Technique {
 public:
  TiledSingleTechnique(ClContext& cl, const TechniqueConfig& config) : cl_(cl), config_(config) {
    if (config.tileWidth < 1 || config.tileHeight < 1) throw Error("tile size must be positive");
    // The work-group shape is built into the kernel (reqd_work_group_size; a tile larger than the
    // group gives each work-item several pixels): up to 16x16 within the device's limit, then
    // within the built kernel's own limit, rebuilding once if that is smaller.
    build(fitGroup(std::min(config.tileWidth, 16), std::min(config.tileHeight, 16),
                   deviceGroupLimit(cl)));
    GroupLimit kernelLimit = groupLimit(cl, kernel_);
    if (size_t(groupW_) * groupH_ > kernelLimit.size)
      build(fitGroup(groupW_, groupH_, kernelLimit));
  }

  std::string name() const override { return "tiled-single"; }
  int lanes() const override { return config_.lanes; }

  FrameResult renderFrame(DeviceFrame& frame, const FrameRequest& request) override {
    allocate(frame, request.wantAssignment);
    auto& q = cl_.queue();
    timer_.clear();
    // The lists are recorded only when asked for: a tile may hold every light, so the buffer is
    // tiles x lights entries.
    cl_uint stride = request.wantAssignment ? cl_uint(std::max(frame.lightCount(), 1)) : 0;
    KernelArgs args(kernel_);
    args.add(toCl(frame.camera.kernelCamera()))
        .add(toCl(glm::vec4(frame.ambient, 0.0f)))
        .add(frame.camera.znear)
        .add(frame.gbufferArgs())
        .add(frame.lightArgs())
        .addIf(config_.features.shadows, frame.lightShadowArgs())
        .add(frame.lightCount())
        .add(frame.directionalArgs())
        .addIf(config_.features.shadows, frame.directionalShadowArgs())
        .add(tileCount_)
        .add(tileLights_)
        .add(stride)
        .add(image_)
        .add(cl::Local(size_t(capacity_) * sizeof(cl_uint)));
    if (config_.lanes > 1) args.add(cl::Local(laneTileBytes()));
    args.done();
    q.enqueueNDRangeKernel(
        kernel_, cl::NullRange,
        cl::NDRange(size_t(grid_.tilesX) * groupW_, size_t(grid_.tilesY) * groupH_),
        cl::NDRange(groupW_, groupH_), nullptr, timer_.next("tile_shade"));
    q.finish();

    FrameResult result;
    result.kernels = timer_.kernels();
    result.totalMs = timer_.totalMs();
    result.image = readImage(cl_, image_, frame);
    std::vector<uint32_t> counts(grid_.count());
    q.enqueueReadBuffer(tileCount_, CL_TRUE, 0, counts.size() * 4, counts.data());
    result.counters = tileWorkCounters(grid_, counts, frame);
    if (request.wantAssignment) {
      std::vector<uint32_t> recorded(size_t(grid_.count()) * stride), offsets, lights;
      q.enqueueReadBuffer(tileLights_, CL_TRUE, 0, recorded.size() * 4, recorded.data());
      for (int t = 0; t < grid_.count(); ++t) {
        offsets.push_back(uint32_t(lights.size()));
        lights.insert(lights.end(), recorded.begin() + size_t(t) * stride,
                      recorded.begin() + size_t(t) * stride + counts[t]);
      }
      result.assignment = tileAssignment(grid_, offsets, counts, lights);
    }
    return result;
  }

 private:
  void build(GroupShape group) {
    groupW_ = int(group.x);
    groupH_ = int(group.y);
    capacity_ = std::max(config_.localListCapacity, groupW_ * groupH_);
    // In lanes the whole tile's shading terms and sums live in local memory; a tile too large for
    // the device's local memory is shaded one pixel per work-item (lanes() then says 1).
    if (config_.lanes > 1 &&
        laneTileBytes() + size_t(capacity_) * 4 + size_t(groupW_) * groupH_ * 8 + 64 >
            cl_.device().getInfo<CL_DEVICE_LOCAL_MEM_SIZE>())
      config_.lanes = 1;
    std::string options = config_.kernelOptions() + config_.lanesOption() +
                          " -DTILE_W=" + std::to_string(config_.tileWidth) +
                          " -DTILE_H=" + std::to_string(config_.tileHeight) +
                          " -DGROUP_W=" + std::to_string(groupW_) +
                          " -DGROUP_H=" + std::to_string(groupH_) +
                          " -DLIST_CAPACITY=" + std::to_string(capacity_);
    program_ = cl_.build("tiled_single.cl", options);
    kernel_ = cl::Kernel(program_, "shade_tiled_single");
  }

  // The kernel's `soa` in lanes: TILE_PLANES (the shading terms + 3 sums) floats per pixel slot,
  // the tile's pixels rounded up to whole vectors (kernels/tiled_single.cl).
  size_t laneTileBytes() const {
    size_t pixels = size_t(config_.tileWidth) * config_.tileHeight;
    return size_t(config_.lanePlanes() + 3) * roundUp(pixels, size_t(std::max(config_.lanes, 1))) *
           sizeof(float);
  }

  void allocate(const DeviceFrame& frame, bool record) {
    TileGrid grid(frame.width(), frame.height(), config_.tileWidth, config_.tileHeight);
    auto& ctx = cl_.context();
    if (grid.count() != grid_.count() || grid.width != grid_.width || grid.height != grid_.height) {
      grid_ = grid;
      tileCount_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, size_t(grid_.count()) * sizeof(uint32_t));
      image_ = cl::Buffer(ctx, CL_MEM_WRITE_ONLY,
                          size_t(frame.width()) * frame.height() * sizeof(cl_float4));
      recordEntries_ = 0;
    }
    size_t entries = record ? size_t(grid_.count()) * std::max(frame.lightCount(), 1) : 1;
    if (entries > recordEntries_) {
      tileLights_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, entries * sizeof(uint32_t));
      recordEntries_ = entries;
    }
  }

  ClContext& cl_;
  TechniqueConfig config_;
  int groupW_ = 16, groupH_ = 16, capacity_ = 256;
  cl::Program program_;
  cl::Kernel kernel_;
  TileGrid grid_;
  cl::Buffer tileCount_, tileLights_, image_;
  size_t recordEntries_ = 0;
  FrameTimer timer_;
};

}  // namespace

std::unique_ptr<Technique> makeTiledSingleTechnique(ClContext& cl, const TechniqueConfig& config) {
  return std::make_unique<TiledSingleTechnique>(cl, config);
}

}  // namespace ts
