#pragma once
// How far an fp32 kernel's pixel may lie from the double reference: a first-order bound of the
// rounding, pixel by pixel, from the same decoded G-buffer and view-space lights the reference
// shades. docs/hard-cases.md derives it; `tileshade check` passes a run when every pixel is
// within it. The bound grows where the model itself is ill-conditioned in fp32 (a light closer to
// a surface point than the rounding of that point's position, a half vector near zero length),
// so those pixels are held to what fp32 can resolve rather than to a fixed fraction of the peak.
// Blinn-Phong point lights have the analytic bound of docs/hard-cases.md; spot and directional
// lights and the metallic-roughness model a measured one (the term's largest change when each
// input moves by its fp32 rounding).
#include <vector>

#include <glm/glm.hpp>

#include "gbuffer/gbuffer_layout.h"
#include "techniques/device_frame.h"

namespace ts {

// Per pixel (row-major), the bound on max over channels of |kernel - reference| for the windowed
// (model 0) or physical (1) model. Background pixels get 0.
std::vector<double> fp32ErrorBound(const EncodedGBuffer& gbuffer, const CameraIntrinsics& camera,
                                   const ViewLights& lights, glm::vec3 ambient, int model);

}  // namespace ts
