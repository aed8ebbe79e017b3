#include "raster/raster_backend.h"

#include <utility>

#include "util/error.h"
#include "util/short_text.h"
#ifndef TILESHADE_NO_GL
#include "raster/gl_rasterizer.h"
#endif

namespace ts {

#ifdef TILESHADE_NO_GL
// A build without OpenGL (TILESHADE_WITH_GL=OFF) has no GlRasterizer; the class stays incomplete
// and is never made.
class GlRasterizer {
 public:
  GBuffer rasterize(const SceneCamera&, int, int, const RasterOptions&) { return {}; }
  std::string renderer() const { return {}; }
  ShadowAtlas drawShadowAtlas(ShadowAtlasLayout) { return {}; }
};
#else
namespace {

ForwardLighting lightingOf(const ViewLights& lights, glm::vec3 ambient,
                           const SceneFeatures& features, int rangeModel, int samples) {
  ForwardLighting lighting;
  lighting.samples = samples;
  lighting.lights = &lights;
  lighting.ambient = ambient;
  lighting.features = features;
  lighting.rangeModel = rangeModel;
  return lighting;
}

// One frame's camera in the OpenGL rasterizer's context.
class GlForwardScene : public ForwardScene {
 public:
  GlForwardScene(GlRasterizer& gl, const SceneCamera& camera, int width, int height, int samples)
      : gl_(gl), camera_(camera), width_(width), height_(height), samples_(samples) {}
  int samples() const override { return samples_; }
  std::vector<GBuffer> sampleGBuffers(const RasterOptions& options) override {
    return gl_.rasterizeSamples(camera_, width_, height_, samples_, options);
  }
  std::vector<float> depthPrepass(double& ms) override {
    return gl_.depthPrepass(camera_, width_, height_, samples_, ms);
  }
  ForwardImage tiledForward(const ViewLights& lights, glm::vec3 ambient,
                            const SceneFeatures& features, int rangeModel,
                            const ForwardLightGrid& grid, bool depthEqual,
                            const ForwardLightGrid* transparentGrid) override {
    return gl_.tiledForward(camera_, width_, height_,
                            lightingOf(lights, ambient, features, rangeModel, samples_), grid,
                            depthEqual, transparentGrid);
  }
  ForwardImage transparentOver(const std::vector<glm::vec4>& opaque, const ViewLights& lights,
                               glm::vec3 ambient, const SceneFeatures& features, int rangeModel,
                               const ForwardLightGrid& grid) override {
    return gl_.transparentOver(camera_, width_, height_,
                               lightingOf(lights, ambient, features, rangeModel, samples_), opaque,
                               grid);
  }
  size_t transparentDraws() const override { return gl_.transparentDraws(); }
  std::vector<TransparentFragment> captureTransparent(const SceneFeatures& features,
                                                      size_t maxFragments) override {
    return gl_.captureTransparent(camera_, width_, height_, features, maxFragments);
  }
  std::vector<ViewBox> batchBoxes() override { return gl_.batchBoxes(camera_); }
  ForwardImage multiPassForward(const ViewLights& lights, glm::vec3 ambient,
                                const SceneFeatures& features, int rangeModel,
                                const IndexLists& lightBatches) override {
    return gl_.multiPassForward(camera_, width_, height_,
                                lightingOf(lights, ambient, features, rangeModel, samples_),
                                lightBatches);
  }
  ForwardImage singlePassForward(const ViewLights& lights, glm::vec3 ambient,
                                 const SceneFeatures& features, int rangeModel,
                                 const IndexLists& batchLights) override {
    return gl_.singlePassForward(camera_, width_, height_,
                                 lightingOf(lights, ambient, features, rangeModel, samples_),
                                 batchLights);
  }

 private:
  GlRasterizer& gl_;
  SceneCamera camera_;
  int width_, height_, samples_;
};

}  // namespace
#endif

const EnumNames<RasterBackend>& rasterBackendNames() {
  static const EnumNames<RasterBackend> names(
      "rasterizer", {{RasterBackend::Software, "software"},
                     {RasterBackend::Gl, "gl",
                      "OpenGL through a headless EGL context: a GPU's driver, else Mesa's "
                      "llvmpipe; docs/opengl.md"}});
  return names;
}

std::string toString(RasterBackend backend) { return rasterBackendNames().name(backend); }

RasterBackend parseRasterBackend(const std::string& name) {
  return rasterBackendNames().parse(name);
}

SceneRasterizer::SceneRasterizer(const Scene& scene, RasterBackend backend)
    : scene_(scene), backend_(backend) {
  if (backend != RasterBackend::Gl) return;
#ifdef TILESHADE_NO_GL
  throw Error(
      "no OpenGL context for --raster gl: this build has none (configured with "
      "TILESHADE_WITH_GL=OFF)");
#else
  gl_ = std::make_unique<GlRasterizer>(scene);
  setupMs_ = gl_->setupMs();
#endif
}

SceneRasterizer::~SceneRasterizer() = default;
SceneRasterizer::SceneRasterizer(SceneRasterizer&&) noexcept = default;

// Coverage of the two rasterizers differs only on silhouettes (docs/opengl.md), a few pixels of a
// frame at most where a sliver of geometry is in view.
constexpr size_t kCoverageSlack = 4;

GBuffer SceneRasterizer::rasterize(const SceneCamera& camera, int width, int height,
                                   const RasterOptions& options) {
  if (!gl_) return ts::rasterize(scene_, camera, width, height, options);
  GBuffer g = gl_->rasterize(camera, width, height, options);
  // A driver that draws nothing (Mesa's softpipe on some machines) would give a black frame that
  // --check calls exact. Only an empty frame pays for the software rasterizer's second opinion.
  if (g.geometryPixels() == 0) {
    const size_t covered = ts::rasterize(scene_, camera, width, height, options).geometryPixels();
    if (covered > kCoverageSlack)
      throw Error("--raster gl: the OpenGL driver (" + gl_->renderer() + ") drew no pixel of a " +
                  std::to_string(width) + "x" + std::to_string(height) +
                  " frame where the software rasterizer covers " + std::to_string(covered) +
                  ": the driver does not draw (check GALLIUM_DRIVER / LIBGL_ALWAYS_SOFTWARE), or "
                  "use --raster software");
  }
  return g;
}

ShadowAtlas SceneRasterizer::drawShadowAtlas(ShadowAtlasLayout layout) {
  if (!gl_) return ts::drawShadowAtlas(scene_, std::move(layout));
  return gl_->drawShadowAtlas(std::move(layout));
}

std::unique_ptr<ForwardScene> SceneRasterizer::forwardScene(const SceneCamera& camera, int width,
                                                            int height, int samples) {
#ifdef TILESHADE_NO_GL
  (void)camera, (void)width, (void)height, (void)samples;
  return nullptr;
#else
  if (!gl_) return nullptr;
  if (samples > 1) {
    gl_->checkSamples(samples);
    // The capture and the composite of the reference are per pixel, not per sample.
    if (gl_->transparentDraws() > 0)
      throw Error("--msaa " + std::to_string(samples) +
                  " with transparent draws (--blend blend) is not done: the transparent pass "
                  "and its reference are per pixel; use --msaa 1 or --blend as-opaque|as-mask");
  }
  return std::make_unique<GlForwardScene>(*gl_, camera, width, height, samples);
#endif
}

std::string SceneRasterizer::description() const {
  return gl_ ? "gl: " + gl_->renderer() : toString(backend_);
}

}  // namespace ts
