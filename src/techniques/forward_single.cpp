// Single-pass forward shading with a per-batch light list, the "minimal set of lights for each
// batch" Olsson & Assarsson contrast with their grid: the lights whose range sphere touches each
// draw batch's box, found on the host each frame (raster/batch_lights.h), uploaded into one
// shader storage buffer, and the scene drawn once, each batch's fragments looping over its list
// with kernels/shading.h (GLSL). No cap: a list is as long as its batch needs (an SSBO, not a
// uniform array), so no light is ever left out. OpenGL (`--raster gl`):
// GlRasterizer::singlePassForward, shaders/tiled_forward.frag.
#include "techniques/forward_batches.h"
#include "techniques/techniques.h"

namespace ts {
namespace {

class ForwardSingleTechnique : public Technique {
 public:
  explicit ForwardSingleTechnique(const TechniqueConfig& config) : config_(config) {}

  std::string name() const override { return "forward-single"; }

  FrameResult renderFrame(DeviceFrame& frame, const FrameRequest& request) override {
    ForwardScene& scene = sceneToDraw(frame, name());
    double listMs = 0.0;
    const IndexLists batchLights = findBatchLights(scene, *frame.lights, listMs);
    const ForwardImage drawn = scene.singlePassForward(*frame.lights, frame.ambient, features(),
                                                       int(config_.rangeModel), batchLights);
    FrameResult result;
    result.kernels = {
        {"batch_lists", listMs, 1}, {"upload", drawn.uploadMs, 1}, {"forward", drawn.drawMs, 1}};
    addShadowUploadRow(*frame.lights, drawn, result.kernels);
    if (drawn.transparentDraws > 0)  // --blend blend: back to front, each with its batch's list
      result.kernels.push_back({"transparent", drawn.transparentMs, int(drawn.transparentDraws)});
    for (const KernelTime& k : result.kernels) result.totalMs += k.ms;
    result.image = drawn.image;
    // Fragment shader invocations x (its batch's list + directional lights), overdrawn fragments
    // included: the shader's own atomic counters.
    result.counters.lightingComputations = drawn.lightingComputations;
    result.counters.evaluations = drawn.lightingComputations;
    setBatchListCounters(batchLights, result.counters);
    result.counters.notes.push_back(
        std::to_string(batchLights.size()) + " draw batches, longest list " +
        std::to_string(batchLights.longest()) + " lights (no cap); OpenGL timer query " +
        std::to_string(drawn.queryMs) + " ms (the row: wall clock)");
    if (request.wantAssignment) result.assignment = batchAssignment(batchLights, drawn);
    return result;
  }

 private:
  TechniqueConfig config_;
};

}  // namespace

std::unique_ptr<Technique> makeForwardSingleTechnique(ClContext&, const TechniqueConfig& config) {
  return std::make_unique<ForwardSingleTechnique>(config);
}

}  // namespace ts
