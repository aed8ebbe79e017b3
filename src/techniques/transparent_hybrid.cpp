#include "techniques/transparent_hybrid.h"

#include <chrono>

#include "techniques/forward_batches.h"

namespace ts {

bool hasTransparentDraws(const DeviceFrame& frame) {
  return frame.forward && frame.forward->transparentDraws() > 0;
}

void shadeTransparentOver(ClContext& cl, const cl::Buffer& opaqueImage, DeviceFrame& frame,
                          TileLightGrid& grid, const TechniqueConfig& config, FrameResult& result) {
  KernelTime gridRow;
  double gridReadMs = 0.0;
  const ForwardLightGrid glass =
      grid.binForTransparency(frame, result.counters.notes, gridRow, gridReadMs);

  // PoCL and llvmpipe share nothing: the image goes through the host (its read is the copy's).
  const auto t0 = std::chrono::steady_clock::now();
  const std::vector<glm::vec4> opaque = readImage(cl, opaqueImage, frame);
  const double imageReadMs =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  ForwardImage drawn = frame.forward->transparentOver(
      opaque, *frame.lights, frame.ambient, config.features, int(config.rangeModel), glass);

  result.kernels.push_back(gridRow);
  result.kernels.push_back({"grid_copy", gridReadMs + drawn.uploadMs, 1});
  result.kernels.push_back({"image_copy", imageReadMs + drawn.imageCopyMs, 1});
  addShadowUploadRow(*frame.lights, drawn, result.kernels);
  result.kernels.push_back({"transparent", drawn.transparentMs, int(drawn.transparentDraws)});
  result.totalMs = 0.0;
  for (const KernelTime& k : result.kernels) result.totalMs += k.ms;
  result.image = std::move(drawn.image);
  // The glass shaded the re-binned lists, not the opaque pixels' (LightAssignment::transparent).
  if (result.assignment) result.assignment->transparent = gridFragmentLists(glass);
  // The fragment shader's own count (fragments x list + directional), as the forward techniques'.
  result.counters.lightingComputations += drawn.lightingComputations;
  result.counters.evaluations += drawn.lightingComputations;
  if (drawn.depthRedrawn)
    result.counters.notes.push_back(
        "transparent pass: the opaque depth drawn again (the G-buffer pass last drawn was "
        "another frame's)");
}

}  // namespace ts
