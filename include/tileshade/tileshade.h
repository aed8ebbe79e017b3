#pragma once
// tileshade's public C++ API: cull and shade a G-buffer with any of tileshade's techniques, on any
// OpenCL device, from an engine or a script. What the `tileshade render` command does, as a
// library (the command is written on it): choose a Device; make a Frame (a G-buffer, its camera
// and its lights: from your own host planes or cl_mem buffers, from G-buffer files, or rasterized
// from a built-in or glTF scene); shade it with a Renderer (a technique and its knobs); read the
// image, the per-kernel times, the counters and, when asked for, the error against tileshade's
// double-precision reference.
//
//   ts::Device device("cpu");
//   ts::Frame frame = ts::Frame::fromHost(device, planes, camera, lights);
//   ts::Renderer renderer(device, ts::Settings{});  // "tiled", 16x16 tiles
//   ts::ShadeResult r = renderer.shade(frame);      // r.rgba, r.kernels, r.counters
//
// Every failure is a ts::Error whose what() is one line, the same line the command prints after
// "tileshade: error: ". Names of knobs (technique, culling, math, layouts, ...) are the command's
// option values (`tileshade render --help`; docs/techniques.md, docs/accuracy.md).
// Conventions (docs/api.md): view space is right-handed, the camera looks down -z with +y up;
// images and planes are rows top first, 4 floats per pixel; angles are radians.
// Versioning: TILESHADE_VERSION_* (tileshade/version.h); the API follows semantic versioning
// from 1.0; before it, a minor version may change it (docs/api.md lists the changes).
#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

// The OpenCL types of the cl_mem / cl_context entry points are OpenCL 1.2's (the level tileshade
// targets); an includer that wants another level defines CL_TARGET_OPENCL_VERSION first. Without
// it, cl_version.h would print a note in every file that includes this header.
#ifndef CL_TARGET_OPENCL_VERSION
#define CL_TARGET_OPENCL_VERSION 120
#endif
#include <CL/cl.h>

#include "tileshade/error.h"
#include "tileshade/version.h"

namespace ts {

// ---- Devices -----------------------------------------------------------------------------------

struct DeviceDescription {
  int index = 0;  // usable as a Device spec
  std::string platform, name;
  std::string type;  // "gpu", "cpu", "accelerator", "other"
  int computeUnits = 0;
  uint64_t globalMemBytes = 0, localMemBytes = 0;
};

// Every OpenCL device of every platform (empty when no ICD is installed).
std::vector<DeviceDescription> listDeviceDescriptions();

class Device {
 public:
  // spec as `--device`: "" or "default" (first GPU, else first CPU; $TILESHADE_DEVICE when set),
  // "cpu", "gpu", an index of listDeviceDescriptions(), or a case-insensitive substring of
  // "platform device". Throws ts::Error when nothing matches.
  explicit Device(const std::string& spec = "");
  // The caller's own OpenCL objects (retained, released with the last copy of this Device). The
  // queue must have been created with CL_QUEUE_PROFILING_ENABLE: the per-kernel times come from
  // its events (ts::Error otherwise). Frames made from cl_mem buffers need this constructor.
  static Device fromOpenCL(cl_context context, cl_device_id device, cl_command_queue queue);

  std::string name() const;  // "platform / device"
  std::string type() const;  // as DeviceDescription::type
  // Wall time spent building kernels on this device so far (never part of a frame's time).
  double compileMs() const;

  struct Impl;
  const std::shared_ptr<Impl>& impl() const { return impl_; }

 private:
  explicit Device(std::shared_ptr<Impl> impl) : impl_(std::move(impl)) {}
  std::shared_ptr<Impl> impl_;
};

// ---- Camera and lights -------------------------------------------------------------------------

using Float3 = std::array<float, 3>;

// The camera the G-buffer was rendered with: the kernels turn (pixel, depth) into a view-space
// position with it, and cull lights against the tiles' frusta it spans.
struct Camera {
  int width = 0, height = 0;  // the G-buffer's size in pixels
  float tanHalfFovX = 1.0f, tanHalfFovY = 1.0f;
  float znear = 0.1f, zfar = 1000.0f;
  // Column-major world-to-view matrix, applied to the lights given to a Frame (identity: they are
  // already in view space).
  std::array<float, 16> viewFromWorld{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};

  // A symmetric perspective camera of vertical field of view yfov (radians) and the image's aspect.
  static Camera perspective(int width, int height, float yfov, float znear, float zfar);
};

enum class LightType { Point, Spot, Directional };

// glTF's punctual lights with tileshade's finite range (docs/techniques.md, "Lights").
struct Light {
  LightType type = LightType::Point;
  Float3 position{0, 0, 0};              // point, spot
  Float3 direction{0, 0, -1};            // spot, directional: unit, where the light travels
  Float3 color{1, 1, 1};                 // linear RGB, intensity included
  float range = 1.0f;                    // point, spot: > 0, the contribution is cut to 0 beyond it
  float innerConeAngle = 0.0f;           // spot: 0 <= inner < outer <= pi/2
  float outerConeAngle = 0.7853981634f;  // spot

  static Light point(Float3 position, Float3 color, float range);
  static Light spot(Float3 position, Float3 direction, Float3 color, float range,
                    float innerConeAngle, float outerConeAngle);
  static Light directional(Float3 direction, Float3 color);
};

struct Lights {
  std::vector<Light> lights;  // in index order (light lists are kept in this order)
  Float3 ambient{0, 0, 0};    // the global ambient term
};

// ---- G-buffers ---------------------------------------------------------------------------------

// Host planes in one of the documented layouts (docs/output-formats.md, "G-buffer layouts"):
// rows top first, tightly packed, the caller's memory (copied by Frame::fromHost).
//   depth     float per pixel, linear view depth (-z_view), 0 = background: every layout
//   "fp32"    normal, diffuse, specular, emissive: 4 floats per pixel each
//   "fp16"    the same as 4 halves (IEEE binary16) per pixel each
//   "packed"  normal, diffuse, specular: one uint32 per pixel (specular: one byte for
//             metallic-roughness); emissive: 4 halves
// The planes' meaning per shading model ("blinn-phong", "metallic-roughness") is that of
// `render --dump` (docs/output-formats.md). specular and emissive may be null: the frame then has
// no specular or emissive term.
struct HostGBuffer {
  int width = 0, height = 0;
  std::string layout = "fp32";
  std::string shadingModel = "blinn-phong";
  const float* depth = nullptr;
  const void* normal = nullptr;
  const void* diffuse = nullptr;
  const void* specular = nullptr;
  const void* emissive = nullptr;
};

// The same planes already on the device, as buffers of the Device's context (Device::fromOpenCL):
// shaded where they are, never copied (the reference error, when asked for, reads them back).
struct DeviceGBuffer {
  int width = 0, height = 0;
  std::string layout = "fp32";
  std::string shadingModel = "blinn-phong";
  cl_mem depth = nullptr, normal = nullptr, diffuse = nullptr;
  cl_mem specular = nullptr, emissive = nullptr;  // null: no such term
};

// A built-in or glTF scene, rasterized: the options of `tileshade render` that make its frame.
struct SceneRequest {
  std::string scene = "builtin:street";  // builtin:street, builtin:atrium, or a .gltf/.glb path
  std::string lights;                    // light set ("" = the scene's default / the file's own)
  int lightCount = -1;                   // -1 = the set's own count
  float lightRange = 0.0f;               // > 0 overrides every light's range
  float lightThreshold = 0.0f;           // > 0: ranges from the attenuation threshold
  std::string variant;                   // built-in variants, a comma list
  bool normalMaps = true;                // apply the scene's normal maps (glTF normalTexture)
  std::string shadows;      // which lights cast shadows: "" (the scene's marks), none, all or N
                            // (their maps: FrameInfo::shadowMaps; every deferred technique and the
                            // reference shade with them; the forward ones refuse)
  int shadowMapSize = 512;  // per point/spot face, a power of two 16..8192 (directional: 4x)
  double shadowBudgetMB = 64.0;        // the shadow atlas's budget, MiB (docs/shadows.md)
  std::string shadowFilter = "none";   // how shading samples the maps: none, pcf2, pcf3, pcf5
  std::string shadowBias = "1.5,1.5";  // depth bias CONSTANT,SLOPE in texel footprints
  // alphaMode BLEND materials: "refuse" (the frame is refused), "blend" (composited back to
  // front by the forward techniques; the G-buffer ones refuse the frame), "as-opaque" or
  // "as-mask" (drawn so)
  std::string blend = "refuse";
  std::string shadingModel = "auto";
  std::string features = "auto";
  uint32_t seed = 1;
  int width = 1280, height = 720;
  int frame = 0;  // of the scene's camera path
  std::string layout = "fp32";
  std::string raster = "software";  // or "gl"
  // MSAA samples a pixel (1, 2, 4, 8; above 1 with raster "gl" only): the forward techniques draw
  // multisampled targets resolved by OpenGL, checked against the per-sample reference; the
  // techniques that shade the G-buffer refuse such a frame.
  int msaa = 1;
};

// One shadow-casting light's share of the frame's shadow atlas (ShadowMapsInfo).
struct ShadowMapLight {
  uint32_t light = 0;               // index into the scene's lights
  std::string type;                 // "point", "spot" or "directional"
  int faces = 0;                    // 6 (a cube) or 1
  int requestedSize = 0, size = 0;  // per face, texels a side: before the budget, as drawn
};

// The shadow maps of a frame, drawn into one float32 atlas (docs/shadows.md), which every
// deferred technique and the reference shade with.
struct ShadowMapsInfo {
  uint64_t faces = 0;
  int atlasWidth = 0, atlasHeight = 0;
  uint64_t bytes = 0;           // the atlas's
  uint64_t trianglesDrawn = 0;  // summed over the faces (each draws what its frustum touches)
  double drawMs = 0.0;          // OpenGL: glFinish to glFinish around the pass
  std::string rasterizer;       // who drew them: "software" or "gl"
  double readMs = 0.0;          // OpenGL: the atlas's read-back (0 for software)
  std::vector<ShadowMapLight> lights;
  std::vector<std::string> notes;  // lights that lost resolution to the budget, wide spot cones
};

// What a frame holds, for tables and records.
struct FrameInfo {
  std::string sceneName;     // the scene's, or the G-buffer descriptor's
  std::string source;        // "software", "gl", "import" or "host"/"device" (the API's planes)
  std::string sourceDetail;  // e.g. "gl: llvmpipe (...)", or the descriptor's path
  uint64_t triangles = 0;    // 0 when no scene was rasterized
  int frame = 0;
  int width = 0, height = 0;
  std::string layout;  // as HostGBuffer::layout
  std::string shadingModel;
  std::string features;  // what the kernels model, e.g. "blinn-phong: specular, point"
  uint64_t bytesPerPixel = 0;
  uint64_t geometryPixels = 0;
  uint64_t lights = 0, directionalLights = 0;  // lights counts directional ones too
  std::string lightSummary;          // "924 lights", "12 lights: 6 point, 5 spot, 1 directional"
  uint64_t shadowCastingLights = 0;  // marked to cast a shadow
  std::optional<ShadowMapsInfo> shadowMaps;    // their maps; none without a shadow-casting light
  double rasterMs = 0.0, rasterSetupMs = 0.0;  // 0 where nothing was rasterized
  // A scene rasterized with raster "gl": the techniques that draw the scene (forward) can shade
  // it, through the same OpenGL context (TechniqueDescription::drawsScene).
  bool drawsScene = false;
  // Draws with an alphaMode BLEND material composited by the forward techniques and the hybrid
  // ones ("blend" policy; TechniqueDescription::hybridTransparency); the other techniques that
  // shade the G-buffer refuse a frame with any.
  uint64_t transparentDraws = 0;
  int msaa = 1;  // SceneRequest::msaa
};

// One frame's inputs on a device, shared by every Renderer that shades it.
class Frame {
 public:
  // Every value is checked as the command checks imported G-buffers (a NaN, a normal far from
  // unit length, a negative colour, a value beyond the shading range, a light without a range:
  // ts::Error naming the plane or light and the pixel).
  static Frame fromHost(Device& device, const HostGBuffer& planes, const Camera& camera,
                        const Lights& lights);
  static Frame fromDevice(Device& device, const DeviceGBuffer& planes, const Camera& camera,
                          const Lights& lights);
  // `render --gbuffer-in`: a folder written by `render --dump` or a descriptor .json; layout ""
  // keeps the files' own.
  static Frame fromFiles(Device& device, const std::string& dirOrDescriptor,
                         const std::string& layout = "");
  static Frame fromScene(Device& device, const SceneRequest& request);

  const FrameInfo& info() const;

  // Writes what `render --dump` writes (gbuffer.exr, lights.json, gbuffer.json) into dir.
  void dump(const std::string& dir) const;

  struct Impl;
  const std::shared_ptr<Impl>& impl() const { return impl_; }

 private:
  explicit Frame(std::shared_ptr<Impl> impl) : impl_(std::move(impl)) {}
  std::shared_ptr<Impl> impl_;
};

// ---- Techniques and results --------------------------------------------------------------------

struct TechniqueDescription {
  std::string name, description;
  // It draws the scene itself (the forward family, docs/techniques.md): it shades only frames
  // whose FrameInfo::drawsScene is true, and refuses (ts::Error) the others.
  bool drawsScene = false;
  // It shades one light per pass and so can reuse one small shadow atlas per light
  // (Settings::shadowStorage "per-light"; deferred, deferred-stencil).
  bool reusesShadowMaps = false;
  // A G-buffer technique that shades transparent surfaces (--blend blend) in a tiled forward pass
  // over its grid after the opaque ones (`tiled`, docs/techniques.md); the other G-buffer
  // techniques refuse a frame with FrameInfo::transparentDraws.
  bool hybridTransparency = false;
  // It shades frames with SceneRequest::msaa above 1 (tiled-forward, tiled-forward-prez); the
  // others refuse them (ts::Error).
  bool multisamples = false;
};
std::vector<TechniqueDescription> listTechniques();

// A technique and its knobs, by the names `tileshade render` takes.
struct Settings {
  std::string technique = "tiled";
  int tileWidth = 16, tileHeight = 16;
  int slices = 16;               // clustered: depth slices
  std::string culling = "rect";  // per-tile light test
  std::string spotCulling = "cone";
  bool depthSplit = false;
  std::string math = "precise";   // precise, fast, native
  std::string lanes = "auto";     // auto, 1, 2, 4, 8, 16
  std::string extraBuildOptions;  // appended to the OpenCL build options
  // Where the shadow maps live: "atlas" (the frame's, every map resident) or "per-light" (only
  // techniques with TechniqueDescription::reusesShadowMaps: each light's maps drawn into one
  // reused atlas just before its pass; ShadeResult::shadowUse). docs/shadows.md.
  std::string shadowStorage = "atlas";
};

struct KernelTiming {
  std::string name;
  double ms = 0.0;  // sum over the frame's launches, from profiling events
  int launches = 0;
};

// docs/techniques.md defines each counter per technique.
struct Counters {
  uint64_t lightingComputations = 0;
  uint64_t evaluations = 0;
  uint64_t gbufferBytesRead = 0;
  uint32_t listMin = 0, listMax = 0;  // lights per bin (0 without bins)
  double listMean = 0.0;
  std::vector<std::string> notes;  // e.g. a light list that was grown
  // --msaa in tiled (a multisampled G-buffer): its samples (1 elsewhere), the pixels it shaded
  // once per sample (the edge mask's; the others once) and the per-sample planes' bytes.
  int msaaSamples = 1;
  uint64_t pixelsShadedPerSample = 0;
  uint64_t msaaGBufferBytes = 0;
};

// The image against a double-precision reference (docs/accuracy.md).
struct ErrorReport {
  double maxAbs = 0.0, rmse = 0.0, psnr = 0.0, maxRelPeak = 0.0;
  double p50 = 0.0, p99 = 0.0, p999 = 0.0;
  double tolerance = 0.0;  // 1e-4 of the peak
  uint64_t pixelsAboveTolerance = 0, nonfinitePixels = 0;
  double peak = 0.0;
  // A technique that draws the scene (forward): the error is what lies beyond the reference's
  // slack for shadow tests decided within rounding of the fragment's position (docs/shadows.md,
  // "Forward techniques"); the pixels it reduced and the ambiguous (pixel, light) pairs.
  bool receiverSlack = false;
  uint64_t slackPixels = 0, ambiguousShadowPairs = 0;
};

struct CheckReport {
  ErrorReport error;           // vs the reference of the kernels' model (positions in double)
  ErrorReport shadingError;    // vs the same with the kernels' float positions: shading arithmetic
  ErrorReport physicalError;   // vs the physical model (no range cut) from fp32 planes
  uint64_t missed = 0;         // contributing (pixel, light) pairs a light list left out
  uint64_t contributing = 0;   // contributing pairs of the reference (the ideal)
  bool missedCounted = true;   // false: the technique keeps no light lists to check (missed = 0)
  double referencePeak = 0.0;  // the reference's largest channel value (non-finite ones too)
};

// The shadow maps a renderer drew itself during the frame (Settings::shadowStorage per-light).
struct ShadowUse {
  int passes = 0;               // map draws: the directional lights' together, one per light
  double drawMs = 0.0;          // drawing them on the host, summed (not in totalMs)
  uint64_t residentBytes = 0;   // the reused atlas on the device (the largest pass's maps)
  uint64_t writtenBytes = 0;    // written to it over the frame
  uint64_t trianglesDrawn = 0;  // over every pass's faces
};

struct ShadeResult {
  std::string technique;
  int width = 0, height = 0;
  std::vector<float> rgba;  // linear RGB + a meaningless alpha, 4 floats a pixel, rows top first
  std::vector<KernelTiming> kernels;
  double totalMs = 0.0;  // sum of the kernel times
  int lanes = 1;         // as it ran
  Counters counters;
  uint64_t nonfinitePixels = 0;
  std::optional<CheckReport> check;    // when ShadeOptions::check
  std::string kernelOptions;           // the OpenCL build options of its kernels
  std::optional<ShadowUse> shadowUse;  // per-light shadow storage on a frame with casters
};

struct ShadeOptions {
  bool check = false;  // compare with the double reference (cached per frame; seconds to minutes)
};

// A technique on a device: its kernels are built at the first frame of each feature set (never
// inside a frame's time) and reused.
class Renderer {
 public:
  // Throws ts::Error for an unknown technique or knob value, before anything is built.
  Renderer(Device& device, const Settings& settings);
  ~Renderer();
  Renderer(Renderer&&) noexcept;
  Renderer& operator=(Renderer&&) noexcept;

  const Settings& settings() const;
  // Builds the kernels for this frame now (what shade() would do first): a configuration the
  // device refuses fails here.
  void prepare(const Frame& frame);
  // The same image bit for bit on every call with the same frame.
  ShadeResult shade(const Frame& frame, const ShadeOptions& options = {});

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// ---- Sweeps ------------------------------------------------------------------------------------

// `tileshade bench` (docs/bench.md) on a --config document; the rows of its bench.csv, every value
// as its text, keyed by column name (docs/output-formats.md lists the columns).
struct BenchRequest {
  std::string configJson;  // a --config document: dimension names as keys, frames, repeat, ...
  std::string configPath;  // or a --config file's path (then configJson stays empty)
  std::string outDir;      // bench.csv, bench.json, summary.csv (replaced when there)
  bool calibrate = false;  // the device-limit calibration behind the limit_pct columns (seconds)
  bool quiet = true;       // no progress on stderr
};
std::vector<std::map<std::string, std::string>> runBench(const BenchRequest& request);

}  // namespace ts
