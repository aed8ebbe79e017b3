#pragma once
// kernels/gbuffer_codecs.h compiled as C++: the G-buffer's per-element decoders in ts::codecs, the
// same source text the kernels decode with (kernels/gbuffer.h), so the host decode (the reference's
// input, `--dump`'s host channels) cannot drift from the device's. The OpenCL built-ins it calls
// are std::'s float overloads here: fmax and fabs are exact on both; exp2 is the one OpenCL allows
// 3 ulp of error, and the host keeps std::exp2(float), as it always has (the tests allow the
// device its 3 ulp).
#include <cmath>
#include <cstdint>

#include <glm/glm.hpp>

namespace ts::codecs {

using uint = uint32_t;
inline float fmax(float a, float b) { return std::fmax(a, b); }
inline float fabs(float x) { return std::fabs(x); }
inline float exp2(float x) { return std::exp2(x); }

#define TS_FLOAT3 glm::vec3
#define TS_MAKE_FLOAT3(x, y, z) glm::vec3((x), (y), (z))
#include "kernels/gbuffer_codecs.h"
#undef TS_FLOAT3
#undef TS_MAKE_FLOAT3

}  // namespace ts::codecs
