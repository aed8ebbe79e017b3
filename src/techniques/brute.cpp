// Brute force: every light for every pixel (kernels/brute.cl). The yardstick the culling
// techniques are measured against; its light "list" is all lights for every pixel.
#include <numeric>

#include "cl/kernel_args.h"
#include "cl/work_group.h"
#include "techniques/tile_grid.h"
#include "techniques/techniques.h"

namespace ts {
namespace {

class BruteTechnique : public Technique {
 public:
  BruteTechnique(ClContext& cl, const TechniqueConfig& config)
      : cl_(cl), config_(config), lanes_(config.lanes) {
    program_ = cl.build("brute.cl", config.kernelOptions() + config.lanesOption());
    kernel_ = cl::Kernel(program_, "shade_brute");
  }

  std::string name() const override { return "brute"; }
  int lanes() const override { return lanes_; }

  FrameResult renderFrame(DeviceFrame& frame, const FrameRequest& request) override {
    size_t pixels = size_t(frame.width()) * frame.height();
    if (imageBytes_ != pixels * sizeof(cl_float4)) {
      imageBytes_ = pixels * sizeof(cl_float4);
      image_ = cl::Buffer(cl_.context(), CL_MEM_WRITE_ONLY, imageBytes_);
    }
    timer_.clear();
    KernelArgs args(kernel_);
    args.add(toCl(frame.camera.kernelCamera()))
        .add(toCl(glm::vec4(frame.ambient, 0.0f)))
        .add(frame.gbufferArgs())
        .add(frame.lightArgs())
        .addIf(config_.features.shadows, frame.lightShadowArgs())
        .add(frame.lightCount())
        .add(frame.directionalArgs())
        .addIf(config_.features.shadows, frame.directionalShadowArgs())
        .add(image_);
    GroupShape g = fitGroup(16, 16, groupLimit(cl_, kernel_));
    if (lanes_ > 1) args.add(laneLocalMemory(config_, g.size()));
    args.done();
    cl_.queue().enqueueNDRangeKernel(kernel_, cl::NullRange,
                                     g.global(frame.width(), frame.height()), g.local(), nullptr,
                                     timer_.next("shade"));
    cl_.queue().finish();

    FrameResult result;
    result.kernels = timer_.kernels();
    result.totalMs = timer_.totalMs();
    result.image = readImage(cl_, image_, frame);
    // One bin (the whole screen) listing every light: the tile counters with a screen-sized tile.
    TileGrid screen(frame.width(), frame.height(), frame.width(), frame.height());
    std::vector<uint32_t> counts{uint32_t(frame.lightCount())};
    result.counters = tileWorkCounters(screen, counts, frame);
    // Depth is read once here (tileWorkCounters assumes a separate depth pass reading it twice).
    result.counters.gbufferBytesRead -= 4 * pixels;
    if (request.wantAssignment) {
      std::vector<uint32_t> all(frame.lightCount());
      std::iota(all.begin(), all.end(), 0u);
      result.assignment = tileAssignment(screen, {0}, counts, all);
    }
    return result;
  }

 private:
  ClContext& cl_;
  TechniqueConfig config_;
  int lanes_;
  cl::Program program_;
  cl::Kernel kernel_;
  cl::Buffer image_;
  size_t imageBytes_ = 0;
  FrameTimer timer_;
};

}  // namespace

std::unique_ptr<Technique> makeBruteTechnique(ClContext& cl, const TechniqueConfig& config) {
  return std::make_unique<BruteTechnique>(cl, config);
}

}  // namespace ts
