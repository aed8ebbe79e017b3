#include "render/pipeline_options.h"

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

}  // namespace ts
