// Traditional deferred shading, one light at a time over its screen footprint (the baseline that
// tiled shading improves on); the kernels, in launch order, are in kernels/deferred.cl.
//
// "deferred": every pixel of a light's rectangle re-reads the G-buffer and shades that light.
// "deferred-stencil": the same rectangles, but a pixel reads only its depth first and the rest
// of the G-buffer only when its surface lies inside the light sphere (what a stencil pass over
// the light volume achieves on a GPU).
//
// Work counters (computed on the host from the uploaded G-buffer and lights, with the float
// culling/position code of the kernels, kernels/culling.h and shading.h via ts::shading_f):
//   lightingComputations  deferred: on-screen pixels covered by light rectangles (sum of areas),
//                         the paper's count for light volumes; stencil: geometry pixels whose
//                         position lies inside a light volume (range sphere, spot cone); both
//                         plus geometry pixels x directional lights (the base pass)
//   evaluations           shading-function calls the kernels make: deferred, geometry pixels in
//                         rectangles; stencil, the same as its lighting computations
//   gbufferBytesRead      base pass: depth for every pixel, the other planes for geometry pixels;
//                         per light and covered pixel: deferred reads the whole pixel
//                         (bytesPerPixel) plus the 16 B accumulation value for geometry pixels,
//                         the depth alone (4 B) for background; stencil reads 4 B depth, plus the
//                         other planes and the accumulation value only inside the sphere
//   listMin/Mean/Max      0: there are no bins (lights are applied per rectangle)
// The light assignment is the rectangle per light (pixelBin empty).
//
// Shadow storage (TechniqueConfig::shadowStorage, docs/shadows.md): with the atlas, every pass
// samples the frame's one atlas; with per-light, the technique draws the maps itself
// (DeviceFrame::perLightShadows): the directional lights' before the base pass, each point or
// spot light's just before its launch, each into the one reused device buffer (a blocking write:
// the in-order queue lets the previous launch finish reading it first, while the host draws the
// next light's maps). A light whose rectangle misses the screen has no launch and draws no map.
#include <algorithm>
#include <chrono>

#include "shading/shading_cpu.h"
#include "cl/kernel_args.h"
#include "cl/work_group.h"
#include "techniques/tile_grid.h"
#include "techniques/techniques.h"
#include "util/error.h"

namespace ts {
namespace {

constexpr size_t kAccumBytes = sizeof(cl_float4);  // one accumulation value per pixel
constexpr int kGroup = 16;                         // work-group edge of the per-light launch

// The pixel rectangle (x0, y0, x1, y1; x1/y1 exclusive) covered by a light's volume (sphere or
// cone) clipped to the near plane: culling.h's tile rectangle with 1x1 tiles, in float like the
// kernels, as a vertex stage would compute it. Empty (all zero) when it misses the screen.
glm::ivec4 lightRectangle(const ViewLights& lights, size_t i, const CameraIntrinsics& camera,
                          int spotCulling) {
  glm::vec4 b = lightNdcBounds(lights, i, camera, spotCulling);
  int x0, y0, x1, y1;
  if (!shading_f::ts_ndc_bounds_to_tiles(b, camera.width, camera.height, 1, 1, &x0, &y0, &x1, &y1))
    return glm::ivec4(0);
  return {x0, y0, x1 + 1, y1 + 1};
}

bool isEmpty(const glm::ivec4& r) { return r.z <= r.x || r.w <= r.y; }

WorkCounters deferredCounters(const DeviceFrame& frame, const std::vector<glm::ivec4>& rects,
                              bool stencil) {
  WorkCounters c;
  const EncodedGBuffer& gb = *frame.gbuffer;
  const CameraIntrinsics& cam = frame.camera;
  const uint64_t full = gb.bytesPerPixel(), rest = full - 4;
  uint64_t geometry = 0;
  for (float d : gb.depth) geometry += d > 0.0f;
  c.gbufferBytesRead = 4 * gb.pixelCount() + geometry * rest;  // base pass
  for (size_t i = 0; i < rects.size(); ++i) {
    const glm::ivec4& r = rects[i];
    if (isEmpty(r)) continue;
    glm::vec4 pr = frame.lights->positionRange[i], spot = frame.lights->spot[i];
    uint64_t covered = uint64_t(r.z - r.x) * uint64_t(r.w - r.y), hits = 0;
    for (int y = r.y; y < r.w; ++y)
      for (int x = r.x; x < r.z; ++x) {
        float depth = gb.depth[size_t(y) * gb.width + x];
        if (depth <= 0.0f) continue;
        if (stencil) {
          // The kernel's test, on the same float position reconstruction.
          glm::vec3 P = shading_f::ts_view_position(x, y, depth, cam.tanHalfFovX, cam.tanHalfFovY,
                                                    cam.width, cam.height);
          if (!shading_f::ts_light_volume_holds(pr, spot, P)) continue;
        }
        ++hits;
      }
    if (stencil) {
      c.lightingComputations += hits;
      c.gbufferBytesRead += 4 * covered + hits * (rest + kAccumBytes);
    } else {
      c.lightingComputations += covered;
      c.gbufferBytesRead += 4 * (covered - hits) + hits * (full + kAccumBytes);
    }
    c.evaluations += hits;
  }
  addDirectionalWork(c, geometry, frame);
  return c;
}

class DeferredTechnique : public Technique {
 public:
  DeferredTechnique(ClContext& cl, const TechniqueConfig& config, bool stencil)
      : cl_(cl), config_(config), stencil_(stencil), lanes_(config.lanes) {
    program_ = cl.build("deferred.cl", config.kernelOptions() + config.lanesOption() +
                                           (stencil ? " -DTS_STENCIL" : ""));
    base_ = cl::Kernel(program_, "deferred_base");
    light_ = cl::Kernel(program_, "deferred_light");
  }

  std::string name() const override { return stencil_ ? "deferred-stencil" : "deferred"; }
  int lanes() const override { return lanes_; }

  FrameResult renderFrame(DeviceFrame& frame, const FrameRequest& request) override {
    size_t pixels = size_t(frame.width()) * frame.height();
    if (pixels != accumPixels_) {
      accum_ = cl::Buffer(cl_.context(), CL_MEM_READ_WRITE, pixels * kAccumBytes);
      accumPixels_ = pixels;
    }
    std::vector<glm::ivec4> rects(frame.lights->size());
    for (size_t i = 0; i < rects.size(); ++i)
      rects[i] = lightRectangle(*frame.lights, i, frame.camera, int(config_.spotCulling));

    timer_.clear();
    shadowUse_.reset();
    if (config_.shadowStorage == ShadowStorage::PerLight && config_.features.shadows &&
        frame.lights->hasShadows())
      preparePerLightMaps(frame);
    enqueueFrame(frame, rects);
    cl_.queue().finish();
    FrameResult result;
    result.shadowUse = shadowUse_;
    result.kernels = timer_.kernels();
    result.totalMs = timer_.totalMs();
    result.image = readImage(cl_, accum_, frame);
    result.counters = deferredCounters(frame, rects, stencil_);
    if (request.wantAssignment) {
      LightAssignment a;
      a.lightRect = std::move(rects);
      result.assignment = std::move(a);
    }
    return result;
  }

 private:
  // The face table pointing into the passes' atlas, and the reused buffer (grown when a frame's
  // largest pass needs more).
  void preparePerLightMaps(const DeviceFrame& frame) {
    if (!frame.perLightShadows)
      throw Error(name() +
                  ": --shadow-storage per-light draws each light's maps from the frame's scene, "
                  "and this frame has none");
    const PerLightShadowMaps& maps = *frame.perLightShadows;
    const std::vector<glm::vec4> table = maps.passFaceTable(frame.lights->shadowFaces);
    passFaces_ = cl::Buffer(cl_.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                            table.size() * sizeof(glm::vec4), const_cast<glm::vec4*>(table.data()));
    const uint64_t bytes = std::max<uint64_t>(maps.residentBytes(), sizeof(float));
    if (bytes > passAtlasBytes_) {
      passAtlas_ = cl::Buffer(cl_.context(), CL_MEM_READ_ONLY, size_t(bytes));
      passAtlasBytes_ = bytes;
    }
    shadowUse_ = FrameShadowUse{};
    shadowUse_->residentBytes = maps.residentBytes();
  }

  // Draws one pass's maps on the host and writes them into the reused buffer.
  void drawPass(const ShadowPass& pass, const PerLightShadowMaps& maps) {
    const auto t0 = std::chrono::steady_clock::now();
    const ShadowAtlas drawn = maps.draw(pass);
    shadowUse_->drawMs +=
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    shadowUse_->passes += 1;
    shadowUse_->writtenBytes += pass.layout.bytes();
    shadowUse_->trianglesDrawn += drawn.trianglesDrawn();
    cl_.queue().enqueueWriteBuffer(passAtlas_, CL_TRUE, 0, drawn.depth.size() * sizeof(float),
                                   drawn.depth.data(), nullptr, timer_.next("shadow_write"));
  }

  void enqueueFrame(DeviceFrame& frame, const std::vector<glm::ivec4>& rects) {
    auto& q = cl_.queue();
    cl_float4 camera = toCl(frame.camera.kernelCamera());
    GroupShape baseGroup = fitGroup(kGroup, kGroup, groupLimit(cl_, base_));
    GroupShape lightGroup = fitGroup(kGroup, kGroup, groupLimit(cl_, light_));
    const PerLightShadowMaps* maps = shadowUse_ ? frame.perLightShadows : nullptr;
    const auto directionalShadows =
        maps ? std::tie(frame.directionalShadow, passFaces_, passAtlas_)
             : std::tie(frame.directionalShadow, frame.shadowFaces, frame.shadowAtlas);
    const auto lightShadows =
        maps ? std::tie(frame.lightShadow, passFaces_, passAtlas_)
             : std::tie(frame.lightShadow, frame.shadowFaces, frame.shadowAtlas);
    if (maps && maps->directionalPass()) drawPass(*maps->directionalPass(), *maps);

    // 1. Base: every pixel, so the accumulation buffer needs no separate clear.
    KernelArgs baseArgs(base_);
    baseArgs.add(camera)
        .add(toCl(glm::vec4(frame.ambient, 0.0f)))
        .add(frame.gbufferArgs())
        .add(frame.directionalArgs())
        .addIf(config_.features.shadows, directionalShadows)
        .add(accum_);
    if (lanes_ > 1) baseArgs.add(laneLocalMemory(config_, baseGroup.size()));
    baseArgs.done();
    q.enqueueNDRangeKernel(base_, cl::NullRange, baseGroup.global(frame.width(), frame.height()),
                           baseGroup.local(), nullptr, timer_.next("base"));

    // 2. One launch per light, all enqueued before waiting (per-light storage: its maps' blocking
    // write first): arguments are captured at enqueue time, and the in-order queue serialises
    // the read-modify-writes of successive lights.
    cl_uint lightArg = 0, rectArg = 0;
    KernelArgs lightArgs(light_);
    lightArgs.add(camera)
        .add(toCl(glm::vec4(frame.ambient, 0.0f)))
        .add(frame.gbufferArgs())
        .add(frame.lightArgs())
        .addIf(config_.features.shadows, lightShadows)
        .later(lightArg)
        .later(rectArg)
        .add(accum_);
    if (lanes_ > 1) lightArgs.add(laneLocalMemory(config_, lightGroup.size()));
    lightArgs.done();
    for (size_t i = 0; i < rects.size(); ++i) {
      const glm::ivec4& r = rects[i];
      if (isEmpty(r)) continue;
      if (maps && frame.lights->shadowOf(i) >= 0)
        drawPass(maps->passOf(frame.lights->shadowOf(i)), *maps);
      light_.setArg(lightArg, cl_int(i));
      light_.setArg(rectArg, cl_int4{{r.x, r.y, r.z, r.w}});
      q.enqueueNDRangeKernel(light_, cl::NullRange, lightGroup.global(r.z - r.x, r.w - r.y),
                             lightGroup.local(), nullptr, timer_.next("light"));
    }
  }

  ClContext& cl_;
  TechniqueConfig config_;
  bool stencil_;
  int lanes_;
  cl::Program program_;
  cl::Kernel base_, light_;
  cl::Buffer accum_;
  size_t accumPixels_ = 0;
  cl::Buffer passFaces_, passAtlas_;  // per-light storage: the passes' face table and atlas
  uint64_t passAtlasBytes_ = 0;
  std::optional<FrameShadowUse> shadowUse_;  // this frame's, with per-light storage
  FrameTimer timer_;
};

}  // namespace

std::unique_ptr<Technique> makeDeferredTechnique(ClContext& cl, const TechniqueConfig& config,
                                                 bool stencil) {
  return std::make_unique<DeferredTechnique>(cl, config, stencil);
}

}  // namespace ts
