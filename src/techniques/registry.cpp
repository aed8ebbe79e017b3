// The one list of techniques. Adding a technique = its own .cpp/.cl pair plus one line here
// (tests/extra_tests.cmake reads the names from the entries' first lines, {"name",).
// The fourth field, where present, is the lanes "auto" picks on CPU devices: 16 where shading in
// lanes measured faster on PoCL with many lights (tiled 6.6x, tiled-single 3.5x, brute 4.8x,
// clustered 6.8x; bench/RESULTS.md, docs/techniques.md); deferred has a lanes path but measured
// 3-21% slower with it (its time is per-light launches and G-buffer re-reads), so it stays at 1.
#include <sstream>

#include "techniques/technique.h"
#include "techniques/techniques.h"
#include "util/error.h"
#include "util/short_text.h"

namespace ts {

const std::vector<TechniqueInfo>& techniqueRegistry() {
  static const std::vector<TechniqueInfo> registry = {
      {"tiled",
       "multi-kernel tiled deferred: depth min/max, light binning, per-pixel shading; glass "
       "(--blend blend, --raster gl) in a tiled forward pass over its grid after; --msaa: a "
       "per-sample G-buffer, edge pixels shaded per sample",
       makeTiledTechnique, 16, /*drawsScene=*/false, /*reusesShadowMaps=*/false,
       /*hybridTransparency=*/true, /*multisamples=*/true},
      {"tiled-single",
       "single-kernel tiled deferred: one work-group per tile reduces depth, tests every light "
       "and shades in local memory",
       makeTiledSingleTechnique, 16},
      {"clustered",
       "clustered deferred: tiles x exponential depth slices, lights binned per non-empty "
       "cluster; --msaa: a per-sample G-buffer, edge pixels shaded per sample in their own "
       "clusters",
       makeClusteredTechnique, 16, /*drawsScene=*/false, /*reusesShadowMaps=*/false,
       /*hybridTransparency=*/false, /*multisamples=*/true},
      {"deferred",
       "traditional deferred: one launch per light over its screen rectangle, each pixel re-reads "
       "the G-buffer and blends into an accumulation buffer",
       [](ClContext& cl, const TechniqueConfig& c) { return makeDeferredTechnique(cl, c, false); },
       1, /*drawsScene=*/false, /*reusesShadowMaps=*/true},
      {"deferred-stencil",
       "traditional deferred with the stencil test's effect: only pixels inside the light sphere "
       "read the full G-buffer and shade",
       [](ClContext& cl, const TechniqueConfig& c) { return makeDeferredTechnique(cl, c, true); },
       1, /*drawsScene=*/false, /*reusesShadowMaps=*/true},
      {"brute", "every light for every pixel, range test only: the naive baseline",
       makeBruteTechnique, 16},
      {"tiled-forward",
       "tiled forward (needs --raster gl): tiled's light grid binned by screen rectangle only (no "
       "depth range), the scene drawn once in OpenGL, each fragment shading its tile's lights",
       [](ClContext& cl, const TechniqueConfig& c) {
         return makeTiledForwardTechnique(cl, c, false);
       },
       1, /*drawsScene=*/true, /*reusesShadowMaps=*/false, /*hybridTransparency=*/false,
       /*multisamples=*/true},
      {"tiled-forward-prez",
       "tiled forward with a depth pre-pass (needs --raster gl): pre-pass depth -> tiled's depth "
       "bounds and binning kernels, then the forward pass with depth test EQUAL",
       [](ClContext& cl, const TechniqueConfig& c) {
         return makeTiledForwardTechnique(cl, c, true);
       },
       1, /*drawsScene=*/true, /*reusesShadowMaps=*/false, /*hybridTransparency=*/false,
       /*multisamples=*/true},
      {"clustered-forward",
       "clustered forward (needs --raster gl): clustered's tiles x depth slices over the scene's "
       "view depth, binned by its kernel, the scene drawn once in OpenGL, each fragment (glass "
       "too) shading the lights of the cluster of its own depth",
       makeClusteredForwardTechnique, 1, /*drawsScene=*/true},
      {"forward",
       "multi-pass forward (needs --raster gl): a base pass (ambient, emission, directional), then "
       "per light one additive pass, depth test EQUAL, over the draw batches its sphere touches",
       makeForwardTechnique, 1, /*drawsScene=*/true},
      {"forward-single",
       "single-pass forward (needs --raster gl): per draw batch the lights touching its box, found "
       "on the host each frame (no list cap), the scene drawn once",
       makeForwardSingleTechnique, 1, /*drawsScene=*/true},
  };
  return registry;
}

std::vector<std::string> techniqueNames() {
  std::vector<std::string> names;
  for (const auto& t : techniqueRegistry()) names.push_back(t.name);
  return names;
}

std::vector<std::string> gbufferTechniqueNames() {
  std::vector<std::string> names;
  for (const auto& t : techniqueRegistry())
    if (!t.drawsScene) names.push_back(t.name);
  return names;
}

const TechniqueInfo& findTechnique(const std::string& name) {
  for (const auto& t : techniqueRegistry())
    if (t.name == name) return t;
  std::ostringstream known;
  for (const auto& n : techniqueNames()) known << (known.tellp() ? ", " : "") << n;
  throw Error("unknown technique '" + shortText(name) + "' (known: " + known.str() + ", all)");
}

std::unique_ptr<Technique> createTechnique(const std::string& name, ClContext& cl,
                                           const TechniqueConfig& config) {
  const TechniqueInfo& info = findTechnique(name);
  TechniqueConfig resolved = config;
  if (config.lanes == 0) resolved.lanes = cl.isGpu() ? 1 : info.autoLanesOnCpu;
  else if (lanesName(config.lanes) == "?")  // a width the kernels have no build for
    throw Error("lanes must be one of " + laneNames().list() + ", not " +
                std::to_string(config.lanes));
  if (config.shadowStorage == ShadowStorage::PerLight && !info.reusesShadowMaps)
    throw Error(shadowStorageRefusal(name));
  std::unique_ptr<Technique> technique = info.create(cl, resolved);
  technique->features_ = resolved.features;
  technique->drawsScene_ = info.drawsScene;
  technique->hybridGlass_ = info.hybridTransparency;
  technique->multisamples_ = info.multisamples;
  return technique;
}

FrameResult Technique::render(DeviceFrame& frame, const FrameRequest& request) {
  // Never a G-buffer image of a frame whose transparent surfaces it would leave out.
  if (!drawsScene_ && !hybridGlass_ && frame.forward && frame.forward->transparentDraws() > 0)
    throw Error(transparencyRefusal(name(), frame.forward->transparentDraws()));
  if (!multisamples_ && frame.forward && frame.forward->samples() > 1)
    throw Error(msaaRefusal(name(), frame.forward->samples()));
  checkFrameFeatures(features_, frame);
  return renderFrame(frame, request);
}

void checkFrameFeatures(const SceneFeatures& features, const DeviceFrame& frame) {
  const EncodedGBuffer& gb = *frame.gbuffer;
  auto fail = [&](const std::string& what) {
    throw Error("kernels built for '" + features.describe() + "' cannot shade this frame: " + what);
  };
  if (gb.model != features.model) fail("its G-buffer holds " + toString(gb.model) + " terms");
  if (features.model == ShadingModel::BlinnPhong && features.specular && !gb.hasSpecularPlane())
    fail("its G-buffer has no specular plane");
  if (features.emissive && !gb.hasEmissive) fail("its G-buffer has no emissive plane");
  if (!features.spot)
    for (size_t i = 0; i < frame.lights->size(); ++i)
      if (frame.lights->isSpot(i)) fail("it has spot lights");
  if (!features.directional && frame.directionalCount() > 0) fail("it has directional lights");
  if (!features.shadows && frame.lights->hasShadows()) fail("it has shadow-casting lights");
}

std::string transparencyRefusal(const std::string& technique, size_t draws) {
  return "technique '" + technique +
         "' shades the G-buffer, which holds the opaque surfaces only, and has no tiled forward "
         "pass for the transparent ones: this frame has " +
         std::to_string(draws) +
         " alphaMode BLEND draw(s) to composite (--blend blend; tiled or a forward technique "
         "draws them, or --blend as-opaque|as-mask)";
}

std::string shadowStorageRefusal(const std::string& technique) {
  return technique +
         ": --shadow-storage per-light is for deferred and deferred-stencil, which shade one "
         "light per pass; " +
         technique + " shades every light at once and needs every map resident (atlas)";
}

std::string msaaRefusal(const std::string& technique, int samples) {
  const TechniqueInfo& t = findTechnique(technique);
  if (!t.drawsScene)
    return "technique '" + technique + "' shades the G-buffer: --msaa " + std::to_string(samples) +
           " is done for tiled, clustered, tiled-forward and tiled-forward-prez only (a "
           "multisampled G-buffer for the other deferred ones is not)";
  // A fragment interpolated at the pixel centre for a sample its triangle covers can lie off
  // the triangle, outside its batch's box (docs/techniques.md, "MSAA").
  if (technique == "clustered-forward")
    return "technique 'clustered-forward' with --msaa " + std::to_string(samples) +
           " is not done: its slices span the scene's view depth bounds, which a fragment "
           "extrapolated to the pixel centre can leave (tiled, clustered, tiled-forward and "
           "tiled-forward-prez take --msaa)";
  return "technique '" + technique + "' with --msaa " + std::to_string(samples) +
         " is not done: its per-batch light lists are culled against the batches' boxes, which a "
         "fragment extrapolated to the pixel centre can leave (tiled, clustered, tiled-forward "
         "and tiled-forward-prez take --msaa)";
}

std::string TechniqueConfig::kernelOptions() const {
  std::ostringstream o;
  const std::string layout = gbufferKernelDefines(format);
  o << layout << (layout.empty() ? "" : " ") << features.kernelDefines()
    << " -DTS_MODEL=" << int(rangeModel) << " -DTS_CULL=" << int(culling);
  if (depthSplit) o << " -DTS_DEPTH_SPLIT=1";
  if (features.spot) o << " -DTS_SPOT_CULL=" << int(spotCulling);
  if (math == MathMode::Fast) o << " -cl-fast-relaxed-math";
  else if (math == MathMode::Native) o << " -DTS_NATIVE_MATH";
  if (!buildOptions.empty()) o << " " << buildOptions;
  return o.str();
}

std::string TechniqueConfig::key() const {
  std::ostringstream k;
  k << kernelOptions() << '|' << tileWidth << 'x' << tileHeight << '|' << clusterSlices << '|'
    << localListCapacity << '|' << presizeLists << '|' << lanes << '|' << toString(shadowStorage);
  return k.str();
}

std::string TechniqueConfig::lanesOption() const {
  return lanes > 1 ? " -DTS_LANES=" + std::to_string(lanes) +
                         " -DTS_HOST_LANE_PLANES=" + std::to_string(lanePlanes())
                   : "";
}

int TechniqueConfig::lanePlanes() const {
  // P, N, kd; with a specular term V, gloss, ks; with metallic-roughness the Smith view term.
  bool specular = features.specular || features.model == ShadingModel::MetallicRoughness;
  if (!specular) return 9;
  return features.model == ShadingModel::MetallicRoughness ? 17 : 16;
}

}  // namespace ts
