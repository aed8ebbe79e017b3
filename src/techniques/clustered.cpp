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
#include <optional>

#include "cl/kernel_args.h"
#include "cl/work_group.h"
#include "techniques/cluster_light_grid.h"
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
    grid_.emplace(cl, program_, config.clusterSlices, "clustered");
    frameRange_ = cl::Kernel(program_, "frame_depth_range");
    pixelSlices_ = cl::Kernel(program_, "pixel_slices");
    clusterBounds_ = cl::Kernel(program_, "cluster_depth_bounds");
    shade_ = cl::Kernel(program_, "shade_clustered");
  }

  std::string name() const override { return "clustered"; }
  int lanes() const override { return config_.lanes; }

  FrameResult renderFrame(DeviceFrame& frame, const FrameRequest& request) override {
    allocate(frame);
    if (config_.presizeLists) grid_->presize(frame, int(config_.spotCulling));
    FrameResult result;
    uint32_t total = grid_->runUntilListFits(
        [&] {
          timer_.clear();
          enqueueFrame(frame);
        },
        result.counters.notes);
    cl_.queue().finish();
    result.kernels = timer_.kernels();
    result.totalMs = timer_.totalMs();
    result.image = readImage(cl_, image_, frame);

    size_t clusters = clusterCount();
    std::vector<uint32_t> counts = grid_->readCounts(), pixels(clusters);
    cl_.queue().enqueueReadBuffer(clusterPixels_, CL_TRUE, 0, clusters * 4, pixels.data());
    auto notes = std::move(result.counters.notes);
    result.counters = workCounters(counts, pixels, frame);
    result.counters.notes = std::move(notes);
    if (request.wantAssignment) result.assignment = assignment(std::move(counts), total, frame);
    return result;
  }

 private:
  size_t clusterCount() const { return grid_->clusterCount(); }

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
    a.binOffset = grid_->readOffsets();
    a.binCount = std::move(counts);
    a.binLights = grid_->readLights(total);
    // The pixels' clusters exactly as the kernels chose them (the stored slice keys).
    std::vector<uint16_t> keys(size_t(frame.width()) * frame.height());
    q.enqueueReadBuffer(pixelSlice_, CL_TRUE, 0, keys.size() * 2, keys.data());
    a.pixelBin.resize(keys.size());
    for (int y = 0; y < frame.height(); ++y)
      for (int x = 0; x < frame.width(); ++x) {
        size_t i = size_t(y) * frame.width() + x;
        a.pixelBin[i] =
            keys[i] == kBackgroundKey
                ? -1
                : int32_t(grid_->tiles().tileOf(x, y) * config_.clusterSlices + keys[i]);
      }
    return a;
  }

  void allocate(const DeviceFrame& frame) {
    if (!grid_->allocate(frame.width(), frame.height(), config_.tileWidth, config_.tileHeight))
      return;
    size_t clusters = clusterCount(), pixels = size_t(frame.width()) * frame.height();
    auto& ctx = cl_.context();
    clusterPixels_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, clusters * sizeof(uint32_t));
    pixelSlice_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, pixels * sizeof(cl_ushort));
    image_ = cl::Buffer(ctx, CL_MEM_WRITE_ONLY, pixels * sizeof(cl_float4));
  }

  void enqueueFrame(DeviceFrame& frame) {
    auto& q = cl_.queue();
    cl_float4 camera = toCl(frame.camera.kernelCamera());
    const TileGrid& grid = grid_->tiles();
    size_t tiles = size_t(grid.count());
    size_t pixels = size_t(frame.width()) * frame.height();
    const cl_uint2 emptyRange = {{0x7f7fffffu, 0u}};  // (FLT_MAX, 0) as bits: min > max
    q.enqueueFillBuffer(grid_->depthRange(), emptyRange, 0, sizeof(cl_uint2), nullptr,
                        timer_.next("clear"));
    grid_->enqueueClear(timer_);

    // 1. The frame's geometry depth range (slicing), then per-cluster bounds: a work-group per
    // tile.
    const size_t rangeGroup =
        powerOfTwoGroup(64, groupLimit(cl_, frameRange_));  // DEPTH_RANGE_GROUP
    size_t rangeGroups = std::clamp<size_t>(pixels / (rangeGroup * 16 * 16), 1,
                                            1024);  // 16 vectors of 16 pixels per item
    KernelArgs(frameRange_).add(frame.depth).add(int(pixels)).add(grid_->depthRange()).done();
    q.enqueueNDRangeKernel(frameRange_, cl::NullRange, cl::NDRange(rangeGroups * rangeGroup),
                           cl::NDRange(rangeGroup), nullptr, timer_.next("depth_range"));
    const size_t sliceGroup = std::min<size_t>(64, groupLimit(cl_, pixelSlices_).size);
    KernelArgs(pixelSlices_)
        .add(frame.depth)
        .add(int(pixels))
        .add(grid_->depthRange())
        .add(pixelSlice_)
        .done();
    q.enqueueNDRangeKernel(
        pixelSlices_, cl::NullRange, cl::NDRange(roundUp((pixels + 15) / 16, sliceGroup)),
        cl::NDRange(sliceGroup), nullptr, timer_.next("slices"));  // 16 pixels per item
    // One work-item per row of the tile (kernels/clustered.cl).
    size_t group = std::min<size_t>({size_t(grid.tileH), 64, groupLimit(cl_, clusterBounds_).size});
    KernelArgs(clusterBounds_)
        .add(frame.depth)
        .add(frame.width())
        .add(frame.height())
        .add(pixelSlice_)
        .add(grid_->clusterDepth())
        .add(clusterPixels_)
        .add(grid_->tileSlices())
        .done();
    q.enqueueNDRangeKernel(clusterBounds_, cl::NullRange, cl::NDRange(tiles * group),
                           cl::NDRange(group), nullptr, timer_.next("cluster_bounds"));

    // 2. Binning: count, scan, fill.
    grid_->enqueueBinning(frame, timer_);

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
        .add(grid_->counts())
        .add(grid_->offsets())
        .add(grid_->lights())
        .add(grid_->capacity())
        .add(image_);
    // In lanes a work-group lies inside one tile (its clusters are the tile's).
    GroupShape g =
        config_.lanes > 1
            ? tileDividingGroup(grid.tileW, grid.tileH, groupLimit(cl_, shade_))
            : fitGroup(std::min(grid.tileW, 16), std::min(grid.tileH, 16), groupLimit(cl_, shade_));
    if (config_.lanes > 1) args.add(laneLocalMemory(config_, g.size()));
    args.done();
    q.enqueueNDRangeKernel(shade_, cl::NullRange, g.global(frame.width(), frame.height()),
                           g.local(), nullptr, timer_.next("shade"));
  }

  ClContext& cl_;
  TechniqueConfig config_;
  cl::Program program_;
  cl::Kernel frameRange_, pixelSlices_, clusterBounds_, shade_;
  std::optional<ClusterLightGrid> grid_;  // made with the program
  cl::Buffer clusterPixels_, pixelSlice_, image_;
  FrameTimer timer_;
};

}  // namespace

std::unique_ptr<Technique> makeClusteredTechnique(ClContext& cl, const TechniqueConfig& config) {
  return std::make_unique<ClusteredTechnique>(cl, config);
}

}  // namespace ts
