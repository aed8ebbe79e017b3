#pragma once
// One measurement of `bench` (bench_run.h runs them): a configuration timed on one frame of its
// group, its error against the references where --error wants it, and the bench.json row of
// both (bench_columns.h makes the bench.csv line of the row).
#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/bench_config.h"
#include "bench/bench_frames.h"
#include "bench/calibrate.h"
#include "cl/cl_context.h"
#include "raster/sample_gbuffers.h"
#include "reference/error_metrics.h"
#include "reference/reference.h"
#include "techniques/technique.h"
#include "visibility/shadow_error.h"

namespace ts {

// One configuration of a run and its state across the frames it times.
struct BenchEntry {
  size_t index = 0;  // in the expanded sweep
  BenchConfig config;
  std::vector<int> frames;  // timed frames
  std::set<int> pending;    // not in the output yet
  std::set<int> errorFrames;
  std::set<int> shadowErrorFrames;  // --shadow-error's
  std::unique_ptr<Technique> technique;
  ClContext* cl = nullptr;
  const Calibration* calibration = nullptr;
  std::string deviceName;
  double compileMs = 0.0;
  SceneFeatures features;     // what its kernels and layout model (BenchScene::features)
  std::string kernelOptions;  // its kernels' build options
  bool warmed = false, failed = false;
};

// One frame of a group of configurations sharing it (scene, lights, resolution), rasterized once,
// and what its configurations derive from it, each made once when first needed: the G-buffer in
// each layout and the error references.
class GroupFrame {
 public:
  // Prepares frame `frame` of `scene` for the group's first configuration (out of memory: a
  // ts::Error naming the frame).
  GroupFrame(BenchScene& scene, const BenchConfig& group, int frame);

  const PreparedFrame& prepared() const { return prepared_; }
  // The scene to draw for the forward techniques (null where the frame is not OpenGL's).
  ForwardScene* forward() const { return forward_.get(); }
  // --msaa: the frame's G-buffer per sample (made at the first call), null without MSAA.
  SampleGBuffers* sampleGBuffers();
  // Its shadow maps (BenchScene::drawShadows), null without a shadow-casting light.
  const ShadowAtlas* shadows() const { return shadows_.get(); }
  // The same maps one light at a time, for per-light shadow storage (made at the first call);
  // null without a shadow-casting light.
  const PerLightShadowMaps* perLightShadows();
  size_t pixels() const { return pixels_; }
  uint64_t geometryPixels() const { return geometry_; }

  // A configuration's layout (precision x features).
  const EncodedGBuffer& encoded(GBufferFormat format, const SceneFeatures& features);
  // The stored values' reference (the features' planes do not change it): with the positions
  // rebuilt in double, or with the kernels' float positions (the shading arithmetic alone).
  const ReferenceImage& storedReference(const EncodedGBuffer& enc, GBufferFormat format, int model,
                                        ReferencePositions positions);
  // The error reference of every configuration of this frame: the windowed model in double from
  // the fp32 G-buffer and the scene's own light ranges, so storage precision, light ranges,
  // arithmetic and culling all show in err_* (error_vs_stored isolates the last two).
  const ReferenceImage& sceneReference();
  // The frame's maps against exact visibility (measured at the first call; shared by the group's
  // configurations, whose maps and sampling are the group's), null without a shadow-casting
  // light.
  const ExactVisibilityResult* exactShadows();

 private:
  // The rounding box of a receiver's position (a forward fragment's, a kernel's float
  // reconstruction): the references give the shadow tests' slack over it.
  std::optional<ReceiverRounding> receiverRounding() const;
  // The frame's transparent fragments (captured once) composited over `ref` where the frame has
  // transparent draws (--blend blend); nothing otherwise.
  void withTransparentSurfaces(ReferenceImage& ref, const ViewLights& lights, int model);
  // The reference of `enc`'s values, or where the forward passes draw multisampled targets
  // (--msaa) every sample's G-buffer in enc's layout shaded and averaged (averageSamples).
  ReferenceImage shadeFrame(const EncodedGBuffer& enc, const ViewLights& lights, int model,
                            ReferencePositions positions);

  BenchScene& scene_;
  PreparedFrame prepared_;
  std::shared_ptr<const ShadowAtlas> shadows_;
  std::unique_ptr<PerLightShadowMaps> perLightShadows_;
  std::unique_ptr<ForwardScene> forward_;
  size_t pixels_;
  uint64_t geometry_;
  std::map<std::pair<GBufferFormat, std::string>, EncodedGBuffer> layouts_;
  std::map<std::pair<int, int>, ReferenceImage> references_, shadingReferences_;
  std::optional<ReferenceImage> sceneReference_;
  std::optional<std::optional<ExactVisibilityResult>> exactShadows_;
  std::optional<std::vector<TransparentFragment>> transparentFragments_;
  std::unique_ptr<SampleGBuffers> samples_;  // --msaa: each sample's planes, made at first use
};

// The median of a configuration's timed renders of one frame.
struct TimedFrame {
  FrameResult r;
  double wallMs, uploadMs;
};

// Renders `repeat` times after the configuration's `warmup` untimed renders (before its first
// frame only); keeps the median by kernel time (the lower middle one for an even count).
// forward: the frame's scene to draw (GroupFrame::forward), null for a G-buffer-only frame.
// perLight: the frame's maps one light at a time (GroupFrame::perLightShadows), for a
// configuration with per-light shadow storage; else null.
// samples: --msaa's per-sample G-buffers (GroupFrame::sampleGBuffers), null without.
TimedFrame timeFrame(BenchEntry& e, const EncodedGBuffer& enc, const PreparedFrame& prepared,
                     ForwardScene* forward, SampleGBuffers* samples,
                     const PerLightShadowMaps* perLight, int warmup, int repeat);

// The error of one frame against the references (on the frames --error-frames selects).
struct FrameErrors {
  std::optional<ErrorStats> error;            // against the scene reference (err_*)
  std::optional<ErrorStats> errorStored;      // against the stored values (error_vs_stored)
  std::optional<ErrorStats> errorShading;     // the same with float positions (err_shading_*)
  const ReferenceImage* reference = nullptr;  // the stored values' reference
  // --shadow-error: the frame's maps against exact visibility, and the image against the
  // reference shaded with exact visibility; null / none without a shadow-casting light.
  const ExactVisibilityResult* exact = nullptr;
  std::optional<ErrorStats> errorVsExact;
  bool shadowErrorWanted = false;
};

// --shadow-error's part of `out`: the frame's exact visibility and `image` against it.
void measureShadowError(GroupFrame& frame, const std::vector<glm::vec4>& image, FrameErrors& out);

// The errors of `image`, configuration `e`'s render of `frame` from `enc`.
FrameErrors measureErrors(const BenchEntry& e, GroupFrame& frame, const EncodedGBuffer& enc,
                          const TechniqueConfig& tc, const std::vector<glm::vec4>& image);

// The bench.json row of configuration `e` on frame `f`.
nlohmann::json measurementRow(const BenchEntry& e, const GroupFrame& frame, int f,
                              const EncodedGBuffer& enc, const TimedFrame& m,
                              const FrameErrors& err, int warmup, int repeat);

}  // namespace ts
