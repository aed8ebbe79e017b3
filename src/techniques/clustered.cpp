// Clustered deferred shading (Olsson, Billeter & Assarsson 2012): tiles x exponential depth
// slices; the kernels, in launch order, are in kernels/clustered.cl.
//
// Work counters (docs/techniques.md):
//   lightingComputations  sum over clusters of (geometry pixels in the cluster x its list length).
//                         Unlike tiled's "tile pixels x list", background pixels are not counted:
//                         a cluster only exists where geometry is (a pixel without geometry has
//                         no depth, so no slice), so the paper's way to count is over geometry.
//   evaluations           shading calls made: each geometry pixel loops over its cluster's list,
//                         so the same number.
//   listMin/Mean/Max      lights per cluster over the non-empty clusters (those holding geometry);
//                         empty clusters get no lights and would only drag the mean to zero.
//   gbufferBytesRead      the depth plane is read three times per pixel (frame range, slices,
//                         shading) and once more per geometry pixel (cluster bounds), the other
//                         planes once per geometry pixel. The per-pixel slice key (2 B written,
//                         2 B read twice) is not G-buffer and is not counted.
// The per-cluster pixel counts come from the device (cluster_depth_bounds counts them while it
// assigns slices), so host and kernels agree on every pixel's cluster.
#include <algorithm>

#include "cl/kernel_args.h"
#include "cl/work_group.h"
#include "techniques/tile_grid.h"
#include "techniques/techniques.h"
#include "util/error.h"
#include "util/option_values.h"

namespace ts {
namespace {

constexpr uint16_t kBackgroundKey = 0xffff;  // pixel_slice of a pixel without geometry

class ClusteredTechnique : public Technique {
 public:
  ClusteredTechnique(ClContext& cl, const TechniqueConfig& config) : cl_(cl), config_(config) {
    if (config.tileWidth < 1 || config.tileHeight < 1) throw Error("tile size must be positive");
    // The slice is stored per pixel as a 16-bit key (0xffff = background), and
    // cluster_depth_bounds keeps three 32-bit counters per slice in local memory.
    if (config.clusterSlices < 1 || config.clusterSlices > kMaxClusterSlices)
      throw Error("cluster slices must be 1.." + std::to_string(kMaxClusterSlices) + ", got " +
                  std::to_string(config.clusterSlices));
    if (size_t(config.clusterSlices) * 12 + 2048 > cl.info().localMemBytes)
      throw Error(std::to_string(config.clusterSlices) +
                  " cluster slices need more local memory "
                  "than the device has (" +
                  std::to_string(cl.info().localMemBytes) + " B)");
    std::string options = config.kernelOptions() + " -DTILE_W=" + std::to_string(config.tileWidth) +
                          " -DTILE_H=" + std::to_string(config.tileHeight) +
                          " -DSLICES=" + std::to_string(config.clusterSlices) +
                          config.lanesOption();
    program_ = cl.build("clustered.cl", options);
    frameRange_ = cl::Kernel(program_, "frame_depth_range");
    pixelSlices_ = cl::Kernel(program_, "pixel_slices");
    clusterBounds_ = cl::Kernel(program_, "cluster_depth_bounds");
    binLights_ = cl::Kernel(program_, "bin_clusters");
    scan_ = cl::Kernel(program_, "exclusive_scan");
    sort_ = cl::Kernel(program_, "sort_bins");
    shade_ = cl::Kernel(program_, "shade_clustered");
  }

  std::string name() const override { return "clustered"; }
  int lanes() const override { return config_.lanes; }

  FrameResult renderFrame(DeviceFrame& frame, const FrameRequest& request) override {
    allocate(frame);
    if (config_.presizeLists)
      // Every light in every slice of its tile rectangle bounds the entries; capped, since many
      // slices make the bound loose (runUntilListFits covers a capped bound).
      reserveList(cl_, clusterLights_, capacity_,
                  std::min(tileListBound(grid_, frame, int(config_.spotCulling)) *
                               size_t(config_.clusterSlices),
                           size_t(16) << 20));
    FrameResult result;
    uint32_t total = runUntilListFits(
        cl_, clusterLights_, capacity_, total_,
        [&] {
          timer_.clear();
          enqueueFrame(frame);
        },
        "cluster", result.counters.notes);
    cl_.queue().finish();
    result.kernels = timer_.kernels();
    result.totalMs = timer_.totalMs();
    result.image = readImage(cl_, image_, frame);

    size_t clusters = clusterCount();
    std::vector<uint32_t> counts(clusters), pixels(clusters);
    cl_.queue().enqueueReadBuffer(clusterCount_, CL_TRUE, 0, clusters * 4, counts.data());
    cl_.queue().enqueueReadBuffer(clusterPixels_, CL_TRUE, 0, clusters * 4, pixels.data());
    auto notes = std::move(result.counters.notes);
    result.counters = workCounters(counts, pixels, frame);
    result.counters.notes = std::move(notes);
    if (request.wantAssignment) result.assignment = assignment(std::move(counts), total, frame);
    return result;
  }

 private:
  size_t clusterCount() const { return size_t(grid_.count()) * config_.clusterSlices; }

  WorkCounters workCounters(const std::vector<uint32_t>& counts,
                            const std::vector<uint32_t>& pixels, const DeviceFrame& frame) const {
    WorkCounters c;
    uint64_t geometry = 0, nonEmpty = 0;
    double sum = 0.0;
    c.listMin = UINT32_MAX;
    for (size_t k = 0; k < counts.size(); ++k) {
      if (pixels[k] == 0) continue;  // no geometry: no cluster (and no lights, by construction)
      c.lightingComputations += uint64_t(pixels[k]) * counts[k];
      geometry += pixels[k];
      ++nonEmpty;
      c.listMin = std::min(c.listMin, counts[k]);
      c.listMax = std::max(c.listMax, counts[k]);
      sum += counts[k];
    }
    if (nonEmpty == 0) c.listMin = 0;
    c.listMean = nonEmpty ? sum / double(nonEmpty) : 0.0;
    c.evaluations = c.lightingComputations;
    size_t screen = size_t(frame.width()) * frame.height();
    c.gbufferBytesRead = 3 * 4 * screen + geometry * frame.gbuffer->bytesPerPixel();
    addDirectionalWork(c, geometry, frame);
    return c;
  }

  LightAssignment assignment(std::vector<uint32_t> counts, uint32_t total,
                             const DeviceFrame& frame) {
    auto& q = cl_.queue();
    LightAssignment a;
    a.binOffset.resize(counts.size());
    q.enqueueReadBuffer(clusterOffset_, CL_TRUE, 0, counts.size() * 4, a.binOffset.data());
    a.binCount = std::move(counts);
    a.binLights.resize(std::max<uint32_t>(total, 1));
    q.enqueueReadBuffer(clusterLights_, CL_TRUE, 0, a.binLights.size() * 4, a.binLights.data());
    a.binLights.resize(total);
    // The pixels' clusters exactly as the kernels chose them (the stored slice keys).
    std::vector<uint16_t> keys(size_t(frame.width()) * frame.height());
    q.enqueueReadBuffer(pixelSlice_, CL_TRUE, 0, keys.size() * 2, keys.data());
    a.pixelBin.resize(keys.size());
    for (int y = 0; y < frame.height(); ++y)
      for (int x = 0; x < frame.width(); ++x) {
        size_t i = size_t(y) * frame.width() + x;
        a.pixelBin[i] = keys[i] == kBackgroundKey
                            ? -1
                            : int32_t(grid_.tileOf(x, y) * config_.clusterSlices + keys[i]);
      }
    return a;
  }

  void allocate(const DeviceFrame& frame) {
    TileGrid grid(frame.width(), frame.height(), config_.tileWidth, config_.tileHeight);
    if (grid.tilesX == grid_.tilesX && grid.tilesY == grid_.tilesY && grid.width == grid_.width &&
        grid.height == grid_.height)
      return;
    grid_ = grid;
    size_t clusters = clusterCount(), pixels = size_t(frame.width()) * frame.height();
    auto& ctx = cl_.context();
    depthRange_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, 2 * sizeof(cl_uint));
    clusterDepth_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, clusters * sizeof(cl_float2));
    clusterPixels_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, clusters * sizeof(uint32_t));
    tileSlices_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, size_t(grid_.count()) * sizeof(cl_int2));
    clusterCount_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, clusters * sizeof(uint32_t));
    clusterOffset_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, clusters * sizeof(uint32_t));
    clusterCursor_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, clusters * sizeof(uint32_t));
    pixelSlice_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, pixels * sizeof(cl_ushort));
    total_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, sizeof(uint32_t));
    // Most clusters hold no geometry, so size the first list by tiles, not clusters; it grows.
    reserveList(cl_, clusterLights_, capacity_, size_t(grid_.count()) * 8);
    image_ = cl::Buffer(ctx, CL_MEM_WRITE_ONLY, pixels * sizeof(cl_float4));
  }

  void enqueueFrame(DeviceFrame& frame) {
    auto& q = cl_.queue();
    cl_float4 camera = toCl(frame.camera.kernelCamera());
    size_t tiles = size_t(grid_.count()), clusters = clusterCount();
    size_t pixels = size_t(frame.width()) * frame.height();
    const uint32_t zero = 0;
    const cl_uint2 emptyRange = {{0x7f7fffffu, 0u}};  // (FLT_MAX, 0) as bits: min > max
    q.enqueueFillBuffer(depthRange_, emptyRange, 0, sizeof(cl_uint2), nullptr,
                        timer_.next("clear"));
    q.enqueueFillBuffer(clusterCount_, zero, 0, clusters * 4, nullptr, timer_.next("clear"));
    q.enqueueFillBuffer(clusterCursor_, zero, 0, clusters * 4, nullptr, timer_.next("clear"));

    // 1. The frame's geometry depth range (slicing), then per-cluster bounds: a work-group per
    // tile.
    const size_t rangeGroup =
        powerOfTwoGroup(64, groupLimit(cl_, frameRange_));  // DEPTH_RANGE_GROUP
    size_t rangeGroups = std::clamp<size_t>(pixels / (rangeGroup * 16 * 16), 1,
                                            1024);  // 16 vectors of 16 pixels per item
    KernelArgs(frameRange_).add(frame.depth).add(int(pixels)).add(depthRange_).done();
    q.enqueueNDRangeKernel(frameRange_, cl::NullRange, cl::NDRange(rangeGroups * rangeGroup),
                           cl::NDRange(rangeGroup), nullptr, timer_.next("depth_range"));
    const size_t sliceGroup = std::min<size_t>(64, groupLimit(cl_, pixelSlices_).size);
    KernelArgs(pixelSlices_)
        .add(frame.depth)
        .add(int(pixels))
        .add(depthRange_)
        .add(pixelSlice_)
        .done();
    q.enqueueNDRangeKernel(
        pixelSlices_, cl::NullRange, cl::NDRange(roundUp((pixels + 15) / 16, sliceGroup)),
        cl::NDRange(sliceGroup), nullptr, timer_.next("slices"));  // 16 pixels per item
    // One work-item per row of the tile (kernels/clustered.cl).
    size_t group =
        std::min<size_t>({size_t(grid_.tileH), 64, groupLimit(cl_, clusterBounds_).size});
    KernelArgs(clusterBounds_)
        .add(frame.depth)
        .add(frame.width())
        .add(frame.height())
        .add(pixelSlice_)
        .add(clusterDepth_)
        .add(clusterPixels_)
        .add(tileSlices_)
        .done();
    q.enqueueNDRangeKernel(clusterBounds_, cl::NullRange, cl::NDRange(tiles * group),
                           cl::NDRange(group), nullptr, timer_.next("cluster_bounds"));

    // 2. Binning: count, scan, fill.
    cl_uint fillArg = 0;
    KernelArgs(binLights_)
        .add(frame.lightPositionRange)
        .add(frame.lightSpot)
        .add(frame.lightCount())
        .add(camera)
        .add(frame.camera.znear)
        .add(depthRange_)
        .add(clusterDepth_)
        .add(tileSlices_)
        .later(fillArg)
        .add(clusterCount_)
        .add(clusterOffset_)
        .add(clusterCursor_)
        .add(clusterLights_)
        .add(cl_uint(capacity_))
        .done();
    enqueueBinning(cl_, {binLights_, fillArg, scan_, sort_}, frame.lightCount(), clusterCount_,
                   int(clusters), clusterOffset_, total_, clusterLights_, capacity_, timer_);

    // 3. Shading: one work-item per pixel, or in lanes with work-groups inside one tile
    // (shade_clustered then takes the tile, and so its clusters, from the group id).
    KernelArgs args(shade_);
    args.add(camera)
        .add(toCl(glm::vec4(frame.ambient, 0.0f)))
        .add(frame.gbufferArgs())
        .add(frame.lightArgs())
        .addIf(config_.features.shadows, frame.lightShadowArgs())
        .add(frame.directionalArgs())
        .addIf(config_.features.shadows, frame.directionalShadowArgs())
        .add(pixelSlice_)
        .add(clusterCount_)
        .add(clusterOffset_)
        .add(clusterLights_)
        .add(cl_uint(capacity_))
        .add(image_);
    // In lanes a work-group lies inside one tile (its clusters are the tile's).
    GroupShape g = config_.lanes > 1
                       ? tileDividingGroup(grid_.tileW, grid_.tileH, groupLimit(cl_, shade_))
                       : fitGroup(std::min(grid_.tileW, 16), std::min(grid_.tileH, 16),
                                  groupLimit(cl_, shade_));
    if (config_.lanes > 1) args.add(laneLocalMemory(config_, g.size()));
    args.done();
    q.enqueueNDRangeKernel(shade_, cl::NullRange, g.global(frame.width(), frame.height()),
                           g.local(), nullptr, timer_.next("shade"));
  }

  ClContext& cl_;
  TechniqueConfig config_;
  cl::Program program_;
  cl::Kernel frameRange_, pixelSlices_, clusterBounds_, binLights_, scan_, sort_, shade_;
  TileGrid grid_;
  cl::Buffer depthRange_, clusterDepth_, clusterPixels_, tileSlices_, clusterCount_, clusterOffset_,
      clusterCursor_, pixelSlice_, total_, clusterLights_, image_;
  size_t capacity_ = 0;
  FrameTimer timer_;
};

}  // namespace

std::unique_ptr<Technique> makeClusteredTechnique(ClContext& cl, const TechniqueConfig& config) {
  return std::make_unique<ClusteredTechnique>(cl, config);
}

}  // namespace ts
