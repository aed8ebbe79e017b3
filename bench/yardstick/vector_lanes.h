// The lane types of the yardstick's SIMD form and the functions kernels/shading.h calls on them:
// in C++ what kernels/lanes.h's floatN is in OpenCL C. The types are GCC/Clang vector extensions
// (`vector_size`), whose arithmetic and comparisons work lane by lane, and whose `c ? a : b`
// selects per lane, as OpenCL's does; so shading.h's lanes compile here as they are (TS_LANE =
// one of these types; TS_ANY = any(); TS_CAST broadcasts a scalar). The square root comes from
// the vector instruction, the specular power from glibc's vector math library (libmvec's exp2f
// and log2f), so no light evaluation leaves the vector registers.
#pragma once

#include <cmath>
#include <type_traits>

#if defined(__x86_64__)
#include <immintrin.h>
#endif

namespace yardstick {

typedef float Floats8 __attribute__((vector_size(32)));
typedef int Mask8 __attribute__((vector_size(32)));
typedef float Floats16 __attribute__((vector_size(64)));
typedef int Mask16 __attribute__((vector_size(64)));

template <class V>
struct LaneCount : std::integral_constant<int, 0> {};
template <>
struct LaneCount<Floats8> : std::integral_constant<int, 8> {};
template <>
struct LaneCount<Floats16> : std::integral_constant<int, 16> {};
template <class V>
using IfLanes = std::enable_if_t<(LaneCount<V>::value > 0), V>;

// TS_CAST(type, x): a vector type gets x in every lane; a scalar type is an ordinary cast.
template <class T, class U>
inline T cast(U x) {
  if constexpr (LaneCount<T>::value > 0) {
    // A vector of ones times the scalar: one broadcast (a lane-by-lane fill is not folded into
    // one), and exact for every x, -0 and NaN included.
    return (T{} + 1.0f) * float(x);
  } else {
    return T(x);
  }
}

// "Any lane set" of a comparison's mask (each lane 0 or -1): one mask test on AVX/AVX-512.
inline bool any(Mask8 m) {
#if defined(__AVX__)
  return !_mm256_testz_si256(__m256i(m), __m256i(m));
#else
  int r = 0;
  for (int i = 0; i < 8; ++i) r |= m[i];
  return r != 0;
#endif
}
inline bool any(Mask16 m) {
#if defined(__AVX512F__)
  return _mm512_test_epi32_mask(__m512i(m), __m512i(m)) != 0;
#else
  int r = 0;
  for (int i = 0; i < 16; ++i) r |= m[i];
  return r != 0;
#endif
}

// The scalar forms' choices (yardstick.cpp), lane by lane: max/min keep b where a is NaN, clamp is
// std::min(std::max(x, lo), hi).
template <class V>
inline IfLanes<V> max(V a, V b) {
  return a > b ? a : b;
}
template <class V>
inline IfLanes<V> min(V a, V b) {
  return a < b ? a : b;
}
template <class V>
inline IfLanes<V> clamp(V x, V lo, V hi) {
  V m = x < lo ? lo : x;
  return hi < m ? hi : m;
}

inline Floats8 sqrt(Floats8 x) {
#if defined(__AVX__)
  return Floats8(_mm256_sqrt_ps(__m256(x)));
#else
  for (int i = 0; i < 8; ++i) x[i] = std::sqrt(x[i]);
  return x;
#endif
}
inline Floats16 sqrt(Floats16 x) {
#if defined(__AVX512F__)
  // The masked form with every lane set: the same instruction, without _mm512_sqrt_ps's
  // "undefined" source operand (which GCC 12 warns about).
  return Floats16(_mm512_mask_sqrt_ps(__m512(x), __mmask16(0xffff), __m512(x)));
#else
  for (int i = 0; i < 16; ++i) x[i] = std::sqrt(x[i]);
  return x;
#endif
}
template <class V>
inline IfLanes<V> rsqrt(V x) {
  return 1.0f / sqrt(x);
}

// exp2 and log2 lane by lane: libmvec's AVX-512 (16 lanes) or AVX2 (8 lanes) variants where the
// build targets them (YARDSTICK_LIBMVEC: CMake found libmvec), else the scalar functions.
#if defined(YARDSTICK_LIBMVEC) && defined(__AVX2__)
extern "C" __m256 _ZGVdN8v_exp2f(__m256);
extern "C" __m256 _ZGVdN8v_log2f(__m256);
#if defined(__AVX512F__)
extern "C" __m512 _ZGVeN16v_exp2f(__m512);
extern "C" __m512 _ZGVeN16v_log2f(__m512);
#endif
#endif

inline Floats8 exp2(Floats8 x) {
#if defined(YARDSTICK_LIBMVEC) && defined(__AVX2__)
  return Floats8(_ZGVdN8v_exp2f(__m256(x)));
#else
  for (int i = 0; i < 8; ++i) x[i] = std::exp2(x[i]);
  return x;
#endif
}
inline Floats8 log2(Floats8 x) {
#if defined(YARDSTICK_LIBMVEC) && defined(__AVX2__)
  return Floats8(_ZGVdN8v_log2f(__m256(x)));
#else
  for (int i = 0; i < 8; ++i) x[i] = std::log2(x[i]);
  return x;
#endif
}
#if defined(YARDSTICK_LIBMVEC) && defined(__AVX512F__)
inline Floats16 exp2(Floats16 x) { return Floats16(_ZGVeN16v_exp2f(__m512(x))); }
inline Floats16 log2(Floats16 x) { return Floats16(_ZGVeN16v_log2f(__m512(x))); }
#else
// Two halves of 8 lanes.
template <Floats8 (*F)(Floats8)>
inline Floats16 byHalves(Floats16 x) {
  Floats8 lo, hi;
  for (int i = 0; i < 8; ++i) lo[i] = x[i], hi[i] = x[i + 8];
  lo = F(lo);
  hi = F(hi);
  for (int i = 0; i < 8; ++i) x[i] = lo[i], x[i + 8] = hi[i];
  return x;
}
inline Floats16 exp2(Floats16 x) { return byHalves<exp2>(x); }
inline Floats16 log2(Floats16 x) { return byHalves<log2>(x); }
#endif

// The scalar form's power (yardstick.cpp's pow: exp2(s log2 x), 0 below FLT_MIN, 1 for s = 0),
// lane by lane.
template <class V>
inline IfLanes<V> pow(V x, V s) {
  V p = exp2(s * log2(x));
  p = x >= 1.17549435e-38f ? p : V{};
  return s == 0.0f ? cast<V>(1.0f) : p;
}

}  // namespace yardstick
