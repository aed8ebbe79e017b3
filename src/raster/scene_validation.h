#pragma once
// The checks both rasterizers run before touching a scene's arrays.
#include "scene/scene.h"

namespace ts {

// Throws ts::Error naming the scene and the bad value: an index count that is not a multiple of
// 3, a vertex, material or texture index out of range, or a per-triangle material list of the
// wrong length.
void validateForRaster(const Scene& scene);

}  // namespace ts
