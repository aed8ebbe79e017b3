#pragma once
// `missed` over the transparent fragments (--blend blend; docs/accuracy.md): the (fragment,
// light) pairs whose double contribution (shaded as compositeTransparent shades the fragment) is
// non-zero while the light is absent from the list the technique used for that fragment, found
// by the technique's rule (FragmentLists, shading/light_assignment.h): the same meaning as
// countMissedContributions has for the opaque pixels. Directional lights are never culled.
#include <cstdint>
#include <vector>

#include "gbuffer/gbuffer_layout.h"
#include "shading/light_assignment.h"
#include "shading/transparent_fragments.h"
#include "shading/view_lights.h"

namespace ts {

// The bin whose list fragment f shaded. Throws ts::Error where the rule cannot place it (a
// fragment without a batch, outside the tiles, a bin past the lists).
size_t transparentFragmentBin(const FragmentLists& lists, const TransparentFragment& f);

// model: the range model (TS_MODEL_WINDOWED / _PHYSICAL); the fragments' terms those of
// `gbuffer` (the planes the technique's reference shades).
uint64_t countMissedTransparent(const FragmentLists& lists,
                                const std::vector<TransparentFragment>& frags,
                                const ViewLights& lights, int model, const EncodedGBuffer& gbuffer);

}  // namespace ts
