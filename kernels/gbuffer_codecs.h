/*
 * The G-buffer's per-element decoders, written once in the common subset of OpenCL C and C++ (as
 * kernels/shading.h is): kernels/gbuffer.h reads its planes with them, and the host decodes with
 * the same text (src/gbuffer/gbuffer_codecs.h compiles it as C++ for gbuffer_layout.cpp there),
 * so what the reference shades cannot drift from what the kernels read. Tests decode every stored
 * code on the device (decode_gbuffer, kernels/dump.cl) against the host
 * (AccuracyKnobs.PackedDecodeMatchesTheHostForEveryCode, MetallicRoughnessDecode), and
 * GBufferCodecs (tests/gbuffer/gbuffer_codecs_test.cpp) fails on a decoder written anywhere else.
 *
 * The includer defines first:
 *   uint                  32-bit unsigned (built in in OpenCL; uint32_t in C++)
 *   TS_FLOAT3             a 3-vector of float with members x, y, z (float3; glm::vec3)
 *   TS_MAKE_FLOAT3(x,y,z) builds one
 * and makes fmax, fabs and exp2 visible for float (OpenCL has them built in; the C++ wrapper maps
 * them to std::, whose float results equal the device's: fmax and fabs are exact, and exp2 is the
 * one place OpenCL allows error (3 ulp), which the tests allow for).
 *
 * Only decoders: the encoders run on the host alone (they round in double, and the normal encoder
 * searches the lattice for the code this decoder turns into the closest normal), in
 * src/gbuffer/gbuffer_layout.cpp. Each decoder is exactly one expression per component, in the
 * order both compilers evaluate it; its divisions are by constants, correctly rounded on the host
 * and, without -cl-fast-relaxed-math, on the devices the tests run on (PoCL, Oclgrind).
 */
#ifndef TS_GBUFFER_CODECS_H
#define TS_GBUFFER_CODECS_H

#ifndef TS_MAKE_FLOAT3
#error "define uint, TS_FLOAT3 and TS_MAKE_FLOAT3 before including gbuffer_codecs.h"
#endif

/* unorm8: byte b (in the low 8 bits) -> b / 255 in [0, 1]. Colours, metallic, roughness. */
static inline float ts_decode_unorm8(uint b) { return (float)b / 255.0f; }

/* Three unorm8 channels in bits 0-7, 8-15, 16-23 (rgb of a packed colour). */
static inline TS_FLOAT3 ts_decode_unorm8x3(uint v) {
  return TS_MAKE_FLOAT3(ts_decode_unorm8(v & 255u), ts_decode_unorm8((v >> 8) & 255u),
                        ts_decode_unorm8((v >> 16) & 255u));
}

/* Shininess byte b -> s = 2^(11 b/255), 1..2048 (exp2: OpenCL allows 3 ulp). */
static inline float ts_decode_shininess(uint b) { return exp2((float)b * (11.0f / 255.0f)); }

/* Metallic-roughness roughness byte: unorm8. */
static inline float ts_decode_roughness_byte(uint b) { return ts_decode_unorm8(b); }

/* snorm16 in the low 16 bits: s / 32767, clamped to -1 (the code -32768). */
static inline float ts_decode_snorm16(uint bits) {
  return fmax((float)(short)(bits & 0xffffu) / 32767.0f, -1.0f);
}

/* Octahedral normal, x in bits 0-15 and y in bits 16-31 (snorm16), before normalisation: the
 * upper hemisphere is |x| + |y| <= 1, the lower one folded over the diagonals (sign(0) = +1). */
static inline TS_FLOAT3 ts_decode_octahedral(uint v) {
  float ex = ts_decode_snorm16(v);
  float ey = ts_decode_snorm16(v >> 16);
  TS_FLOAT3 n = TS_MAKE_FLOAT3(ex, ey, 1.0f - fabs(ex) - fabs(ey));
  if (n.z < 0.0f) {
    float nx = (1.0f - fabs(ey)) * (ex >= 0.0f ? 1.0f : -1.0f);
    float ny = (1.0f - fabs(ex)) * (ey >= 0.0f ? 1.0f : -1.0f);
    n.x = nx;
    n.y = ny;
  }
  return n;
}

#endif
