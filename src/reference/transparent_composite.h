#pragma once
// The reference of a frame with transparent surfaces (--blend blend): each captured transparent
// fragment shaded in double with kernels/shading.h (every light, as shadeReference shades a
// pixel), then composited per pixel in the forward pass's order (draw order, then primitive
// order) with premultiplied "over" onto the opaque reference: c = alpha * shade + (1 - alpha) c.
#include <vector>

#include <glm/glm.hpp>

#include "gbuffer/gbuffer_layout.h"
#include "reference/reference.h"
#include "shading/shading_cpu.h"
#include "shading/transparent_fragments.h"
#include "shading/view_lights.h"

namespace ts {

// `reference`: the opaque surfaces' (shadeReference of `gbuffer`, which holds no transparent
// surface), composited in place; its contributing pairs and peak are updated (the peak over the
// composite). model: the range model; the fragments are shaded with the G-buffer's shading model
// and terms (its specular and emissive planes, or none). Throws ts::Error
// for a fragment outside the image, or with shadow-casting lights (the forward passes shade no
// shadows, so neither does this).
// The fragment's surface as decodeSurface gives a pixel's: its own position (the forward pass's
// interpolated one, widened), its planes through surfaceTerms with the G-buffer's terms.
SurfaceD transparentSurface(const TransparentFragment& f, const EncodedGBuffer& gbuffer);

// The shading point of a fragment's surface, and punctual light i's double contribution there
// (no shadows), as compositeTransparent sums them (and the transparent `missed` tests them).
shading_d::ts_shading_point transparentShadingPoint(const SurfaceD& s, int shading);
glm::dvec3 transparentPunctualLight(const shading_d::ts_shading_point& p, const SurfaceD& s,
                                    const ViewLights& lights, size_t i, int model, int shading);

void compositeTransparent(ReferenceImage& reference, const std::vector<TransparentFragment>& frags,
                          const ViewLights& lights, glm::vec3 ambient, int model,
                          const EncodedGBuffer& gbuffer);

}  // namespace ts
