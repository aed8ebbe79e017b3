// Tiled forward shading (Olsson & Assarsson 2011, TiledFwd and TiledFwd-PreZ): the light grid of
// `tiled`, built by the same OpenCL kernels (kernels/tiled.cl), read by a fragment shader that
// draws the scene (raster/forward_scene.h; OpenGL, shaders/tiled_forward.frag).
//   tiled-forward       no depth range: every tile gets the camera's whole [znear, zfar] instead
//                       of tile_depth_bounds' output, so a light is binned by its screen rectangle
//                       only (the paper's TiledFwd); the scene drawn once with the depth test.
//   tiled-forward-prez  a depth-only pre-pass, its linear depth through tile_depth_bounds as in
//                       `tiled`, then the forward pass with the depth test EQUAL (TiledFwd-PreZ).
// The grid is copied through the host (PoCL and llvmpipe share nothing): its own row, grid_copy,
// in the per-kernel table, as are the OpenGL passes (timer queries): depth_prepass, forward.
#include <algorithm>
#include <cfloat>
#include <chrono>

#include "cl/kernel_args.h"
#include "cl/work_group.h"
#include "techniques/techniques.h"
#include "techniques/tile_grid.h"
#include "util/error.h"

namespace ts {
namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

class TiledForwardTechnique : public Technique {
 public:
  TiledForwardTechnique(ClContext& cl, const TechniqueConfig& config, bool prez)
      : cl_(cl), config_(config), prez_(prez) {
    if (config.tileWidth < 1 || config.tileHeight < 1) throw Error("tile size must be positive");
    // The binning kernels of `tiled`, built as tiled builds them (its shading kernel is unused).
    std::string options = config.kernelOptions() + " -DTILE_W=" + std::to_string(config.tileWidth) +
                          " -DTILE_H=" + std::to_string(config.tileHeight);
    program_ = cl.build("tiled.cl", options);
    depthBounds_ = cl::Kernel(program_, "tile_depth_bounds");
    binLights_ = cl::Kernel(program_, "bin_lights");
    scan_ = cl::Kernel(program_, "exclusive_scan");
    sort_ = cl::Kernel(program_, "sort_bins");
  }

  std::string name() const override { return prez_ ? "tiled-forward-prez" : "tiled-forward"; }

  FrameResult renderFrame(DeviceFrame& frame, const FrameRequest& request) override {
    if (!frame.forward)
      throw Error(name() +
                  " draws the scene: it needs a frame rasterized with --raster gl (not the "
                  "software rasterizer or an imported G-buffer)");
    allocate(frame);
    FrameResult result;
    double prepassMs = 0.0;
    if (prez_) {
      const std::vector<float> depth = frame.forward->depthPrepass(prepassMs);
      cl_.queue().enqueueWriteBuffer(prepassDepth_, CL_TRUE, 0, depth.size() * sizeof(float),
                                     depth.data());
    }
    if (config_.presizeLists)
      reserveList(cl_, tileLights_, capacity_,
                  tileListBound(grid_, frame, int(config_.spotCulling)));
    const uint32_t total = runUntilListFits(
        cl_, tileLights_, capacity_, total_,
        [&] {
          timer_.clear();
          enqueueGrid(frame);
        },
        "tile", result.counters.notes);
    cl_.queue().finish();
    result.kernels = timer_.kernels();

    // The grid to the host, then into OpenGL's buffers (inside tiledForward: uploadMs).
    const auto copyStart = Clock::now();
    ForwardLightGrid grid;
    grid.tileW = grid_.tileW;
    grid.tileH = grid_.tileH;
    grid.tilesX = grid_.tilesX;
    grid.tilesY = grid_.tilesY;
    grid.counts.resize(size_t(grid_.count()));
    grid.offsets.resize(size_t(grid_.count()));
    grid.lights.resize(std::max<uint32_t>(total, 1));
    auto& q = cl_.queue();
    q.enqueueReadBuffer(tileCount_, CL_TRUE, 0, grid.counts.size() * 4, grid.counts.data());
    q.enqueueReadBuffer(tileOffset_, CL_TRUE, 0, grid.offsets.size() * 4, grid.offsets.data());
    q.enqueueReadBuffer(tileLights_, CL_TRUE, 0, grid.lights.size() * 4, grid.lights.data());
    grid.lights.resize(total);
    const double readMs = msSince(copyStart);

    const ForwardImage drawn = frame.forward->tiledForward(*frame.lights, frame.ambient, features(),
                                                           int(config_.rangeModel), grid, prez_);
    if (prez_) result.kernels.push_back({"depth_prepass", prepassMs, 1});
    result.kernels.push_back({"grid_copy", readMs + drawn.uploadMs, 1});
    result.kernels.push_back({"forward", drawn.drawMs, 1});
    result.totalMs = 0.0;
    for (const KernelTime& k : result.kernels) result.totalMs += k.ms;
    result.image = drawn.image;
    result.counters.notes.push_back("forward pass: OpenGL timer query " +
                                    std::to_string(drawn.queryMs) + " ms, wall clock " +
                                    std::to_string(drawn.drawMs) + " ms (the row)");

    auto notes = std::move(result.counters.notes);
    result.counters = tileWorkCounters(grid_, grid.counts, frame);
    result.counters.notes = std::move(notes);
    // Forward shading's count is the fragment shader's own: invocations x lights evaluated
    // (overdrawn fragments included); evaluations are the same calls.
    result.counters.lightingComputations = drawn.lightingComputations;
    result.counters.evaluations = drawn.lightingComputations;
    result.counters.gbufferBytesRead = 0;  // no G-buffer
    if (request.wantAssignment)
      result.assignment = tileAssignment(grid_, grid.offsets, grid.counts, grid.lights);
    return result;
  }

 private:
  void allocate(const DeviceFrame& frame) {
    TileGrid grid(frame.width(), frame.height(), config_.tileWidth, config_.tileHeight);
    if (grid.tilesX == grid_.tilesX && grid.tilesY == grid_.tilesY && grid.width == grid_.width &&
        grid.height == grid_.height)
      return;
    grid_ = grid;
    const size_t tiles = size_t(grid_.count());
    auto& ctx = cl_.context();
    tileDepth_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, tiles * sizeof(cl_float4));
    tileCount_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, tiles * sizeof(uint32_t));
    tileOffset_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, tiles * sizeof(uint32_t));
    tileCursor_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, tiles * sizeof(uint32_t));
    total_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, sizeof(uint32_t));
    reserveList(cl_, tileLights_, capacity_, tiles * 8);
    if (prez_)
      prepassDepth_ =
          cl::Buffer(ctx, CL_MEM_READ_ONLY, size_t(frame.width()) * frame.height() * sizeof(float));
  }

  void enqueueGrid(DeviceFrame& frame) {
    auto& q = cl_.queue();
    const cl_float4 camera = toCl(frame.camera.kernelCamera());
    const size_t tiles = size_t(grid_.count());
    const uint32_t zero = 0;
    q.enqueueFillBuffer(tileCount_, zero, 0, tiles * 4, nullptr, timer_.next("clear"));
    q.enqueueFillBuffer(tileCursor_, zero, 0, tiles * 4, nullptr, timer_.next("clear"));
    if (prez_) {
      // As `tiled` launches it (tiled.cpp), on the pre-pass's depth.
      size_t group = powerOfTwoGroup(pow2AtLeast(size_t(grid_.tileW) * grid_.tileH, 64),
                                     groupLimit(cl_, depthBounds_));
      KernelArgs(depthBounds_)
          .add(prepassDepth_)
          .add(frame.width())
          .add(frame.height())
          .add(tileDepth_)
          .done();
      q.enqueueNDRangeKernel(depthBounds_, cl::NullRange, cl::NDRange(tiles * group),
                             cl::NDRange(group), nullptr, timer_.next("depth_bounds"));
    } else {
      // No depth range: the camera's [znear, zfar] in every tile, the second range empty.
      const cl_float4 whole = {{frame.camera.znear, frame.camera.zfar, FLT_MAX, 0.0f}};
      q.enqueueFillBuffer(tileDepth_, whole, 0, tiles * sizeof(cl_float4), nullptr,
                          timer_.next("clear"));
    }
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
  }

  ClContext& cl_;
  TechniqueConfig config_;
  bool prez_;
  cl::Program program_;
  cl::Kernel depthBounds_, binLights_, scan_, sort_;
  TileGrid grid_;
  cl::Buffer tileDepth_, tileCount_, tileOffset_, tileCursor_, total_, tileLights_, prepassDepth_;
  size_t capacity_ = 0;
  FrameTimer timer_;
};

}  // namespace

std::unique_ptr<Technique> makeTiledForwardTechnique(ClContext& cl, const TechniqueConfig& config,
                                                     bool prez) {
  return std::make_unique<TiledForwardTechnique>(cl, config, prez);
}

}  // namespace ts
