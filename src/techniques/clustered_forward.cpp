// Clustered forward shading (Olsson, Billeter & Assarsson 2012, its forward form): `clustered`'s
// grid of tiles x exponential depth slices, binned by the same OpenCL kernel (bin_clusters,
// kernels/clustered.cl), copied to OpenGL through the host (row grid_copy, as tiled-forward's),
// and the scene drawn once in OpenGL (shaders/tiled_forward.frag): each fragment finds its
// cluster from its own view depth and shades that cluster's list with kernels/shading.h.
//
// The slices' depth range: forward has no G-buffer, and no depth pre-pass here, so the slices
// span the view-space depth bounds of the scene's draw batches at this camera (their boxes,
// ForwardScene::batchBoxes, clipped to [znear, zfar]) rather than the frame's geometry depth as
// `clustered` has it. Every fragment, opaque or transparent, lies inside those bounds, so a glass
// fragment in front of the opaque surface still finds its own cluster: no far bound of the opaque
// depth is needed (the reason the paper gives for clusters and transparency). For the same
// reason a cluster's depth range is its whole slice, not the depths of the geometry in it (which
// only a pre-pass could give, and which would leave out the glass): binning tests each light
// against every cluster of its tile rectangle and slice range. The slice's bounds are widened by
// kSliceSlack so that the rounding of log in GLSL (which picks a fragment's slice) never puts a
// fragment in a cluster whose bounds exclude it; the lists are thus exact (conservative) for
// every fragment drawn.
//
// Counters: lighting computations and evaluations are the fragment shader's own count
// (invocations x lights evaluated, overdrawn and transparent fragments included), as for the
// other forward techniques; list statistics over all clusters (each may receive fragments).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>

#include "techniques/cluster_light_grid.h"
#include "techniques/forward_batches.h"
#include "techniques/tile_grid.h"
#include "techniques/techniques.h"
#include "util/error.h"
#include "util/option_values.h"

namespace ts {
namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// Relative widening of each slice's depth bounds: GLSL's log (a few ulps) and the kernels' differ
// by far less than 1e-3 in log units, so the fragment's slice always contains its depth.
constexpr double kSliceSlack = 1e-3;

// The slicing of one frame: slices from zn to zf (view depth), scale = slices / log(zf / zn).
struct Slicing {
  float zn = 1.0f, zf = 1.0f, scale = 0.0f;
  int slice(float z, int slices) const {  // as kernels/clustered.cl and the fragment shader
    return int(std::clamp(std::log(z / zn) * scale, 0.0f, float(slices - 1)));
  }
};

// The scene's depth bounds at this camera: the union of the batches' view boxes (the camera looks
// down -z), clipped to the camera's range. An empty or flat range gives scale 0 (one slice used).
Slicing sceneSlicing(const std::vector<ViewBox>& boxes, float znear, float zfar, int slices) {
  float nearest = zfar, farthest = znear;
  for (const ViewBox& b : boxes) {
    nearest = std::min(nearest, -b.max.z);
    farthest = std::max(farthest, -b.min.z);
  }
  Slicing s;
  s.zn = std::clamp(nearest, znear, zfar);
  s.zf = std::clamp(farthest, s.zn, zfar);
  s.scale = s.zf > s.zn ? float(slices) / std::log(s.zf / s.zn) : 0.0f;
  return s;
}

class ClusteredForwardTechnique : public Technique {
 public:
  ClusteredForwardTechnique(ClContext& cl, const TechniqueConfig& config)
      : cl_(cl),
        config_(config),
        program_(build(cl, config)),
        grid_(cl, program_, config.clusterSlices, "clustered-forward") {}

  std::string name() const override { return "clustered-forward"; }

  FrameResult renderFrame(DeviceFrame& frame, const FrameRequest& request) override {
    ForwardScene& scene = sceneToDraw(frame, name());
    allocate(frame);
    FrameResult result;
    const int slices = config_.clusterSlices;

    // Host: the scene's depth bounds and every cluster's slice bounds, written to the device.
    auto boundsStart = Clock::now();
    const Slicing slicing =
        sceneSlicing(scene.batchBoxes(), frame.camera.znear, frame.camera.zfar, slices);
    writeSliceBounds(slicing);
    const double boundsMs = msSince(boundsStart);

    if (config_.presizeLists) grid_.presize(frame, int(config_.spotCulling));
    const uint32_t total = grid_.runUntilListFits(
        [&] {
          timer_.clear();
          grid_.enqueueClear(timer_);
          grid_.enqueueBinning(frame, timer_);
        },
        result.counters.notes);
    cl_.queue().finish();
    result.kernels = timer_.kernels();
    result.kernels.insert(result.kernels.begin(), {"slice_bounds", boundsMs, 1});

    auto copyStart = Clock::now();
    const ForwardLightGrid grid = toHost(total, slicing);
    const double readMs = msSince(copyStart);

    const ForwardImage drawn = scene.tiledForward(*frame.lights, frame.ambient, features(),
                                                  int(config_.rangeModel), grid, false, nullptr);
    addGridForwardPass(*frame.lights, drawn, readMs, result);
    result.counters.notes.push_back("slices span the scene's view depth " +
                                    std::to_string(slicing.zn) + ".." + std::to_string(slicing.zf) +
                                    "; forward pass: OpenGL timer query " +
                                    std::to_string(drawn.queryMs) + " ms, wall clock " +
                                    std::to_string(drawn.drawMs) + " ms (the row)");
    setCounters(result.counters, grid, drawn, frame);
    if (request.wantAssignment) {
      result.assignment = assignment(grid, slicing, frame);
      // Glass fragments find the cluster of their own depth in the same grid.
      if (drawn.transparentDraws > 0) result.assignment->transparent = gridFragmentLists(grid);
    }
    return result;
  }

 private:
  static cl::Program build(ClContext& cl, const TechniqueConfig& config) {
    if (config.tileWidth < 1 || config.tileHeight < 1) throw Error("tile size must be positive");
    if (config.clusterSlices < 1 || config.clusterSlices > kMaxClusterSlices)
      throw Error("cluster slices must be 1.." + std::to_string(kMaxClusterSlices) + ", got " +
                  std::to_string(config.clusterSlices));
    // clustered.cl as `clustered` builds it (its binning kernels only; shading happens in GL).
    std::string options = config.kernelOptions() + " -DTILE_W=" + std::to_string(config.tileWidth) +
                          " -DTILE_H=" + std::to_string(config.tileHeight) +
                          " -DSLICES=" + std::to_string(config.clusterSlices);
    return cl.build("clustered.cl", options);
  }

  void allocate(const DeviceFrame& frame) {
    if (!grid_.allocate(frame.width(), frame.height(), config_.tileWidth, config_.tileHeight))
      return;
    // Every tile holds all its slices (any of them may receive a fragment).
    const int slices = config_.clusterSlices;
    const std::vector<cl_int2> all(size_t(grid_.tiles().count()), cl_int2{{0, slices - 1}});
    cl_.queue().enqueueWriteBuffer(grid_.tileSlices(), CL_TRUE, 0, all.size() * sizeof(cl_int2),
                                   all.data());
  }

  // Cluster c = tile * slices + k spans slice k's depths, widened by kSliceSlack; the kernels'
  // (zn, zf) is the slicing's range, so bin_clusters slices a light's depth extent the same way.
  void writeSliceBounds(const Slicing& s) {
    const int slices = config_.clusterSlices;
    std::vector<cl_float2> one(static_cast<size_t>(slices));
    for (int k = 0; k < slices; ++k) {
      double lo = s.scale > 0.0f ? double(s.zn) * std::exp(double(k) / s.scale) : s.zn;
      double hi = s.scale > 0.0f ? double(s.zn) * std::exp(double(k + 1) / s.scale) : s.zf;
      if (k == 0) lo = s.zn;
      if (k == slices - 1) hi = s.zf;
      one[size_t(k)] = {{float(lo * (1.0 - kSliceSlack)), float(hi * (1.0 + kSliceSlack))}};
    }
    sliceBounds_.resize(grid_.clusterCount());
    for (size_t c = 0; c < sliceBounds_.size(); ++c) sliceBounds_[c] = one[c % size_t(slices)];
    auto& q = cl_.queue();
    q.enqueueWriteBuffer(grid_.clusterDepth(), CL_FALSE, 0, sliceBounds_.size() * sizeof(cl_float2),
                         sliceBounds_.data());
    // As float bits (the kernels' depth_range), not widened: bin_clusters slices a light's depth
    // extent with them, which must be the shader's slicing (zn, scale); its own slack covers the
    // rounding. The boxes already hold every fragment (raster/draw_batches.h), so clipping a
    // light's extent to [zn, zf] drops none that reaches one.
    sliceRange_ = {{0u, 0u}};
    std::memcpy(&sliceRange_.s[0], &s.zn, 4);
    std::memcpy(&sliceRange_.s[1], &s.zf, 4);
    q.enqueueWriteBuffer(grid_.depthRange(), CL_TRUE, 0, sizeof(cl_uint2), &sliceRange_);
  }

  ForwardLightGrid toHost(uint32_t total, const Slicing& s) const {
    ForwardLightGrid g;
    const TileGrid& tiles = grid_.tiles();
    g.tileW = tiles.tileW;
    g.tileH = tiles.tileH;
    g.tilesX = tiles.tilesX;
    g.tilesY = tiles.tilesY;
    g.slices = config_.clusterSlices;
    g.sliceNear = s.zn;
    g.sliceScale = s.scale;
    g.counts = grid_.readCounts();
    g.offsets = grid_.readOffsets();
    g.lights = grid_.readLights(total);
    return g;
  }

  void setCounters(WorkCounters& c, const ForwardLightGrid& grid, const ForwardImage& drawn,
                   const DeviceFrame& frame) const {
    // Forward shading's count is the fragment shader's own (see the file's comment).
    c.lightingComputations = drawn.lightingComputations;
    c.evaluations = drawn.lightingComputations;
    c.gbufferBytesRead = 0;  // no G-buffer
    c.listMin = grid.counts.empty() ? 0 : UINT32_MAX;
    double sum = 0.0;
    for (uint32_t n : grid.counts) {
      c.listMin = std::min(c.listMin, n);
      c.listMax = std::max(c.listMax, n);
      sum += n;
    }
    c.listMean = grid.counts.empty() ? 0.0 : sum / double(grid.counts.size());
    (void)frame;
  }

  // Each pixel's opaque surface in the cluster of its depth (the frame's G-buffer from the same
  // rasterization, sliced as the shader slices its fragment's depth), for the missed count.
  LightAssignment assignment(const ForwardLightGrid& grid, const Slicing& s,
                             const DeviceFrame& frame) const {
    LightAssignment a;
    a.binOffset = grid.offsets;
    a.binCount = grid.counts;
    a.binLights = grid.lights;
    const auto& depth = frame.gbuffer->depth;
    a.pixelBin.resize(size_t(frame.width()) * frame.height());
    for (int y = 0; y < frame.height(); ++y)
      for (int x = 0; x < frame.width(); ++x) {
        const size_t i = size_t(y) * frame.width() + x;
        a.pixelBin[i] =
            depth[i] > 0.0f
                ? int32_t(grid_.tiles().tileOf(x, y) * grid.slices + s.slice(depth[i], grid.slices))
                : -1;
      }
    return a;
  }

  ClContext& cl_;
  TechniqueConfig config_;
  cl::Program program_;
  ClusterLightGrid grid_;
  std::vector<cl_float2> sliceBounds_;  // host copy kept alive for the non-blocking write
  cl_uint2 sliceRange_{};
  FrameTimer timer_;
};

}  // namespace

std::unique_ptr<Technique> makeClusteredForwardTechnique(ClContext& cl,
                                                         const TechniqueConfig& config) {
  return std::make_unique<ClusteredForwardTechnique>(cl, config);
}

}  // namespace ts
