#include "render/pipeline_options.h"

#include <string>

#include "util/error.h"

namespace ts {

TechniqueConfig PipelineOptions::techniqueConfig(const SceneFeatures& sceneFeatures) const {
  TechniqueConfig t;
  t.format = format;
  t.features = sceneFeatures;
  t.tileWidth = tileWidth;
  t.tileHeight = tileHeight;
  t.clusterSlices = clusterSlices;
  t.culling = culling;
  t.spotCulling = spotCulling;
  t.depthSplit = depthSplit;
  t.math = math;
  t.lanes = lanes;
  t.shadowStorage = shadowStorage;
  return t;
}

SceneOptions PipelineOptions::sceneOptions() const {
  SceneOptions s;
  s.lightSet = lightSet;
  s.seed = seed;
  s.lightCount = lightCount;
  s.lightRange = lightRange;
  s.variant = variant;
  s.normalMaps = normalMaps;
  s.shadows = shadows;
  s.blend = blend;
  return s;
}

void checkMsaa(int samples, RasterBackend raster) {
  if (samples != 1 && samples != 2 && samples != 4 && samples != 8)
    throw Error("--msaa " + std::to_string(samples) + ": samples a pixel must be 1, 2, 4 or 8");
  if (samples > 1 && raster != RasterBackend::Gl)
    throw Error("--msaa " + std::to_string(samples) +
                " needs --raster gl: the forward techniques draw multisampled targets in OpenGL "
                "(the software rasterizer has one sample a pixel)");
}

}  // namespace ts
