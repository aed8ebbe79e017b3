#pragma once
// kernels/shading.h and kernels/culling.h compiled as C++: ts::shading_d (double, the reference)
// and ts::shading_f (float, to compare arithmetic with the kernels on the host). The same source
// text as the kernels, so the model cannot drift between device and reference.
#include <algorithm>
#include <cmath>

#include <glm/glm.hpp>

#define TS_MAKE3(x, y, z) TS_REAL3((x), (y), (z))
#define TS_MAKE4(x, y, z, w) TS_REAL4((x), (y), (z), (w))
// kernels/shadows.h reads the float face table and atlas the kernels get, widened to TS_REAL.
#define TS_SHADOW_FACES const glm::vec4*
#define TS_SHADOW_ATLAS const float*
#define TS_SHADOW_FACE(t, i) TS_REAL4((t)[i])
#define TS_SHADOW_TEXEL(a, i) TS_REAL((a)[i])

namespace ts {

namespace shading_d {
inline double sqrt(double x) { return std::sqrt(x); }
inline double rsqrt(double x) { return 1.0 / std::sqrt(x); }
inline double pow(double x, double y) { return std::pow(x, y); }
inline double max(double a, double b) { return a > b ? a : b; }
inline double clamp(double x, double lo, double hi) { return std::min(std::max(x, lo), hi); }
inline double min(double a, double b) { return a < b ? a : b; }
inline double floor(double x) { return std::floor(x); }
inline double dot(const glm::dvec3& a, const glm::dvec3& b) { return glm::dot(a, b); }
#define TS_REAL double
#define TS_REAL3 glm::dvec3
#define TS_REAL4 glm::dvec4
#include "kernels/shading.h"
#include "kernels/culling.h"
#include "kernels/shadows.h"
#undef TS_SHADOWS_H
#undef TS_REAL
#undef TS_REAL3
#undef TS_REAL4
#undef TS_LANE
#undef TS_ANY
}  // namespace shading_d

namespace shading_f {
inline float sqrt(float x) { return std::sqrt(x); }
inline float rsqrt(float x) { return 1.0f / std::sqrt(x); }
inline float pow(float x, float y) { return std::pow(x, y); }
inline float max(float a, float b) { return a > b ? a : b; }
inline float clamp(float x, float lo, float hi) { return std::min(std::max(x, lo), hi); }
inline float min(float a, float b) { return a < b ? a : b; }
inline float floor(float x) { return std::floor(x); }
inline float dot(const glm::vec3& a, const glm::vec3& b) { return glm::dot(a, b); }
#define TS_REAL float
#define TS_REAL3 glm::vec3
#define TS_REAL4 glm::vec4
#include "kernels/shading.h"
#include "kernels/culling.h"
#include "kernels/shadows.h"
#undef TS_SHADOWS_H
#undef TS_REAL
#undef TS_REAL3
#undef TS_REAL4
#undef TS_LANE
#undef TS_ANY
}  // namespace shading_f

}  // namespace ts
