// Traditional multi-pass forward shading, as the thesis implements it (and the forward baseline
// of every source the project follows): a base pass of the whole scene (ambient, emission,
// directional lights), then for each point or spot light one additive pass (blend ONE, ONE)
// that draws only the draw batches its range sphere touches, with the depth test EQUAL against
// the base pass's depth, each fragment shading that one light with kernels/shading.h (GLSL).
// The light-to-batch lists are found on the host each frame (raster/batch_lights.h). OpenGL
// (`--raster gl`): GlRasterizer::multiPassForward, shaders/tiled_forward.frag.
#include <chrono>

#include "techniques/forward_batches.h"
#include "techniques/techniques.h"

namespace ts {
namespace {

class ForwardTechnique : public Technique {
 public:
  explicit ForwardTechnique(const TechniqueConfig& config) : config_(config) {}

  std::string name() const override { return "forward"; }

  FrameResult renderFrame(DeviceFrame& frame, const FrameRequest& request) override {
    ForwardScene& scene = sceneToDraw(frame, name());
    double listMs = 0.0;
    const IndexLists batchLights = findBatchLights(scene, *frame.lights, listMs);
    // The same pairs per light: what each light's pass draws (host time, the same row).
    const auto t0 = std::chrono::steady_clock::now();
    const IndexLists lightBatches = transposeLists(batchLights, frame.lights->size());
    listMs +=
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();

    const ForwardImage drawn = scene.multiPassForward(*frame.lights, frame.ambient, features(),
                                                      int(config_.rangeModel), lightBatches);
    FrameResult result;
    result.kernels = {{"batch_lists", listMs, 1},
                      {"upload", drawn.uploadMs, 1},
                      {"base", drawn.baseMs, 1},
                      {"light_passes", drawn.drawMs, int(drawn.passes)}};
    addShadowUploadRow(*frame.lights, drawn, result.kernels);
    if (drawn.transparentDraws > 0)  // --blend blend: back to front, each with its batch's list
      result.kernels.push_back({"transparent", drawn.transparentMs, int(drawn.transparentDraws)});
    for (const KernelTime& k : result.kernels) result.totalMs += k.ms;
    result.image = drawn.image;
    // The paper's count: fragment shader invocations x lights evaluated, from the shader's own
    // atomic counters (the base pass's fragments x directional lights, each light pass's x 1).
    result.counters.lightingComputations = drawn.lightingComputations;
    result.counters.evaluations = drawn.lightingComputations;
    setBatchListCounters(batchLights, result.counters);
    result.counters.notes.push_back(
        std::to_string(drawn.passes) + " light passes, " + std::to_string(drawn.draws) +
        " draw calls over " + std::to_string(batchLights.size()) +
        " draw batches; OpenGL timer queries: base " + std::to_string(drawn.baseQueryMs) +
        " ms, light passes " + std::to_string(drawn.queryMs) + " ms (the rows: wall clock)");
    if (request.wantAssignment) result.assignment = batchAssignment(batchLights, drawn);
    return result;
  }

 private:
  TechniqueConfig config_;
};

}  // namespace

std::unique_ptr<Technique> makeForwardTechnique(ClContext&, const TechniqueConfig& config) {
  return std::make_unique<ForwardTechnique>(config);
}

}  // namespace ts
