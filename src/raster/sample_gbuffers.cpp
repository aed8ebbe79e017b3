#include "raster/sample_gbuffers.h"

namespace ts {

SampleGBuffers::SampleGBuffers(ForwardScene& scene, const SceneFeatures& features)
    : scene_(scene), features_(features) {}

const std::vector<GBuffer>& SampleGBuffers::drawn() {
  if (gbuffers_.empty()) {
    RasterOptions raster;  // as prepareFrame rasterizes the frame
    raster.model = features_.model;
    raster.normalMaps = features_.normalMaps;
    gbuffers_ = scene_.sampleGBuffers(raster);
  }
  return gbuffers_;
}

const std::vector<EncodedGBuffer>& SampleGBuffers::fp32() {
  if (fp32_.empty())
    for (const GBuffer& g : drawn()) fp32_.push_back(encode(g, GBufferFormat::FP32));
  return fp32_;
}

const std::vector<EncodedGBuffer>& SampleGBuffers::like(const EncodedGBuffer& frame) {
  std::vector<EncodedGBuffer>& planes = like_[{frame.format, frame.hasSpecular, frame.hasEmissive}];
  if (planes.empty()) {
    // The features that choose encode's planes (gbuffer_layout.cpp): specular and emissive.
    SceneFeatures features = SceneFeatures::general(frame.model);
    features.specular = frame.hasSpecular;
    features.emissive = frame.hasEmissive;
    for (const GBuffer& g : drawn()) planes.push_back(encode(g, frame.format, features));
  }
  return planes;
}

}  // namespace ts
