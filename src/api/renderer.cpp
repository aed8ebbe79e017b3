// ts::Renderer of tileshade.h: a technique (createTechnique) with the knobs of Settings, built
// for each frame's features on first use; the check is `render --check`'s.
#include <map>

#include "api/api_internal.h"
#include "reference/error_metrics.h"
#include "reference/transparent_missed.h"
#include "techniques/technique.h"
#include "util/error.h"
#include "util/option_values.h"

namespace ts {
namespace {

// Relative tolerance (of the reference peak) of the "pixels above tolerance" count.
constexpr double kReportTolerance = 1e-4;

ErrorReport errorReport(const ErrorStats& e) {
  ErrorReport r;
  r.maxAbs = e.maxAbs;
  r.rmse = e.rmse;
  r.psnr = e.psnr;
  r.maxRelPeak = e.maxRelPeak;
  r.p50 = e.p50;
  r.p99 = e.p99;
  r.p999 = e.p999;
  r.tolerance = e.tolerance;
  r.pixelsAboveTolerance = e.pixelsAboveTolerance;
  r.nonfinitePixels = e.nonfinitePixels;
  r.peak = e.peak;
  r.receiverSlack = e.receiverSlack;
  r.slackPixels = e.slackPixels;
  r.ambiguousShadowPairs = e.ambiguousShadowPairs;
  return r;
}

// slack: Allow for a technique that draws the scene (its fragments' own positions; reference.h).
ErrorReport compared(const std::vector<glm::vec4>& image, const ReferenceImage& reference,
                     ReceiverSlack slack) {
  return errorReport(
      compareToReference(image, reference, kReportTolerance * reference.peak, slack));
}

// --blend blend: the misses over the frame's transparent fragments, each against the list its
// technique shaded it with. A technique that drew them and kept no such lists is a bug, said so.
uint64_t transparentMisses(const LightAssignment& assignment, const FrameReferences& refs,
                           const EncodedGBuffer& planes, const PreparedFrame& p, int model) {
  if (refs.fragments.empty()) return 0;
  if (!assignment.transparent)
    throw Error("the technique kept no light lists for the frame's " +
                std::to_string(refs.fragments.size()) + " transparent fragments");
  return countMissedTransparent(*assignment.transparent, refs.fragments, p.lights, model, planes);
}

}  // namespace

struct Renderer::Impl {
  std::shared_ptr<Device::Impl> device;
  Settings settings;
  TechniqueConfig knobs;  // format and features come from each frame
  std::map<std::string, std::unique_ptr<Technique>> built;  // by TechniqueConfig::key()

  TechniqueConfig configFor(const Frame& frame) const {
    TechniqueConfig c = knobs;
    c.format = frame.impl()->prepared.encoded.format;
    c.features = frame.impl()->prepared.features;
    return c;
  }
  Technique& techniqueFor(const Frame& frame) {
    if (frame.impl()->device != device)
      throw Error("the frame was made on another Device than the renderer's");
    const TechniqueConfig c = configFor(frame);
    std::unique_ptr<Technique>& t = built[c.key()];
    if (!t) t = createTechnique(settings.technique, device->cl, c);
    return *t;
  }
};

Renderer::Renderer(Device& device, const Settings& s) : impl_(std::make_unique<Impl>()) {
  impl_->device = device.impl();
  impl_->settings = s;
  findTechnique(s.technique);
  TechniqueConfig& c = impl_->knobs;
  c.tileWidth = int(checkInteger("--tile", s.tileWidth, 1, kMaxTileSide));
  c.tileHeight = int(checkInteger("--tile", s.tileHeight, 1, kMaxTileSide));
  c.clusterSlices = int(checkInteger("--slices", s.slices, 1, kMaxClusterSlices));
  c.culling = cullTestNames().parseOption("--culling", s.culling);
  c.spotCulling = spotCullingNames().parseOption("--spot-culling", s.spotCulling);
  c.depthSplit = s.depthSplit;
  c.math = mathModeNames().parseOption("--math", s.math);
  c.lanes = laneNames().parseOption("--lanes", s.lanes);
  c.buildOptions = s.extraBuildOptions;
  c.shadowStorage = shadowStorageNames().parseOption("--shadow-storage", s.shadowStorage);
  if (c.shadowStorage == ShadowStorage::PerLight && !findTechnique(s.technique).reusesShadowMaps)
    throw Error(shadowStorageRefusal(s.technique));
}

Renderer::~Renderer() = default;
Renderer::Renderer(Renderer&&) noexcept = default;
Renderer& Renderer::operator=(Renderer&&) noexcept = default;

const Settings& Renderer::settings() const { return impl_->settings; }

void Renderer::prepare(const Frame& frame) {
  openclErrorsAsTs([&] { impl_->techniqueFor(frame); });
}

ShadeResult Renderer::shade(const Frame& frame, const ShadeOptions& options) {
  return openclErrorsAsTs([&] {
    Technique& technique = impl_->techniqueFor(frame);
    Frame::Impl& f = *frame.impl();
    const bool drawsScene = findTechnique(impl_->settings.technique).drawsScene;
    // A device frame's planes are the caller's: a check reads them back first (the counters
    // already have the depth).
    FrameRequest request;
    request.wantAssignment = options.check;
    FrameResult r = technique.render(f.onDevice, request);

    ShadeResult out;
    out.technique = impl_->settings.technique;
    out.width = f.onDevice.width();
    out.height = f.onDevice.height();
    out.rgba.resize(r.image.size() * 4);
    for (size_t i = 0; i < r.image.size(); ++i)
      for (int c = 0; c < 4; ++c) out.rgba[4 * i + size_t(c)] = r.image[i][c];
    for (const KernelTime& k : r.kernels) out.kernels.push_back({k.name, k.ms, k.launches});
    out.totalMs = r.totalMs;
    out.lanes = technique.lanes();
    const WorkCounters& c = r.counters;
    out.counters.lightingComputations = c.lightingComputations;
    out.counters.evaluations = c.evaluations;
    out.counters.gbufferBytesRead = c.gbufferBytesRead;
    out.counters.listMin = c.listMin;
    out.counters.listMax = c.listMax;
    out.counters.listMean = c.listMean;
    out.counters.notes = c.notes;
    if (c.sampleShading) {
      out.counters.msaaSamples = c.sampleShading->samples;
      out.counters.pixelsShadedPerSample = c.sampleShading->pixelsShadedPerSample;
      out.counters.msaaGBufferBytes = c.sampleShading->gbufferBytes;
    }
    out.nonfinitePixels = countNonFinitePixels(r.image);
    if (r.shadowUse)
      out.shadowUse =
          ShadowUse{r.shadowUse->passes, r.shadowUse->drawMs, r.shadowUse->residentBytes,
                    r.shadowUse->writtenBytes, r.shadowUse->trianglesDrawn};
    const TechniqueConfig config = impl_->configFor(frame);
    out.kernelOptions = config.kernelOptions();
    if (options.check) {
      const FrameReferences& refs = f.ensureReferences({}, drawsScene);
      CheckReport check;
      // What lies beyond the shadow tests' slack over the receiver's rounding (reference.h).
      const ReceiverSlack slack = ReceiverSlack::Allow;
      check.error = compared(r.image, refs.reference, slack);
      check.shadingError = compared(r.image, refs.shadingOnly, slack);
      check.physicalError = compared(r.image, refs.physical, slack);
      check.contributing = refs.reference.contributing;
      check.referencePeak = refs.reference.peak;
      if (r.assignment) {
        const PreparedFrame& p = f.prepared;
        if (f.multisampled())
          check.missed = countMissedOverSamples(*r.assignment, f.samplePlanes(drawsScene),
                                                p.intrinsics, p.lights, int(config.rangeModel));
        else
          check.missed = countMissedContributions(*r.assignment, f.planesShadedBy(drawsScene),
                                                  p.intrinsics, p.lights, int(config.rangeModel));
        check.missed += transparentMisses(*r.assignment, refs, f.planesShadedBy(drawsScene), p,
                                          int(config.rangeModel));
      } else {
        check.missedCounted = false;
      }
      out.check = check;
    }
    return out;
  });
}

std::vector<TechniqueDescription> listTechniques() {
  std::vector<TechniqueDescription> out;
  for (const TechniqueInfo& t : techniqueRegistry())
    out.push_back({t.name, t.description, t.drawsScene, t.reusesShadowMaps, t.hybridTransparency,
                   t.multisamples});
  return out;
}

}  // namespace ts
