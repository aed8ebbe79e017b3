#pragma once
// What stands behind the public handles of tileshade.h: a Device is a ClContext, a Frame a
// PreparedFrame on that device (plus its cached references). Only the API's own files and the
// command-line code above it (src/cli/) include this; engines see tileshade.h alone.
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "raster/sample_gbuffers.h"
#include "reference/reference.h"
#include "render/frame_setup.h"
#include "render/render_input.h"
#include "shading/transparent_fragments.h"
#include "techniques/device_frame.h"
#include "tileshade/tileshade.h"
#include "util/error.h"

namespace ts {

// tileshade.h promises ts::Error for every failure: an OpenCL error inside the API becomes one,
// with the OpenCL C++ bindings' text and the error code.
template <typename F>
auto openclErrorsAsTs(F&& f) -> decltype(f()) {
  try {
    return f();
  } catch (const cl::Error& e) {
    throw Error(std::string("OpenCL error: ") + e.what() + " (" + std::to_string(e.err()) + ")");
  }
}

struct Device::Impl {
  explicit Impl(const std::string& spec) : cl(spec) {}
  Impl(cl_context context, cl_device_id device, cl_command_queue queue)
      : cl(context, device, queue), own(true) {}
  ClContext cl;
  bool own = false;  // the caller's context (Device::fromOpenCL): cl_mem frames allowed
};

// The row progress of one reference pass called `label` (the command's progress bar).
using PassProgress = std::function<RowProgress(const std::string& label)>;

// The double-precision references of a frame (render --check's three; docs/accuracy.md).
struct FrameReferences {
  ReferenceImage reference;    // windowed model, positions from depth in double
  ReferenceImage shadingOnly;  // the same with the kernels' float positions
  ReferenceImage physical;     // physical model from the fp32 planes
  // --blend blend: the transparent fragments composited over all three
  // (reference/transparent_composite.h), as the forward and hybrid techniques blend them; 0
  // otherwise.
  size_t transparentFragments = 0;
  // The fragments themselves: the transparent `missed` tests each against the list its
  // technique shaded it with (reference/transparent_missed.h).
  std::vector<TransparentFragment> fragments;
};

struct Frame::Impl {
  std::shared_ptr<Device::Impl> device;
  PreparedFrame prepared;  // host copy; for device planes, only depth until readHostPlanes()
  DeviceFrame onDevice;    // points into `prepared` (an Impl never moves: it is shared)
  FrameInfo info;
  std::optional<DeviceGBuffer> devicePlanes;  // Frame::fromDevice: the caller's buffers
  bool hostPlanesComplete = true;
  std::optional<FrameReferences> references;  // computed at the first check
  // A technique that draws the scene (forward) reads no G-buffer, so the frame's layout does not
  // quantize its surfaces: its references are those of the rasterization's fp32 planes. Computed
  // at its first check, and only for a frame whose layout is not fp32 (else `references`).
  std::optional<FrameReferences> drawnReferences;
  std::optional<EncodedGBuffer> fp32Planes;  // the fp32 encoding behind drawnReferences
  // Frame::fromScene: the scene and its rasterizer, kept alive for the techniques that draw it
  // (onDevice.forward; null unless rasterized with --raster gl).
  std::unique_ptr<Scene> scene;
  std::unique_ptr<SceneRasterizer> rasterizer;
  std::unique_ptr<ForwardScene> forward;
  std::shared_ptr<const ShadowAtlas> shadowAtlas;  // Frame::fromScene with shadow casters
  // Its maps one light at a time, for per-light shadow storage (onDevice.perLightShadows).
  std::unique_ptr<PerLightShadowMaps> perLightShadows;

  // Frame::fromDevice: reads the caller's planes back (for the reference and for dump).
  void readHostPlanes();
  // Computed at the first call (seconds to minutes for big frames), then cached; `pass` gives
  // each of the three passes its row progress (empty: none).
  const FrameReferences& ensureReferences(const PassProgress& pass = {}, bool drawsScene = false);
  // The planes a technique shades: the frame's layout, or its fp32 encoding for one that draws
  // the scene (the reference and the missed-contribution count use the same ones).
  const EncodedGBuffer& planesShadedBy(bool drawsScene);
  // The transparent surfaces over the three references (none without transparent draws), the
  // fragments shaded with the planes' terms of planesShadedBy(drawsScene).
  void compositeTransparentSurfaces(FrameReferences& r, bool drawsScene);

  // --msaa: a frame whose forward passes draw multisampled targets. Its references shade every
  // sample's G-buffer and average them (averageSamples): for the techniques that draw the scene
  // each sample's fp32 encoding (with every plane), for tiled each sample in the frame's layout
  // (the planes it shades); made at the first check.
  bool multisampled() const { return forward && forward->samples() > 1; }
  const std::vector<EncodedGBuffer>& samplePlanes(bool drawsScene);
  const FrameReferences& ensureSampleReferences(const PassProgress& pass, bool drawsScene);
  std::optional<FrameReferences> drawnSampleReferences, gbufferSampleReferences;
  std::unique_ptr<SampleGBuffers> sampleGBuffers;  // --msaa: made with `forward`
};

// The frame's references (computed now if no check asked for them yet): the command's heatmap.
// drawsScene: those of a technique that draws the scene (TechniqueDescription::drawsScene).
const FrameReferences& frameReferences(const Frame& frame, const PassProgress& pass = {},
                                       bool drawsScene = false);
// `render --gbuffer-in --features`: the features an imported frame's kernels model, instead of
// its files' own (chooseFeatures). Throws ts::Error on a bad spec.
void overrideFrameFeatures(Frame& frame, const std::string& features);

}  // namespace ts
