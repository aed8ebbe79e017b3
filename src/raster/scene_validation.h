#pragma once
// The checks both rasterizers run before touching a scene's arrays.
#include "scene/scene.h"

namespace ts {

// Throws ts::Error naming the scene and the bad value: an index count that is not a multiple of
// 3, a vertex, material or texture index out of range, or a per-triangle material list of the
// wrong length; and, through refuseBlendedMaterials, a scene that draws an alphaMode BLEND
// material unless the scene composites them (Scene::blendComposited, --blend blend).
void validateForRaster(const Scene& scene);

// Whether some triangle of the scene is drawn with an alphaMode BLEND material.
bool drawsBlendedMaterials(const Scene& scene);

// Throws ts::Error naming the alphaMode BLEND materials that the scene's triangles are drawn with:
// drawing them opaque would hide them (issue #17). `--blend` (applyBlendPolicy,
// scene/scene_loader.h) opts in to compositing them (blend) or drawing them opaque or masked.
void refuseBlendedMaterials(const Scene& scene);

}  // namespace ts
