#pragma once
// Storage layouts of the G-buffer on the device, and the host decoder that mirrors
// kernels/gbuffer.h exactly (the reference shades the same values the kernels read).
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "raster/gbuffer.h"

namespace ts {

// fp32: float4 planes (68 B/pixel). fp16: half4 planes (36 B/pixel). packed (24 B/pixel):
// octahedral normal in 2 x snorm16, unorm8 diffuse RGBA, unorm8 specular RGB + a shininess byte,
// half4 emissive. Depth is float32 in every layout. Error bounds: docs/accuracy.md.
enum class GBufferFormat { FP32, FP16, PACKED };

// Half's largest finite value: fp16 planes (and the packed emissive) clamp to +-kMaxHalf instead
// of storing inf (docs/accuracy.md).
constexpr float kMaxHalf = 65504.0f;

std::string toString(GBufferFormat format);
// "fp32" | "fp16" | "packed"; throws ts::Error otherwise.
GBufferFormat parseGBufferFormat(const std::string& name);
// OpenCL build option selecting the layout's decoder in kernels/gbuffer.h ("" for fp32).
std::string gbufferKernelDefines(GBufferFormat format);

// The planes exactly as they are uploaded (see kernels/gbuffer.h for the layout).
struct EncodedGBuffer {
  GBufferFormat format = GBufferFormat::FP32;
  int width = 0;
  int height = 0;
  std::vector<float> depth;
  // fp32/fp16: 4 elements per pixel each. packed: one uint per pixel for normal, diffuse and
  // specular, half4 for emissive.
  std::vector<uint8_t> normal, diffuse, specular, emissive;

  size_t pixelCount() const { return size_t(width) * size_t(height); }
  size_t bytesPerPixel() const;  // all planes together
  // OpenCL build options selecting the matching decoder in kernels/gbuffer.h.
  std::string kernelDefines() const;
};

EncodedGBuffer encode(const GBuffer& gbuffer, GBufferFormat format);

// The packed layout's element codecs (kernels/gbuffer.h, TS_GBUFFER_PACKED), exposed for tests.
namespace packed {
// Octahedral encoding, x in bits 0-15 and y in bits 16-31 (snorm16, scale 32767). Of the four
// lattice points around the exact octahedral coordinates it picks the one whose decoded normal is
// closest to `n` (angular error <= kMaxNormalErrorRad). Zero or non-finite input encodes +Z.
uint32_t encodeNormal(glm::vec3 n);
// ts_decode_normal before its normalize(): the float vector the kernel computes.
glm::vec3 decodeNormalUnnormalized(uint32_t v);
// unorm8: round(clamp(c, 0, 1) * 255); decoded as float(byte) / 255.0f.
uint8_t encodeUnorm8(float c);
float decodeUnorm8(uint8_t b);
// Shininess byte b = round(255 log2(clamp(s, 1, 2048)) / 11); decoded s = exp2(b * (11/255)),
// in float as the kernel computes it.
uint8_t encodeShininess(float s);
float decodeShininess(uint8_t b);
// Documented bounds (docs/accuracy.md; checked by tests/gbuffer_layout_test.cpp).
// Normal: half the diagonal of a 1/32767 lattice cell, stretched by up to ~2 where the octahedron
// is farthest from the sphere; 4.31e-5 measured over 2e7 random normals (plain round-to-nearest
// would give 6.5e-5).
constexpr double kMaxNormalErrorRad = 4.5e-5;
constexpr double kMaxUnorm8Error = 0.5 / 255.0 + 1e-7;  // half a step, plus float decode rounding
constexpr double kMaxShininessRelError = 0.0151;  // 2^(11/510) - 1 = 1.506%, plus float rounding
}  // namespace packed

// A decoded pixel in double precision, from the stored values.
struct SurfaceD {
  glm::dvec3 P{0.0}, N{0.0}, V{0.0}, kd{0.0}, ks{0.0}, ke{0.0};
  double shininess = 0.0;
};

// Returns false for background. Mirrors ts_load_surface (kernels/gbuffer.h).
bool decodeSurface(const EncodedGBuffer& gbuffer, const CameraIntrinsics& camera, int x, int y,
                   SurfaceD& surface);

}  // namespace ts
