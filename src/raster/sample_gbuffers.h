#pragma once
// --msaa: a frame's G-buffer per sample (ForwardScene::sampleGBuffers, the multisampled G-buffer
// pass), drawn at the first use and encoded per layout on demand. Shared by what needs the
// samples: the per-sample references of render's check (api/frame.cpp) and of bench
// (bench/bench_measure.cpp), and `tiled`'s multisampled G-buffer (DeviceFrame::samples).
#include <map>
#include <tuple>
#include <vector>

#include "gbuffer/gbuffer_layout.h"
#include "raster/forward_scene.h"
#include "scene/scene_features.h"

namespace ts {

class SampleGBuffers {
 public:
  // `features`: the frame's, as it was rasterized (model, normal maps). The scene outlives this.
  SampleGBuffers(ForwardScene& scene, const SceneFeatures& features);
  int samples() const { return scene_.samples(); }
  // Every sample's planes with every plane of the model in fp32 (encode(g, FP32)), sample k at
  // element k: what the references of the techniques that draw the scene shade.
  const std::vector<EncodedGBuffer>& fp32();
  // Every sample's planes in the layout of `frame` (its precision and its planes: specular,
  // emissive), as the frame's own G-buffer is encoded: what a G-buffer technique shades.
  const std::vector<EncodedGBuffer>& like(const EncodedGBuffer& frame);

 private:
  const std::vector<GBuffer>& drawn();

  ForwardScene& scene_;
  SceneFeatures features_;
  std::vector<GBuffer> gbuffers_;  // drawn at the first use
  std::vector<EncodedGBuffer> fp32_;
  // By (layout, specular plane, emissive plane).
  std::map<std::tuple<GBufferFormat, bool, bool>, std::vector<EncodedGBuffer>> like_;
};

}  // namespace ts
