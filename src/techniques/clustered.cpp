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
//
// --msaa N (--raster gl): as tiled's (techniques/multisampled_gbuffer.h), with every sample in its
// own cluster: the frame's depth range, the slice keys and the clusters' bounds over every
// sample's depth (so a cluster that only an edge's other sample falls in is binned), sample 0 of
// every pixel shaded by shade_clustered, then the edge pixels' other samples, each with its own
// cluster's list, and the average (shade_clustered_edge_samples). The counters then count the
// samples shaded: every pixel's sample 0 with geometry, and the edges' other samples with
// geometry, each times its cluster's list.
#include <algorithm>
#include <optional>

#include "cl/kernel_args.h"
#include "cl/work_group.h"
#include "techniques/cluster_light_grid.h"
#include "techniques/multisampled_gbuffer.h"
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
    program_ = build(cl, config);
    grid_.emplace(cl, program_, config.clusterSlices, "clustered");
    frameRange_ = cl::Kernel(program_, "frame_depth_range");
    pixelSlices_ = cl::Kernel(program_, "pixel_slices");
    clusterBounds_ = cl::Kernel(program_, "cluster_depth_bounds");
    shade_ = cl::Kernel(program_, "shade_clustered");
  }

  std::string name() const override { return "clustered"; }
  int lanes() const override { return config_.lanes; }

  FrameResult renderFrame(DeviceFrame& frame, const FrameRequest& request) override {
    const int samples = frame.forward ? frame.forward->samples() : 1;
    if (samples > 1) uploadSamples(frame);
    allocate(frame, samples);
    if (config_.presizeLists) grid_->presize(frame, int(config_.spotCulling));
    FrameResult result;
    uint32_t total = grid_->runUntilListFits(
        [&] {
          timer_.clear();
          enqueueFrame(frame, samples);
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
    std::vector<uint16_t> keys;
    if (samples > 1 || request.wantAssignment) keys = readKeys(frame, samples);
    result.counters = samples > 1 ? multisampledWorkCounters(counts, pixels, keys, frame)
                                  : workCounters(counts, pixels, frame);
    result.counters.notes = std::move(notes);
    if (request.wantAssignment)
      result.assignment = assignment(std::move(counts), total, keys, frame);
    return result;
  }

 private:
  static cl::Program build(ClContext& cl, const TechniqueConfig& config) {
    std::string options = config.kernelOptions() + " -DTILE_W=" + std::to_string(config.tileWidth) +
                          " -DTILE_H=" + std::to_string(config.tileHeight) +
                          " -DSLICES=" + std::to_string(config.clusterSlices) +
                          config.lanesOption();
    return cl.build("clustered.cl", options);
  }

  size_t clusterCount() const { return grid_->clusterCount(); }

  // --msaa N: every sample's planes on the device (DeviceFrame::samples, in the frame's layout).
  void uploadSamples(DeviceFrame& frame) {
    const std::vector<EncodedGBuffer>& planes = multisampledPlanes(frame, "clustered");
    if (!msaa_) {
      // The edges' samples are shaded one per work-item (kernels/gbuffer.h's scalar shading):
      // with lanes a second build of clustered.cl without them, made at the first multisampled
      // frame so that no other frame pays for its compile.
      TechniqueConfig scalar = config_;
      scalar.lanes = 1;
      edgeProgram_ = config_.lanes > 1 ? build(cl_, scalar) : program_;
      shadeEdges_ = cl::Kernel(edgeProgram_, "shade_clustered_edge_samples");
      msaa_.emplace(cl_, edgeProgram_);
    }
    msaa_->upload(planes, *frame.gbuffer);
  }

  // The stored slice keys of every sample (sample-major), after the queue finished the frame.
  std::vector<uint16_t> readKeys(const DeviceFrame& frame, int samples) const {
    std::vector<uint16_t> keys(size_t(frame.width()) * frame.height() * size_t(samples));
    cl_.queue().enqueueReadBuffer(pixelSlice_, CL_TRUE, 0, keys.size() * 2, keys.data());
    return keys;
  }

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

  // The counters of a multisampled frame (see the top of the file): its lists' statistics as
  // workCounters' (over the clusters holding some sample), lighting computations and evaluations
  // over the samples shaded, and the G-buffer bytes estimated from the passes (range, slices and
  // the edge mask: every sample's depth and planes; bounds: every geometry sample's depth;
  // shading: sample 0's planes, the edges' further samples').
  WorkCounters multisampledWorkCounters(const std::vector<uint32_t>& counts,
                                        const std::vector<uint32_t>& pixels,
                                        const std::vector<uint16_t>& keys,
                                        const DeviceFrame& frame) const {
    WorkCounters c = workCounters(counts, pixels, frame);
    const std::vector<uint8_t> edges = msaa_->readEdges();
    const TileGrid& grid = grid_->tiles();
    const size_t plane = size_t(frame.width()) * frame.height();
    const size_t samples = size_t(msaa_->samples());
    const uint64_t perSample = frame.gbuffer->bytesPerPixel();
    SampleShading shading;
    shading.samples = int(samples);
    uint64_t shaded = 0, geometrySamples = 0;
    c.lightingComputations = 0;
    for (uint32_t p : pixels) geometrySamples += p;
    for (int y = 0; y < frame.height(); ++y)
      for (int x = 0; x < frame.width(); ++x) {
        const size_t i = size_t(y) * frame.width() + size_t(x);
        const size_t last = edges[i] ? samples : 1;
        if (edges[i]) ++shading.pixelsShadedPerSample;
        for (size_t k = 0; k < last; ++k) {
          const uint16_t key = keys[k * plane + i];
          if (key == kBackgroundKey) continue;
          c.lightingComputations += counts[size_t(grid.tileOf(x, y)) * grid_->slices() + key];
          ++shaded;
        }
      }
    c.evaluations = c.lightingComputations;
    c.gbufferBytesRead = 2 * 4 * plane * samples + 4 * geometrySamples +
                         perSample * plane * samples + 4 * plane + shaded * (perSample - 4);
    addDirectionalWork(c, shaded, frame);
    shading.gbufferBytes = msaa_->bytes();
    c.sampleShading = shading;
    return c;
  }

  LightAssignment assignment(std::vector<uint32_t> counts, uint32_t total,
                             const std::vector<uint16_t>& keys, const DeviceFrame& frame) {
    LightAssignment a;
    a.binOffset = grid_->readOffsets();
    a.binCount = std::move(counts);
    a.binLights = grid_->readLights(total);
    // The pixels' clusters exactly as the kernels chose them (the stored slice keys); with --msaa
    // one plane per sample (reference.h's countMissedOverSamples reads them so).
    const size_t plane = size_t(frame.width()) * frame.height();
    a.pixelBin.resize(keys.size());
    for (size_t k = 0; k < keys.size() / plane; ++k)
      for (int y = 0; y < frame.height(); ++y)
        for (int x = 0; x < frame.width(); ++x) {
          size_t i = k * plane + size_t(y) * frame.width() + x;
          a.pixelBin[i] =
              keys[i] == kBackgroundKey
                  ? -1
                  : int32_t(grid_->tiles().tileOf(x, y) * config_.clusterSlices + keys[i]);
        }
    return a;
  }

  void allocate(const DeviceFrame& frame, int samples) {
    size_t pixels = size_t(frame.width()) * frame.height();
    auto& ctx = cl_.context();
    if (grid_->allocate(frame.width(), frame.height(), config_.tileWidth, config_.tileHeight)) {
      clusterPixels_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, clusterCount() * sizeof(uint32_t));
      // Read and write: with --msaa shade_clustered_edge_samples adds to sample 0's shades.
      image_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, pixels * sizeof(cl_float4));
      keySamples_ = 0;
    }
    if (keySamples_ != samples) {  // one key per sample of every pixel
      pixelSlice_ =
          cl::Buffer(ctx, CL_MEM_READ_WRITE, pixels * size_t(samples) * sizeof(cl_ushort));
      keySamples_ = samples;
    }
  }

  // `samples` > 1: the multisampled frame (uploadSamples), its depth planes one after another.
  void enqueueFrame(DeviceFrame& frame, int samples) {
    auto& q = cl_.queue();
    const TileGrid& grid = grid_->tiles();
    size_t tiles = size_t(grid.count());
    const cl::Buffer& depth = samples > 1 ? msaa_->depth() : frame.depth;
    size_t pixels = size_t(frame.width()) * frame.height() * size_t(samples);  // depths
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
    KernelArgs(frameRange_).add(depth).add(int(pixels)).add(grid_->depthRange()).done();
    q.enqueueNDRangeKernel(frameRange_, cl::NullRange, cl::NDRange(rangeGroups * rangeGroup),
                           cl::NDRange(rangeGroup), nullptr, timer_.next("depth_range"));
    const size_t sliceGroup = std::min<size_t>(64, groupLimit(cl_, pixelSlices_).size);
    KernelArgs(pixelSlices_)
        .add(depth)
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
        .add(depth)
        .add(frame.width())
        .add(frame.height())
        .add(pixelSlice_)
        .add(grid_->clusterDepth())
        .add(clusterPixels_)
        .add(grid_->tileSlices())
        .add(cl_int(samples))
        .done();
    q.enqueueNDRangeKernel(clusterBounds_, cl::NullRange, cl::NDRange(tiles * group),
                           cl::NDRange(group), nullptr, timer_.next("cluster_bounds"));

    // 2. Binning: count, scan, fill.
    grid_->enqueueBinning(frame, timer_);

    // 3. Shading: one work-item per pixel, or in lanes with work-groups inside one tile
    // (shade_clustered then takes the tile, and so its clusters, from the group id). With
    // --msaa: sample 0 (the planes' first width x height elements, the keys' first plane), then
    // the edge mask and the edges' other samples.
    if (samples > 1) enqueueShading(frame, msaa_->gbufferArgs());
    else enqueueShading(frame, frame.gbufferArgs());
    if (samples > 1) enqueueEdgeSamples(frame);
  }

  // What shade_clustered and shade_clustered_edge_samples take first: the camera, the ambient,
  // `planes`, the lights (with their shadow maps in builds with shadows), the slice keys and the
  // cluster lists.
  template <typename Planes>
  KernelArgs& addShadingArgs(KernelArgs& args, DeviceFrame& frame, const Planes& planes) {
    return args.add(toCl(frame.camera.kernelCamera()))
        .add(toCl(glm::vec4(frame.ambient, 0.0f)))
        .add(planes)
        .add(frame.lightArgs())
        .addIf(config_.features.shadows, frame.lightShadowArgs())
        .add(frame.directionalArgs())
        .addIf(config_.features.shadows, frame.directionalShadowArgs())
        .add(pixelSlice_)
        .add(grid_->counts())
        .add(grid_->offsets())
        .add(grid_->lights())
        .add(grid_->capacity());
  }

  template <typename Planes>
  void enqueueShading(DeviceFrame& frame, const Planes& planes) {
    const TileGrid& grid = grid_->tiles();
    KernelArgs args(shade_);
    addShadingArgs(args, frame, planes).add(image_);
    // In lanes a work-group lies inside one tile (its clusters are the tile's).
    GroupShape g =
        config_.lanes > 1
            ? tileDividingGroup(grid.tileW, grid.tileH, groupLimit(cl_, shade_))
            : fitGroup(std::min(grid.tileW, 16), std::min(grid.tileH, 16), groupLimit(cl_, shade_));
    if (config_.lanes > 1) args.add(laneLocalMemory(config_, g.size()));
    args.done();
    cl_.queue().enqueueNDRangeKernel(shade_, cl::NullRange, g.global(frame.width(), frame.height()),
                                     g.local(), nullptr, timer_.next("shade"));
  }

  void enqueueEdgeSamples(DeviceFrame& frame) {
    const MultisampledGBuffer& ms = *msaa_;
    msaa_->enqueueEdgeMask(timer_);
    KernelArgs args(shadeEdges_);
    addShadingArgs(args, frame, ms.gbufferArgs())
        .add(ms.edges())
        .add(cl_int(ms.samples()))
        .add(ms.planeBytes())
        .add(image_)
        .done();
    const GroupShape g = fitGroup(16, 16, groupLimit(cl_, shadeEdges_));
    cl_.queue().enqueueNDRangeKernel(shadeEdges_, cl::NullRange,
                                     g.global(frame.width(), frame.height()), g.local(), nullptr,
                                     timer_.next("shade_edge_samples"));
  }

  ClContext& cl_;
  TechniqueConfig config_;
  cl::Program program_;
  cl::Kernel frameRange_, pixelSlices_, clusterBounds_, shade_;
  std::optional<ClusterLightGrid> grid_;  // made with the program
  cl::Buffer clusterPixels_, pixelSlice_, image_;
  int keySamples_ = 0;       // the samples pixelSlice_ holds keys for
  cl::Program edgeProgram_;  // --msaa: clustered.cl without lanes (program_ itself at lanes 1)
  cl::Kernel shadeEdges_;
  std::optional<MultisampledGBuffer> msaa_;  // made at the first multisampled frame
  FrameTimer timer_;
};

}  // namespace

std::unique_ptr<Technique> makeClusteredTechnique(ClContext& cl, const TechniqueConfig& config) {
  return std::make_unique<ClusteredTechnique>(cl, config);
}

}  // namespace ts
