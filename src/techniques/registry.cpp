// The one list of techniques. Adding a technique = its own .cpp/.cl pair plus one line here
// (tests/extra_tests.cmake reads the names from the entries' first lines, {"name",).
// The last field, where present, is the lanes "auto" picks on CPU devices: 16 where shading in
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
      {"tiled", "multi-kernel tiled deferred: depth min/max, light binning, per-pixel shading",
       makeTiledTechnique, 16},
      {"tiled-single",
       "single-kernel tiled deferred: one work-group per tile reduces depth, tests every light "
       "and shades in local memory",
       makeTiledSingleTechnique, 16},
      {"clustered",
       "clustered deferred: tiles x exponential depth slices, lights binned per non-empty cluster",
       makeClusteredTechnique, 16},
      {"deferred",
       "traditional deferred: one launch per light over its screen rectangle, each pixel re-reads "
       "the G-buffer and blends into an accumulation buffer",
       [](ClContext& cl, const TechniqueConfig& c) { return makeDeferredTechnique(cl, c, false); }},
      {"deferred-stencil",
       "traditional deferred with the stencil test's effect: only pixels inside the light sphere "
       "read the full G-buffer and shade",
       [](ClContext& cl, const TechniqueConfig& c) { return makeDeferredTechnique(cl, c, true); }},
      {"brute", "every light for every pixel, range test only: the naive baseline",
       makeBruteTechnique, 16},
  };
  return registry;
}

std::vector<std::string> techniqueNames() {
  std::vector<std::string> names;
  for (const auto& t : techniqueRegistry()) names.push_back(t.name);
  return names;
}

const TechniqueInfo& findTechnique(const std::string& name) {
  for (const auto& t : techniqueRegistry())
    if (t.name == name) return t;
  std::ostringstream known;
  for (const auto& n : techniqueNames()) known << (known.tellp() ? ", " : "") << n;
  throw Error("unknown technique '" + shortText(name) + "' (known: " + known.str() + ", all)");
}

namespace {
// The widths kernels/lanes.h is built for (TS_LANES; floatN exists for these N).
const int kLaneWidths[] = {1, 2, 4, 8, 16};

bool isLaneWidth(int n) {
  for (int w : kLaneWidths)
    if (n == w) return true;
  return false;
}

Error badLanes(const std::string& text) {
  return Error("lanes must be auto, 1, 2, 4, 8 or 16, not '" + shortText(text) + "'");
}
}  // namespace

std::unique_ptr<Technique> createTechnique(const std::string& name, ClContext& cl,
                                           const TechniqueConfig& config) {
  const TechniqueInfo& info = findTechnique(name);
  TechniqueConfig resolved = config;
  if (config.lanes == 0) resolved.lanes = cl.isGpu() ? 1 : info.autoLanesOnCpu;
  else if (!isLaneWidth(config.lanes)) throw badLanes(std::to_string(config.lanes));
  std::unique_ptr<Technique> technique = info.create(cl, resolved);
  technique->features_ = resolved.features;
  return technique;
}

FrameResult Technique::render(DeviceFrame& frame, const FrameRequest& request) {
  checkFrameFeatures(features_, frame);
  return renderFrame(frame, request);
}

void checkFrameFeatures(const SceneFeatures& features, const DeviceFrame& frame) {
  const EncodedGBuffer& gb = *frame.gbuffer;
  auto fail = [&](const std::string& what) {
    throw Error("kernels built for '" + features.describe() + "' cannot shade this frame: " +
                what);
  };
  if (gb.model != features.model)
    fail("its G-buffer holds " + toString(gb.model) + " terms");
  if (features.model == ShadingModel::BlinnPhong && features.specular && !gb.hasSpecularPlane())
    fail("its G-buffer has no specular plane");
  if (features.emissive && !gb.hasEmissive) fail("its G-buffer has no emissive plane");
  if (!features.spot)
    for (size_t i = 0; i < frame.lights->size(); ++i)
      if (frame.lights->isSpot(i)) fail("it has spot lights");
  if (!features.directional && frame.directionalCount() > 0) fail("it has directional lights");
}

namespace {
// A culling knob's names, in the order of the kernels' constants (kernels/culling.h).
const char* const kCullingNames[] = {"rect", "frustum", "aabb"};                    // TS_CULL_*
const char* const kSpotCullingNames[] = {"cone", "bound-sphere", "range-sphere"};  // TS_SPOT_CULL_*

template <size_t N>
int knobIndex(const char* const (&names)[N], const std::string& name, const std::string& knob) {
  std::string known;
  for (size_t i = 0; i < N; ++i) {
    if (name == names[i]) return int(i);
    known += (i ? ", " : "") + std::string(names[i]);
  }
  throw Error("unknown " + knob + " '" + shortText(name) + "' (known: " + known + ")");
}

template <size_t N>
std::string knobName(const char* const (&names)[N], int index) {
  return index >= 0 && index < int(N) ? names[index] : "?";
}
}  // namespace

int parseCulling(const std::string& name) { return knobIndex(kCullingNames, name, "culling test"); }

int parseSpotCulling(const std::string& name) {
  return knobIndex(kSpotCullingNames, name, "spot culling");
}

std::string cullingName(int culling) { return knobName(kCullingNames, culling); }

int parseLanes(const std::string& text) {
  if (text == "auto") return 0;
  for (int n : kLaneWidths)
    if (text == std::to_string(n)) return n;
  throw badLanes(text);
}

std::string lanesName(int lanes) { return lanes == 0 ? "auto" : std::to_string(lanes); }

std::string TechniqueConfig::kernelOptions() const {
  std::ostringstream o;
  const std::string layout = gbufferKernelDefines(format);
  o << layout << (layout.empty() ? "" : " ") << features.kernelDefines()
    << " -DTS_MODEL=" << shadingModel << " -DTS_CULL=" << culling;
  if (depthSplit) o << " -DTS_DEPTH_SPLIT=1";
  if (features.spot) o << " -DTS_SPOT_CULL=" << spotCulling;
  if (math == "fast") o << " -cl-fast-relaxed-math";
  else if (math == "native") o << " -DTS_NATIVE_MATH";
  else if (math != "precise")
    throw Error("unknown shading arithmetic '" + shortText(math) +
                "' (known: precise, fast, native)");
  if (!buildOptions.empty()) o << " " << buildOptions;
  return o.str();
}

std::string TechniqueConfig::key() const {
  std::ostringstream k;
  k << kernelOptions() << '|' << tileWidth << 'x' << tileHeight << '|' << clusterSlices << '|'
    << localListCapacity << '|' << presizeLists << '|' << lanes;
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
