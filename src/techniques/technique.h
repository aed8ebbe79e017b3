#pragma once
// The interface every light-culling/shading technique implements. A technique is created for a
// device and a configuration (its kernels are built then: compile time never mixes with frame
// time) and renders frames from a DeviceFrame. Registering a technique touches one place:
// techniqueRegistry() in src/techniques/registry.cpp.
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "cl/cl_context.h"
#include "gbuffer/gbuffer_layout.h"
#include "scene/scene_features.h"
#include "shading/light_assignment.h"
#include "techniques/device_frame.h"
#include "techniques/technique_knobs.h"

namespace ts {

// Everything that changes how a technique's kernels are built or launched.
struct TechniqueConfig {
  GBufferFormat format = GBufferFormat::FP32;
  // What the kernels model (shading model, material terms, light types): only these are compiled
  // in, and the G-buffer must have been encoded for the same features. Default: everything for
  // Blinn-Phong.
  SceneFeatures features = SceneFeatures::general(ShadingModel::BlinnPhong);
  int tileWidth = 16;
  int tileHeight = 16;
  int clusterSlices = 16;        // depth slices of the clustered technique
  bool presizeLists = true;      // tiled: size the light list from the host's bound of the
                                 // frame's entries (off: start small and grow, as tests do)
  int localListCapacity = 1024;  // tiled-single: lights its local-memory list holds before it
                                 // shades a chunk (raised to the work-group size if smaller);
                                 // also its batch of light tests (kernels/tiled_single.cl)
  // The knobs with named values (technique_knobs.h: meaning, kernel constant, name table).
  RangeModel rangeModel = RangeModel::Windowed;  // TS_MODEL
  CullTest culling = CullTest::Rect;             // TS_CULL: the per-tile test
  bool depthSplit = false;  // tiles: split the depth range at its middle (TS_DEPTH_SPLIT, tiled.cl)
  SpotCulling spotCulling = SpotCulling::Cone;  // TS_SPOT_CULL
  MathMode math = MathMode::Precise;            // shading arithmetic
  // Where the shadow maps live (technique_knobs.h); PerLight only for the techniques whose
  // TechniqueInfo::reusesShadowMaps (createTechnique refuses the others).
  ShadowStorage shadowStorage = ShadowStorage::Atlas;
  std::string buildOptions;  // extra OpenCL build options (e.g. -cl-fast-relaxed-math)
  // Pixels shaded together against each light (kernels/lanes.h): 0 = auto (createTechnique resolves
  // it: on CPU devices 16 for tiled, tiled-single, clustered and brute, 1 for the rest; 1 on
  // GPUs), 1 = one work-item per pixel, 2/4/8/16 = lanes.
  int lanes = 0;

  // " -DTS_LANES=N -DTS_HOST_LANE_PLANES=P" for a technique with a lanes path when lanes > 1,
  // else "".
  std::string lanesOption() const;
  // Floats per pixel slot of the lanes' local buffer for these features (kernels/lanes.h, which
  // checks the count at build time).
  int lanePlanes() const;

  // Build options every technique passes to ClContext::build (G-buffer layout, features, range
  // model, culling test, arithmetic, extras).
  std::string kernelOptions() const;
  // kernelOptions and every other field a technique builds or launches with: configurations with
  // one key create the same technique (check's cache). A new field belongs here.
  std::string key() const;
};

struct KernelTime {
  std::string name;
  double ms = 0.0;  // sum over this frame's launches, from profiling events
  int launches = 0;
};

// --msaa in a G-buffer technique (tiled): its multisampled G-buffer and where it shaded per sample.
struct SampleShading {
  int samples = 1;
  uint64_t pixelsShadedPerSample = 0;  // the edge pixels (kernels/msaa_edges.h)
  uint64_t gbufferBytes = 0;           // the per-sample planes on the device, every sample
};

// Work counters of one frame (definitions per technique in docs/techniques.md).
struct WorkCounters {
  uint64_t lightingComputations = 0;  // counted the paper's way for this technique
  uint64_t evaluations = 0;           // shading-function calls the kernels actually made
  uint64_t gbufferBytesRead = 0;      // estimated from the access pattern
  // Lights per bin (tile or cluster); zero where the technique has no bins.
  uint32_t listMin = 0;
  double listMean = 0.0;
  uint32_t listMax = 0;
  std::vector<std::string> notes;              // e.g. "light list buffer grown to N entries"
  std::optional<SampleShading> sampleShading;  // a multisampled G-buffer's (tiled --msaa) only
};

// The shadow maps a technique drew itself during the frame (--shadow-storage per-light): each
// light's maps into one reused atlas just before its pass (raster/per_light_shadows.h).
struct FrameShadowUse {
  int passes = 0;               // map draws (the directional lights' together, one per light)
  double drawMs = 0.0;          // their drawing on the host, summed (culling and rasterizing)
  uint64_t residentBytes = 0;   // the reused atlas on the device: the largest pass's maps
  uint64_t writtenBytes = 0;    // written to it over the frame (every pass's maps)
  uint64_t trianglesDrawn = 0;  // over every pass's faces
};

struct FrameResult {
  std::vector<glm::vec4> image;  // linear RGB per pixel (w unused), row 0 = top
  std::vector<KernelTime> kernels;
  double totalMs = 0.0;  // sum of kernel times
  WorkCounters counters;
  std::optional<LightAssignment> assignment;  // filled when asked for
  // Set by a technique that drew the frame's maps itself (ShadowStorage::PerLight with casters).
  std::optional<FrameShadowUse> shadowUse;
};

struct FrameRequest {
  bool wantAssignment = false;  // read back the light lists (tests, stats)
};

class Technique {
 public:
  virtual ~Technique() = default;
  virtual std::string name() const = 0;
  // Renders a frame: the same image bit for bit on every call with the same frame (light lists
  // are in light index order, docs/techniques.md). Throws ts::Error, before any work, when the
  // frame needs what the kernels were not built for (checkFrameFeatures).
  FrameResult render(DeviceFrame& frame, const FrameRequest& request);
  // Pixels its shading kernel evaluates together per light (TechniqueConfig::lanes as it ran).
  virtual int lanes() const { return 1; }
  // What its kernels were built for (TechniqueConfig::features).
  const SceneFeatures& features() const { return features_; }

 protected:
  virtual FrameResult renderFrame(DeviceFrame& frame, const FrameRequest& request) = 0;

 private:
  friend std::unique_ptr<Technique> createTechnique(const std::string&, ClContext&,
                                                    const TechniqueConfig&);
  SceneFeatures features_;
  bool drawsScene_ = false;    // TechniqueInfo::drawsScene
  bool hybridGlass_ = false;   // TechniqueInfo::hybridTransparency
  bool multisamples_ = false;  // TechniqueInfo::multisamples
};

// Throws ts::Error naming the mismatch when kernels built for `features` cannot render `frame`
// exactly: its G-buffer holds another model's terms or lacks a plane they read, or it has spot
// or directional lights they do not shade, or shadow-casting lights without TS_HAS_SHADOWS.
void checkFrameFeatures(const SceneFeatures& features, const DeviceFrame& frame);

struct TechniqueInfo {
  std::string name;
  std::string description;
  std::function<std::unique_ptr<Technique>(ClContext&, const TechniqueConfig&)> create;
  // Lanes for TechniqueConfig::lanes = 0 (auto) on a CPU device: the measured faster choice
  // (bench/RESULTS.md); GPUs always get 1.
  int autoLanesOnCpu = 1;
  // Draws the scene (the forward family) instead of reading the G-buffer: runs only on frames
  // with a DeviceFrame::forward scene (`--raster gl`); `all` leaves it out elsewhere.
  bool drawsScene = false;
  // Shades one light per pass, so it can reuse one small shadow atlas per light
  // (ShadowStorage::PerLight); the others shade every light at once and need every map resident.
  bool reusesShadowMaps = false;
  // A G-buffer technique that shades a frame's transparent surfaces (--blend blend) in a tiled
  // forward pass over its own grid after the opaque ones (techniques/transparent_hybrid.h: the
  // paper's hybrid); the other G-buffer techniques refuse such a frame.
  bool hybridTransparency = false;
  // Shades a frame drawn with --msaa above 1 (multisampled forward targets, OpenGL's resolve);
  // Technique::render refuses such a frame for the others (msaaRefusal).
  bool multisamples = false;
};
// The one line a G-buffer technique without the hybrid refuses a frame with `draws` transparent
// draws with (Technique::render; render's checks before any file).
std::string transparencyRefusal(const std::string& technique, size_t draws);

const std::vector<TechniqueInfo>& techniqueRegistry();
// The one line createTechnique (and render's, bench's checks) refuse ShadowStorage::PerLight
// with for a technique that does not reuse shadow maps.
std::string shadowStorageRefusal(const std::string& technique);
// The one line a technique without TechniqueInfo::multisamples refuses --msaa `samples` with.
std::string msaaRefusal(const std::string& technique, int samples);
std::vector<std::string> techniqueNames();
// The techniques that shade the frame's G-buffer (all but the drawsScene ones): what `all` means
// where the frame has no scene to draw (software raster, imported G-buffer, bench, check).
std::vector<std::string> gbufferTechniqueNames();
// Both throw ts::Error naming the known techniques when `name` is not one of them.
const TechniqueInfo& findTechnique(const std::string& name);
// Throws ts::Error naming the known techniques when `name` is not one of them, or for a bad
// lanes value. Resolves lanes = 0 (auto) for the device before the technique sees the config.
std::unique_ptr<Technique> createTechnique(const std::string& name, ClContext& cl,
                                           const TechniqueConfig& config);

}  // namespace ts
