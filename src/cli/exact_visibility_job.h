#pragma once
// `render --exact-visibility`: the exact visibility of every (pixel, shadow-casting light) pair
// of the frame and the maps against it (visibility/shadow_error.h), its image and its stats.json
// record.
#include "tileshade/tileshade.h"
#include "visibility/shadow_error.h"

namespace ts {

// Throws ts::Error (one line) for a frame without the scene's triangles (an imported G-buffer)
// or without a shadow-casting light.
ExactVisibilityResult exactVisibility(const Frame& frame);

}  // namespace ts
