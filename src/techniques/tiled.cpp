// Multi-kernel tiled deferred shading; the kernels, in launch order, are in kernels/tiled.cl.
// A frame with transparent surfaces (--blend blend, --raster gl) gets the paper's hybrid after
// (techniques/transparent_hybrid.h). A multisampled frame (--msaa N, --raster gl) is shaded from
// its per-sample G-buffer as Lauritzen's tiled deferred (techniques/multisampled_gbuffer.h): the
// tiles' depth ranges over every sample, an edge mask, every pixel's sample 0 shaded by
// shade_tiled, then the edge pixels' other samples and the average (shade_tiled_edge_samples).
#include <optional>

#include "cl/kernel_args.h"
#include "cl/work_group.h"
#include "techniques/multisampled_gbuffer.h"
#include "techniques/tile_light_grid.h"
#include "techniques/techniques.h"
#include "techniques/transparent_hybrid.h"
#include "util/error.h"

namespace ts {
namespace {

class TiledTechnique : public Technique {
 public:
  TiledTechnique(ClContext& cl, const TechniqueConfig& config)
      : cl_(cl), config_(config), program_(build(cl, config)), grid_(cl, program_) {
    shade_ = cl::Kernel(program_, "shade_tiled");
  }

  std::string name() const override { return "tiled"; }
  int lanes() const override { return config_.lanes; }

  FrameResult renderFrame(DeviceFrame& frame, const FrameRequest& request) override {
    if (frame.forward && frame.forward->samples() > 1) return renderMultisampled(frame, request);
    allocate(frame);
    FrameResult result = run(
        frame, request, [&] { enqueueFrame(frame); },
        [&](const std::vector<uint32_t>& counts) {
          return tileWorkCounters(grid_.grid(), counts, frame);
        });
    // --blend blend: the glass in a tiled forward pass over the grid, after the lists are read
    // (its re-binning overwrites them).
    if (hasTransparentDraws(frame))
      shadeTransparentOver(cl_, image_, frame, grid_, config_, result);
    else result.image = readImage(cl_, image_, frame);
    return result;
  }

 private:
  static cl::Program build(ClContext& cl, const TechniqueConfig& config) {
    if (config.tileWidth < 1 || config.tileHeight < 1) throw Error("tile size must be positive");
    std::string options = config.kernelOptions() + " -DTILE_W=" + std::to_string(config.tileWidth) +
                          " -DTILE_H=" + std::to_string(config.tileHeight) + config.lanesOption();
    return cl.build("tiled.cl", options);
  }

  void allocate(const DeviceFrame& frame) {
    if (grid_.allocate(frame.width(), frame.height(), config_.tileWidth, config_.tileHeight))
      // Read and write: with --msaa shade_tiled_edge_samples adds to sample 0's shades.
      image_ = cl::Buffer(cl_.context(), CL_MEM_READ_WRITE,
                          size_t(frame.width()) * frame.height() * sizeof(cl_float4));
  }

  // --msaa N: the G-buffer of every sample (DeviceFrame::samples, in the frame's layout).
  FrameResult renderMultisampled(DeviceFrame& frame, const FrameRequest& request) {
    const std::vector<EncodedGBuffer>& planes = multisampledPlanes(frame, "tiled");
    if (!msaa_) {
      // The edges' samples are shaded one per work-item (kernels/gbuffer.h's scalar shading, in
      // builds without lanes only): with lanes a second build of tiled.cl without them, made at
      // the first multisampled frame so that no other frame pays for its compile.
      TechniqueConfig scalar = config_;
      scalar.lanes = 1;
      edgeProgram_ = config_.lanes > 1 ? build(cl_, scalar) : program_;
      shadeEdges_ = cl::Kernel(edgeProgram_, "shade_tiled_edge_samples");
      msaa_.emplace(cl_, edgeProgram_);
    }
    msaa_->upload(planes, *frame.gbuffer);
    allocate(frame);
    FrameResult result = run(
        frame, request, [&] { enqueueMultisampled(frame); },
        [&](const std::vector<uint32_t>& counts) {
          return multisampledTileWorkCounters(grid_.grid(), counts, planes, msaa_->readEdges(),
                                              frame);
        });
    result.image = readImage(cl_, image_, frame);
    return result;
  }

  // Both forms' frame: `enqueue`d until the lists fit, its kernel rows, its counters (`counters`
  // of the tiles' list lengths, the binning's notes kept) and, when asked, the assignment.
  template <typename Enqueue, typename Counters>
  FrameResult run(DeviceFrame& frame, const FrameRequest& request, Enqueue enqueue,
                  Counters counters) {
    if (config_.presizeLists) grid_.presize(frame, int(config_.spotCulling));
    FrameResult result;
    uint32_t total = grid_.runUntilListFits(
        [&] {
          timer_.clear();
          enqueue();
        },
        result.counters.notes);
    cl_.queue().finish();
    result.kernels = timer_.kernels();
    result.totalMs = timer_.totalMs();

    const std::vector<uint32_t> counts = grid_.readCounts();
    auto notes = std::move(result.counters.notes);
    result.counters = counters(counts);
    result.counters.notes = std::move(notes);
    if (request.wantAssignment)
      result.assignment =
          tileAssignment(grid_.grid(), grid_.readOffsets(), counts, grid_.readLights(total));
    return result;
  }

  void enqueueFrame(DeviceFrame& frame) {
    // 1. Depth bounds, 2. binning: count, scan, fill, sort (techniques/tile_light_grid.h).
    grid_.enqueueClear(timer_);
    grid_.enqueueDepthBounds(frame.depth, frame.width(), frame.height(), timer_);
    grid_.enqueueBinning(frame, timer_);
    // 3. Shading: one work-item per pixel.
    enqueueShading(frame, frame.gbufferArgs());
  }

  // The multisampled frame: the ranges over every sample's depth (no sample's surface culled),
  // the same binning, the edge mask, sample 0 of every pixel as without MSAA (the planes'
  // first width x height elements), then the edges' other samples.
  void enqueueMultisampled(DeviceFrame& frame) {
    const MultisampledGBuffer& ms = *msaa_;
    grid_.enqueueClear(timer_);
    grid_.enqueueDepthBounds(ms.depth(), frame.width(), frame.height(), timer_, ms.samples());
    grid_.enqueueBinning(frame, timer_);
    msaa_->enqueueEdgeMask(timer_);
    enqueueShading(frame, ms.gbufferArgs());
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

  // What shade_tiled and shade_tiled_edge_samples take first: the camera, the ambient, `planes`,
  // the lights (with their shadow maps in builds with shadows) and the tile lists.
  template <typename Planes>
  KernelArgs& addShadingArgs(KernelArgs& args, DeviceFrame& frame, const Planes& planes) {
    return args.add(toCl(frame.camera.kernelCamera()))
        .add(toCl(glm::vec4(frame.ambient, 0.0f)))
        .add(planes)
        .add(frame.lightArgs())
        .addIf(config_.features.shadows, frame.lightShadowArgs())
        .add(frame.directionalArgs())
        .addIf(config_.features.shadows, frame.directionalShadowArgs())
        .add(grid_.counts())
        .add(grid_.offsets())
        .add(grid_.lights())
        .add(grid_.capacity());
  }

  // shade_tiled over `planes` (the frame's, or sample 0's of the multisampled G-buffer).
  template <typename Planes>
  void enqueueShading(DeviceFrame& frame, const Planes& planes) {
    KernelArgs args(shade_);
    addShadingArgs(args, frame, planes).add(image_);
    // Work-groups inside one tile: shade_tiled takes the tile from the group id.
    const TileGrid& grid = grid_.grid();
    GroupShape g = tileDividingGroup(grid.tileW, grid.tileH, groupLimit(cl_, shade_));
    if (config_.lanes > 1) args.add(laneLocalMemory(config_, g.size()));
    args.done();
    cl_.queue().enqueueNDRangeKernel(shade_, cl::NullRange, g.global(frame.width(), frame.height()),
                                     g.local(), nullptr, timer_.next("shade"));
  }

  ClContext& cl_;
  TechniqueConfig config_;
  cl::Program program_;
  TileLightGrid grid_;
  cl::Kernel shade_;
  cl::Program edgeProgram_;  // --msaa: tiled.cl without lanes (program_ itself at lanes 1)
  cl::Kernel shadeEdges_;
  std::optional<MultisampledGBuffer> msaa_;  // made at the first multisampled frame
  cl::Buffer image_;
  FrameTimer timer_;
};

}  // namespace

std::unique_ptr<Technique> makeTiledTechnique(ClContext& cl, const TechniqueConfig& config) {
  return std::make_unique<TiledTechnique>(cl, config);
}

}  // namespace ts
