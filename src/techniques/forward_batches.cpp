#include "techniques/forward_batches.h"

#include <algorithm>
#include <chrono>
#include <cstdint>

#include "util/error.h"

namespace ts {

ForwardScene& sceneToDraw(const DeviceFrame& frame, const std::string& technique) {
  if (!frame.forward)
    throw Error(technique +
                " draws the scene: it needs a frame rasterized with --raster gl (not the "
                "software rasterizer or an imported G-buffer)");
  return *frame.forward;
}

IndexLists findBatchLights(ForwardScene& scene, const ViewLights& lights, double& ms) {
  const auto t0 = std::chrono::steady_clock::now();
  IndexLists lists = batchLightLists(scene.batchBoxes(), lights);
  ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return lists;
}

void setBatchListCounters(const IndexLists& batchLights, WorkCounters& counters) {
  if (batchLights.size() == 0) return;
  counters.listMin = UINT32_MAX;
  for (uint32_t c : batchLights.counts) counters.listMin = std::min(counters.listMin, c);
  counters.listMax = batchLights.longest();
  counters.listMean = double(batchLights.items.size()) / double(batchLights.size());
}

void addShadowUploadRow(const ViewLights& lights, const ForwardImage& drawn,
                        std::vector<KernelTime>& kernels) {
  if (lights.hasShadows()) kernels.push_back({"shadow_upload", drawn.shadowUploadMs, 1});
}

void addGridForwardPass(const ViewLights& lights, const ForwardImage& drawn, double gridReadMs,
                        FrameResult& result) {
  result.kernels.push_back({"grid_copy", gridReadMs + drawn.uploadMs, 1});
  result.kernels.push_back({"forward", drawn.drawMs, 1});
  addShadowUploadRow(lights, drawn, result.kernels);
  if (drawn.transparentDraws > 0)
    result.kernels.push_back({"transparent", drawn.transparentMs, int(drawn.transparentDraws)});
  result.totalMs = 0.0;
  for (const KernelTime& k : result.kernels) result.totalMs += k.ms;
  result.image = drawn.image;
}

LightAssignment batchAssignment(const IndexLists& batchLights, const ForwardImage& drawn) {
  LightAssignment a;
  a.binOffset = batchLights.offsets;
  a.binCount = batchLights.counts;
  a.binLights = batchLights.items;
  a.pixelBin = drawn.pixelBatch;
  if (drawn.transparentDraws > 0) {
    FragmentLists glass;
    glass.binOffset = batchLights.offsets;
    glass.binCount = batchLights.counts;
    glass.binLights = batchLights.items;
    glass.byBatch = true;
    a.transparent = std::move(glass);
  }
  return a;
}

FragmentLists gridFragmentLists(const ForwardLightGrid& grid) {
  FragmentLists lists;
  lists.binOffset = grid.offsets;
  lists.binCount = grid.counts;
  lists.binLights = grid.lights;
  lists.tileW = grid.tileW;
  lists.tileH = grid.tileH;
  lists.tilesX = grid.tilesX;
  lists.slices = grid.slices;
  lists.sliceNear = grid.sliceNear;
  lists.sliceScale = grid.sliceScale;
  return lists;
}

}  // namespace ts
