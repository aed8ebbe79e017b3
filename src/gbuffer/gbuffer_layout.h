#pragma once
// Storage layouts of the G-buffer on the device, and the host decoder: the kernels' own element
// decoders (kernels/gbuffer_codecs.h, through gbuffer_codecs.h), put together as kernels/gbuffer.h
// does, so the reference shades the same values the kernels read. Adding a layout: the steps are
// at the layout table in gbuffer_layout.cpp.
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "gbuffer/gbuffer.h"
#include "scene/scene_features.h"
#include "util/enum_names.h"

namespace ts {

// Storage precisions. fp32: float4 planes. fp16: half4 planes. packed: octahedral normal in
// 2 x snorm16, unorm8 diffuse RGBA, unorm8 specular RGB + a shininess byte (metallic-roughness:
// a roughness byte), half4 emissive. Depth is float32 in every layout. Which planes a layout has
// depends on the scene's features (EncodedGBuffer); with every plane, Blinn-Phong takes 68, 36 and
// 24 B/pixel. Table and error bounds: docs/accuracy.md.
enum class GBufferFormat { FP32, FP16, PACKED };
const EnumNames<GBufferFormat>& gbufferFormatNames();  // "fp32", "fp16", "packed"

// Half's largest finite value: fp16 planes (and the packed emissive) clamp to +-kMaxHalf instead
// of storing inf (docs/accuracy.md).
constexpr float kMaxHalf = 65504.0f;

std::string toString(GBufferFormat format);
// "fp32" | "fp16" | "packed"; throws ts::Error naming them otherwise.
GBufferFormat parseGBufferFormat(const std::string& name);
// OpenCL build option selecting the layout's decoder in kernels/gbuffer.h ("" for fp32).
std::string gbufferKernelDefines(GBufferFormat format);

// The planes exactly as they are uploaded (see kernels/gbuffer.h for the layout). Depth, normal and
// diffuse are always there; the specular plane only for Blinn-Phong with a specular term (ks +
// shininess) or packed metallic-roughness (roughness byte; fp32/fp16 keep roughness in the
// normal's w, metallic in the diffuse's w), the emissive plane only with emission. An absent
// plane is an empty vector.
struct EncodedGBuffer {
  GBufferFormat format = GBufferFormat::FP32;
  ShadingModel model = ShadingModel::BlinnPhong;
  bool hasSpecular = true, hasEmissive = true;  // the features the planes were chosen for
  int width = 0;
  int height = 0;
  std::vector<float> depth;
  // fp32/fp16: 4 elements per pixel each. packed: one uint per pixel for normal, diffuse and
  // (Blinn-Phong) specular, one byte for the metallic-roughness specular plane, half4 emissive.
  std::vector<uint8_t> normal, diffuse, specular, emissive;

  size_t pixelCount() const { return size_t(width) * size_t(height); }
  bool hasSpecularPlane() const;
  size_t bytesPerPixel() const;  // the planes present, together
  // OpenCL build options selecting the matching decoder in kernels/gbuffer.h (the precision; the
  // planes present follow from the features' own defines).
  std::string kernelDefines() const;
};

// Encodes the planes `features` needs (model: the G-buffer's own, which must equal
// features.model).
EncodedGBuffer encode(const GBuffer& gbuffer, GBufferFormat format, const SceneFeatures& features);
// Every plane, for the G-buffer's model (the general layout).
EncodedGBuffer encode(const GBuffer& gbuffer, GBufferFormat format);

// The packed layout's element codecs (kernels/gbuffer.h, TS_GBUFFER_PACKED), exposed for tests:
// the encoders (host only) and the decoders of kernels/gbuffer_codecs.h.
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
// Documented bounds (docs/accuracy.md; checked by tests/gbuffer/gbuffer_layout_test.cpp).
// Normal: half the diagonal of a 1/32767 lattice cell, stretched by up to ~2 where the octahedron
// is farthest from the sphere; 4.31e-5 measured over 2e7 random normals (plain round-to-nearest
// would give 6.5e-5).
constexpr double kMaxNormalErrorRad = 4.5e-5;
constexpr double kMaxUnorm8Error = 0.5 / 255.0 + 1e-7;  // half a step, plus float decode rounding
constexpr double kMaxShininessRelError = 0.0151;  // 2^(11/510) - 1 = 1.506%, plus float rounding
}  // namespace packed

// A decoded pixel in double precision, from the stored values: ts_surface of kernels/gbuffer.h,
// with the emission and the ambient albedo apart (the reference forms the base itself).
struct SurfaceD {
  glm::dvec3 P{0.0}, N{0.0}, V{0.0};
  glm::dvec3 kd{0.0}, ks{0.0};  // the colours of the weights wd and ws (kernels/shading.h)
  double gloss = 1.0;           // Blinn-Phong shininess, metallic-roughness alpha
  double viewTerm = 1.0;        // metallic-roughness: Smith view term
  glm::dvec3 cDiff{0.0};        // the colour the ambient term lights
  glm::dvec3 ke{0.0};
};

// The four planes after depth, in the kernels' argument order.
enum class GBufferPlane { Normal, Diffuse, Specular, Emissive };

// Pixel i's element of `plane` decoded as the kernels decode it but before the normal's
// renormalisation: fp32/fp16 the stored float4 (half widened exactly); packed the octahedral
// vector (w = 0), unorm8 colours (diffuse rgba; specular rgb + the decoded shininess in w), half4
// emissive. Metallic-roughness's specular element is (roughness, 0, 0, 0), wherever the layout
// keeps it; an absent plane gives what a material without the term has (specular (0,0,0,1),
// emissive 0). encode() of these values in the same layout gives back the stored bits (checked by
// GBufferImport tests), which is what makes a `--dump` round-trip exactly.
glm::vec4 decodeStored(const EncodedGBuffer& gbuffer, GBufferPlane plane, size_t i);

// Returns false for background. Mirrors ts_load_surface (kernels/gbuffer.h).
bool decodeSurface(const EncodedGBuffer& gbuffer, const CameraIntrinsics& camera, int x, int y,
                   SurfaceD& surface);

// The rest of ts_load_surface once the planes are decoded (surface.P and V already set): the
// normal renormalised, the model's colour weights, gloss and view term, the emission. Also what
// the reference shades a transparent fragment's planes with (reference/transparent_composite.h).
void surfaceTerms(glm::vec4 normal, glm::vec4 diffuse, glm::vec4 specular, glm::vec4 emissive,
                  ShadingModel model, bool hasSpecular, SurfaceD& surface);

}  // namespace ts
