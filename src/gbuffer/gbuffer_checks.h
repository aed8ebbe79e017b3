#pragma once
// The value checks every G-buffer that comes from outside goes through: the files of
// `--gbuffer-in` (gbuffer_import.cpp, per channel) and the planes an engine hands to the API
// (checkGBufferValues). One set of rules and messages, so both refuse the same values the same way.
#include <string>

#include <glm/glm.hpp>

#include "gbuffer/gbuffer.h"
#include "gbuffer/gbuffer_layout.h"
#include "scene/shading_range.h"

namespace ts {

// Values in messages to full precision: 1.0000001 must not read as 1.
std::string fullPrecision(double v);
// "pixel (x, y)"
std::string pixelText(int x, int y);

// Geometry nearer than the near plane cannot come from a camera with that near plane, and the
// culling clips light volumes there: every technique but brute would drop the lights that reach
// it. Within float rounding of the plane (kNearPlaneTolerance) a surface is on it.
constexpr double kNearPlaneTolerance = 1e-5;
inline bool inFrontOfNearPlane(float depth, float znear) {
  return double(depth) < double(znear) * (1.0 - kNearPlaneTolerance);
}

// Throws "<where>: <what> is NaN|infinite at pixel (x, y)" when v is not finite.
void checkFiniteValue(const std::string& where, const std::string& what, float v, int x, int y);
// Throws "<where>: <what> is V at pixel (x, y), below 0": colours and material terms.
void checkNotNegative(const std::string& where, const std::string& what, float v, int x, int y);
// The kernels renormalise the normal, but the layouts store it as given: fp16 turns x1e6 into inf
// and x1e-40 into 0. Lengths in [0.5, 2] hold every layout's normals (packed dumps store octahedral
// vectors, length >= 1/sqrt(3)) and renormalise safely; anything else is a renderer's mistake.
void checkNormalLength(const std::string& where, glm::vec3 n, int x, int y);

// Every geometry pixel (depth > 0) of `g` as readGBufferFiles checks the values it reads: depth
// finite and not in front of `znear`, every plane value finite, colours not negative, normals of
// about unit length; background is depth 0 exactly (a negative or NaN depth is an error). Returns
// the surfaces' shading-range terms (the caller adds the lights and calls checkShadingRange).
// `where` starts every message ("host G-buffer").
ShadingRangeTerms checkGBufferValues(const GBuffer& g, float znear, const std::string& where);

}  // namespace ts
