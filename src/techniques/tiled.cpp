// Multi-kernel tiled deferred shading; the kernels, in launch order, are in kernels/tiled.cl.
#include <algorithm>

#include "cl/kernel_args.h"
#include "cl/work_group.h"
#include "techniques/tile_grid.h"
#include "techniques/techniques.h"
#include "util/error.h"

namespace ts {
namespace {

class TiledTechnique : public Technique {
 public:
  TiledTechnique(ClContext& cl, const TechniqueConfig& config) : cl_(cl), config_(config) {
    if (config.tileWidth < 1 || config.tileHeight < 1) throw Error("tile size must be positive");
    std::string options = config.kernelOptions() + " -DTILE_W=" + std::to_string(config.tileWidth) +
                          " -DTILE_H=" + std::to_string(config.tileHeight) + config.lanesOption();
    program_ = cl.build("tiled.cl", options);
    depthBounds_ = cl::Kernel(program_, "tile_depth_bounds");
    binLights_ = cl::Kernel(program_, "bin_lights");
    scan_ = cl::Kernel(program_, "exclusive_scan");
    sort_ = cl::Kernel(program_, "sort_bins");
    shade_ = cl::Kernel(program_, "shade_tiled");
  }

  std::string name() const override { return "tiled"; }
  int lanes() const override { return config_.lanes; }

  FrameResult renderFrame(DeviceFrame& frame, const FrameRequest& request) override {
    allocate(frame);
    if (config_.presizeLists)
      reserveList(cl_, tileLights_, capacity_,
                  tileListBound(grid_, frame, int(config_.spotCulling)));
    FrameResult result;
    uint32_t total = runUntilListFits(
        cl_, tileLights_, capacity_, total_,
        [&] {
          timer_.clear();
          enqueueFrame(frame);
        },
        "tile", result.counters.notes);
    cl_.queue().finish();
    result.kernels = timer_.kernels();
    result.totalMs = timer_.totalMs();
    result.image = readImage(cl_, image_, frame);

    std::vector<uint32_t> counts(grid_.count()), offsets(grid_.count());
    cl_.queue().enqueueReadBuffer(tileCount_, CL_TRUE, 0, counts.size() * 4, counts.data());
    auto notes = std::move(result.counters.notes);
    result.counters = tileWorkCounters(grid_, counts, frame);
    result.counters.notes = std::move(notes);
    if (request.wantAssignment) {
      cl_.queue().enqueueReadBuffer(tileOffset_, CL_TRUE, 0, offsets.size() * 4, offsets.data());
      std::vector<uint32_t> lights(std::max<uint32_t>(total, 1));
      cl_.queue().enqueueReadBuffer(tileLights_, CL_TRUE, 0, lights.size() * 4, lights.data());
      lights.resize(total);
      result.assignment = tileAssignment(grid_, offsets, counts, lights);
    }
    return result;
  }

 private:
  void allocate(const DeviceFrame& frame) {
    TileGrid grid(frame.width(), frame.height(), config_.tileWidth, config_.tileHeight);
    if (grid.tilesX == grid_.tilesX && grid.tilesY == grid_.tilesY && grid.width == grid_.width &&
        grid.height == grid_.height)
      return;
    grid_ = grid;
    size_t tiles = size_t(grid_.count());
    auto& ctx = cl_.context();
    tileDepth_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, tiles * sizeof(cl_float4));
    tileCount_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, tiles * sizeof(uint32_t));
    tileOffset_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, tiles * sizeof(uint32_t));
    tileCursor_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, tiles * sizeof(uint32_t));
    total_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, sizeof(uint32_t));
    reserveList(cl_, tileLights_, capacity_, tiles * 8);
    image_ = cl::Buffer(ctx, CL_MEM_WRITE_ONLY,
                        size_t(frame.width()) * frame.height() * sizeof(cl_float4));
  }

  void enqueueFrame(DeviceFrame& frame) {
    auto& q = cl_.queue();
    cl_float4 camera = toCl(frame.camera.kernelCamera());
    size_t tiles = size_t(grid_.count());
    const uint32_t zero = 0;
    q.enqueueFillBuffer(tileCount_, zero, 0, tiles * 4, nullptr, timer_.next("clear"));
    q.enqueueFillBuffer(tileCursor_, zero, 0, tiles * 4, nullptr, timer_.next("clear"));

    // 1. Depth bounds: one work-group per tile, at most 64 work-items each reading several
    // pixels: fewer tree-reduction steps (on PoCL 256-item groups spent more time reducing than
    // reading: 10 -> 3-5 ms at 1280x720 with 16x16 tiles).
    size_t group = powerOfTwoGroup(pow2AtLeast(size_t(grid_.tileW) * grid_.tileH, 64),
                                   groupLimit(cl_, depthBounds_));
    KernelArgs(depthBounds_)
        .add(frame.depth)
        .add(frame.width())
        .add(frame.height())
        .add(tileDepth_)
        .done();
    q.enqueueNDRangeKernel(depthBounds_, cl::NullRange, cl::NDRange(tiles * group),
                           cl::NDRange(group), nullptr, timer_.next("depth_bounds"));

    // 2. Binning: count, scan, fill.
    cl_uint fillArg = 0;
    KernelArgs(binLights_)
        .add(frame.lightPositionRange)
        .add(frame.lightSpot)
        .add(frame.lightCount())
        .add(camera)
        .add(frame.camera.znear)
        .add(tileDepth_)
        .later(fillArg)
        .add(tileCount_)
        .add(tileOffset_)
        .add(tileCursor_)
        .add(tileLights_)
        .add(cl_uint(capacity_))
        .done();
    enqueueBinning(cl_, {binLights_, fillArg, scan_, sort_}, frame.lightCount(), tileCount_,
                   int(tiles), tileOffset_, total_, tileLights_, capacity_, timer_);

    // 3. Shading: one work-item per pixel.
    KernelArgs args(shade_);
    args.add(camera)
        .add(toCl(glm::vec4(frame.ambient, 0.0f)))
        .add(frame.gbufferArgs())
        .add(frame.lightArgs())
        .add(frame.directionalArgs())
        .add(tileCount_)
        .add(tileOffset_)
        .add(tileLights_)
        .add(cl_uint(capacity_))
        .add(image_);
    // Work-groups inside one tile: shade_tiled takes the tile from the group id.
    GroupShape g = tileDividingGroup(grid_.tileW, grid_.tileH, groupLimit(cl_, shade_));
    if (config_.lanes > 1) args.add(laneLocalMemory(config_, g.size()));
    args.done();
    q.enqueueNDRangeKernel(shade_, cl::NullRange, g.global(frame.width(), frame.height()),
                           g.local(), nullptr, timer_.next("shade"));
  }

  ClContext& cl_;
  TechniqueConfig config_;
  cl::Program program_;
  cl::Kernel depthBounds_, binLights_, scan_, sort_, shade_;
  TileGrid grid_;
  cl::Buffer tileDepth_, tileCount_, tileOffset_, tileCursor_, total_, tileLights_, image_;
  size_t capacity_ = 0;
  FrameTimer timer_;
};

}  // namespace

std::unique_ptr<Technique> makeTiledTechnique(ClContext& cl, const TechniqueConfig& config) {
  return std::make_unique<TiledTechnique>(cl, config);
}

}  // namespace ts
