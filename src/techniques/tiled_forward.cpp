// Tiled forward shading (Olsson & Assarsson 2011, TiledFwd and TiledFwd-PreZ): the light grid of
// `tiled`, built by the same OpenCL kernels (kernels/tiled.cl), read by a fragment shader that
// draws the scene (raster/forward_scene.h; OpenGL, shaders/tiled_forward.frag).
//   tiled-forward       no depth range: every tile gets the camera's whole [znear, zfar] instead
//                       of tile_depth_bounds' output, so a light is binned by its screen rectangle
//                       only (the paper's TiledFwd); the scene drawn once with the depth test.
//   tiled-forward-prez  a depth-only pre-pass, its linear depth through tile_depth_bounds as in
//                       `tiled`, then the forward pass with the depth test EQUAL (TiledFwd-PreZ).
// Transparent draws (--blend blend) follow the opaque pass, back to front, blended: tiled-forward
// draws them with its grid (no depth range culls nothing in front); tiled-forward-prez bins the
// lights a second time for them, each tile's range [znear, the opaque far bound] (Olsson &
// Assarsson Section 4: only the far bound may cull a transparent fragment), row
// transparent_grid.
// The grid is copied through the host (PoCL and llvmpipe share nothing): its own row, grid_copy,
// in the per-kernel table, as are the OpenGL passes (timer queries): depth_prepass, forward.
#include <chrono>
#include <optional>

#include "techniques/forward_batches.h"
#include "techniques/techniques.h"
#include "techniques/tile_light_grid.h"
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
      : cl_(cl), config_(config), prez_(prez), program_(build(cl, config)), grid_(cl, program_) {}

  std::string name() const override { return prez_ ? "tiled-forward-prez" : "tiled-forward"; }

  FrameResult renderFrame(DeviceFrame& frame, const FrameRequest& request) override {
    ForwardScene& scene = sceneToDraw(frame, name());
    allocate(frame);
    FrameResult result;
    double prepassMs = 0.0;
    if (prez_) {
      // With --msaa a plane per sample: the tiles' ranges must cover every sample's depth.
      const std::vector<float> depth = scene.depthPrepass(prepassMs);
      samples_ = scene.samples();
      if (prepassDepth_.getInfo<CL_MEM_SIZE>() < depth.size() * sizeof(float))
        prepassDepth_ = cl::Buffer(cl_.context(), CL_MEM_READ_ONLY, depth.size() * sizeof(float));
      cl_.queue().enqueueWriteBuffer(prepassDepth_, CL_TRUE, 0, depth.size() * sizeof(float),
                                     depth.data());
    }
    if (config_.presizeLists) grid_.presize(frame, int(config_.spotCulling));
    const uint32_t total = grid_.runUntilListFits(
        [&] {
          timer_.clear();
          enqueueGrid(frame);
        },
        result.counters.notes);
    cl_.queue().finish();
    result.kernels = timer_.kernels();

    // The grid to the host, then into OpenGL's buffers (inside tiledForward: uploadMs).
    auto copyStart = Clock::now();
    const TileGrid& tiles = grid_.grid();
    const ForwardLightGrid grid = grid_.toHost(total);
    double readMs = msSince(copyStart);

    std::optional<ForwardLightGrid> transparentGrid;
    if (prez_ && scene.transparentDraws() > 0) {
      KernelTime row;
      double glassReadMs = 0.0;
      transparentGrid = grid_.binForTransparency(frame, result.counters.notes, row, glassReadMs);
      result.kernels.push_back(row);
      readMs += glassReadMs;
    }

    const ForwardImage drawn =
        scene.tiledForward(*frame.lights, frame.ambient, features(), int(config_.rangeModel), grid,
                           prez_, transparentGrid ? &*transparentGrid : nullptr);
    if (prez_) result.kernels.push_back({"depth_prepass", prepassMs, 1});
    addGridForwardPass(*frame.lights, drawn, readMs, result);
    result.counters.notes.push_back("forward pass: OpenGL timer query " +
                                    std::to_string(drawn.queryMs) + " ms, wall clock " +
                                    std::to_string(drawn.drawMs) + " ms (the row)");

    auto notes = std::move(result.counters.notes);
    result.counters = tileWorkCounters(tiles, grid.counts, frame);
    result.counters.notes = std::move(notes);
    // Forward shading's count is the fragment shader's own: invocations x lights evaluated
    // (overdrawn fragments included); evaluations are the same calls.
    result.counters.lightingComputations = drawn.lightingComputations;
    result.counters.evaluations = drawn.lightingComputations;
    result.counters.gbufferBytesRead = 0;  // no G-buffer
    if (request.wantAssignment) {
      result.assignment = tileAssignment(tiles, grid.offsets, grid.counts, grid.lights);
      // The glass shaded the transparent grid's lists where there is one, else the opaque's.
      if (drawn.transparentDraws > 0)
        result.assignment->transparent =
            gridFragmentLists(transparentGrid ? *transparentGrid : grid);
    }
    return result;
  }

 private:
  static cl::Program build(ClContext& cl, const TechniqueConfig& config) {
    if (config.tileWidth < 1 || config.tileHeight < 1) throw Error("tile size must be positive");
    // The binning kernels of `tiled`, built as tiled builds them (its shading kernel is unused).
    std::string options = config.kernelOptions() + " -DTILE_W=" + std::to_string(config.tileWidth) +
                          " -DTILE_H=" + std::to_string(config.tileHeight);
    return cl.build("tiled.cl", options);
  }

  void allocate(const DeviceFrame& frame) {
    if (grid_.allocate(frame.width(), frame.height(), config_.tileWidth, config_.tileHeight) &&
        prez_)
      prepassDepth_ = cl::Buffer(cl_.context(), CL_MEM_READ_ONLY,
                                 size_t(frame.width()) * frame.height() * sizeof(float));
  }

  void enqueueGrid(DeviceFrame& frame) {
    grid_.enqueueClear(timer_);
    if (prez_)  // as `tiled` bounds its G-buffer's depth, on the pre-pass's
      grid_.enqueueDepthBounds(prepassDepth_, frame.width(), frame.height(), timer_, samples_);
    else  // no depth range: a light is binned by its screen rectangle only
      grid_.enqueueWholeDepthRange(frame.camera.znear, frame.camera.zfar, timer_);
    grid_.enqueueBinning(frame, timer_);
  }

  ClContext& cl_;
  TechniqueConfig config_;
  bool prez_;
  cl::Program program_;
  TileLightGrid grid_;
  cl::Buffer prepassDepth_;
  int samples_ = 1;  // planes in prepassDepth_ (--msaa)
  FrameTimer timer_;
};

}  // namespace

std::unique_ptr<Technique> makeTiledForwardTechnique(ClContext& cl, const TechniqueConfig& config,
                                                     bool prez) {
  return std::make_unique<TiledForwardTechnique>(cl, config, prez);
}

}  // namespace ts
