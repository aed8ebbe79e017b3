#include "gbuffer/gbuffer_layout.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

// The half <-> float conversions are computed, not looked up, so no libImath symbol is needed.
#ifndef IMATH_HALF_NO_LOOKUP_TABLE
#define IMATH_HALF_NO_LOOKUP_TABLE
#endif
#include <Imath/half.h>

#include "gbuffer/gbuffer_codecs.h"
#include "gbuffer/plane_alloc.h"
#include "shading/shading_cpu.h"
#include "util/error.h"
#include "util/short_text.h"

namespace ts {
namespace {

constexpr size_t kFp32Element = 4 * sizeof(float);     // float4
constexpr size_t kFp16Element = 4 * sizeof(uint16_t);  // half4
constexpr size_t kPackedElement = sizeof(uint32_t);    // one uint (normal, diffuse, specular)

// The layouts, one row each: the build option that selects a layout's decoder in
// kernels/gbuffer.h and the sizes of its elements. A new layout is
//   1. its element codecs: the decoders in kernels/gbuffer_codecs.h (the kernels' and the host's
//      one copy), the encoders in this file (host only; namespace packed shows the pattern);
//   2. a GBufferFormat value (gbuffer_layout.h) with its name;
//   3. a row here;
//   4. in kernels/gbuffer.h, under the row's option, the plane element types and ts_decode_*
//      written with those codecs; here, encode() and load/decodeStored() of the same planes;
//   5. its bounds in docs/accuracy.md ("G-buffer precision"), checked in gbuffer_layout_test.cpp,
//      and a test that decodes every code it stores on the device against the host (as
//      AccuracyKnobs.PackedDecodeMatchesTheHostForEveryCode and MetallicRoughnessDecode do).
struct LayoutRow {
  GBufferFormat format;
  const char* kernelDefine;  // OpenCL build option ("" = the header's default, fp32)
  size_t elementBytes;       // per pixel of the normal, diffuse and (Blinn-Phong) specular planes
  size_t emissiveBytes;      // per pixel of the emissive plane
};
constexpr LayoutRow kLayouts[] = {
    {GBufferFormat::FP32, "", kFp32Element, kFp32Element},
    {GBufferFormat::FP16, "-DTS_GBUFFER_FP16", kFp16Element, kFp16Element},
    {GBufferFormat::PACKED, "-DTS_GBUFFER_PACKED", kPackedElement, kFp16Element},  // half4 HDR
};

const LayoutRow& layoutRow(GBufferFormat format) {
  for (const LayoutRow& row : kLayouts)
    if (row.format == format) return row;
  throw Error("G-buffer format " + std::to_string(int(format)) + " has no layout row");
}
size_t elementBytes(GBufferFormat format) { return layoutRow(format).elementBytes; }
size_t emissiveBytes(GBufferFormat format) { return layoutRow(format).emissiveBytes; }

// The packed layout's uint planes, one element per pixel.
template <typename F>
std::vector<uint8_t> encodePacked(const std::vector<glm::vec4>& plane, size_t pixels, F pack) {
  std::vector<uint8_t> out;
  plane_alloc::assignZeroed(out, pixels * kPackedElement);
  uint32_t* dst = reinterpret_cast<uint32_t*>(out.data());
  for (size_t i = 0; i < pixels; ++i) dst[i] = pack(plane[i]);
  return out;
}

uint32_t loadPacked(const std::vector<uint8_t>& plane, size_t i) {
  uint32_t v;
  std::memcpy(&v, plane.data() + i * kPackedElement, kPackedElement);
  return v;
}

uint32_t packUnorm8x4(const glm::vec4& c) {
  return uint32_t(packed::encodeUnorm8(c.x)) | uint32_t(packed::encodeUnorm8(c.y)) << 8 |
         uint32_t(packed::encodeUnorm8(c.z)) << 16 | uint32_t(packed::encodeUnorm8(c.w)) << 24;
}

// A float as the nearest half (round to nearest even), values beyond half's range clamped to
// +-65504 (kMaxHalf): rounding them would give inf, and an inf in the G-buffer turns shading into
// inf or NaN (0 * inf). Tiny values become half denormals or 0 (documented in docs/accuracy.md).
uint16_t toHalfBits(float v) { return Imath::half(std::clamp(v, -kMaxHalf, kMaxHalf)).bits(); }

std::vector<uint8_t> encodePlane(const std::vector<glm::vec4>& plane, size_t pixels,
                                 GBufferFormat format) {
  std::vector<uint8_t> out;
  if (format == GBufferFormat::FP32) {
    static_assert(sizeof(glm::vec4) == kFp32Element, "glm::vec4 must be 4 packed floats");
    const uint8_t* bytes = reinterpret_cast<const uint8_t*>(plane.data());
    plane_alloc::assignRange(out, bytes, bytes + pixels * kFp32Element);
  } else {
    plane_alloc::assignZeroed(out, pixels * kFp16Element);
    uint16_t* dst = reinterpret_cast<uint16_t*>(out.data());
    for (size_t i = 0; i < pixels; ++i)
      for (int c = 0; c < 4; ++c) dst[4 * i + size_t(c)] = toHalfBits(plane[i][c]);
  }
  return out;
}

// The element at pixel i as the kernels read it (vload4 / vload_half4; both exact). Not for the
// packed uint planes (the packed emissive plane is half4: pass FP16).
glm::vec4 load4(const std::vector<uint8_t>& plane, size_t i, GBufferFormat format) {
  glm::vec4 v;
  if (format == GBufferFormat::FP32) {
    std::memcpy(&v, plane.data() + i * kFp32Element, kFp32Element);
  } else {
    uint16_t bits[4];
    std::memcpy(bits, plane.data() + i * kFp16Element, kFp16Element);
    for (int c = 0; c < 4; ++c) {
      Imath::half h;
      h.setBits(bits[c]);
      v[c] = float(h);
    }
  }
  return v;
}

// OpenCL's normalize: a zero vector comes back unchanged (instead of NaN).
glm::dvec3 normalizeLikeOpenCL(const glm::dvec3& v) {
  double len2 = glm::dot(v, v);
  return len2 > 0.0 ? v / std::sqrt(len2) : v;
}

}  // namespace

namespace packed {

// The decoders are the kernels' own (kernels/gbuffer_codecs.h); the encoders are host-only.
glm::vec3 decodeNormalUnnormalized(uint32_t v) { return codecs::ts_decode_octahedral(v); }

uint32_t encodeNormal(glm::vec3 n) {
  const glm::dvec3 d(n);
  const double l1 = std::abs(d.x) + std::abs(d.y) + std::abs(d.z);
  if (!(l1 > 0.0) || !std::isfinite(l1)) return 0u;  // decodes to +Z
  // Exact octahedral coordinates in [-1, 1]^2; the lower hemisphere folds over the diagonals
  // (sign(+0) = +1, as the decoder's `>= 0` test; sign(-0) = -1: where the fold maps two codes to
  // one direction, only the sign of a zero component tells them apart, and keeping it makes
  // re-encoding a decoded normal give back its code, which `--gbuffer-in` relies on).
  double px = d.x / l1, py = d.y / l1;
  if (d.z < 0.0) {
    double fx = (1.0 - std::abs(py)) * (std::signbit(px) ? -1.0 : 1.0);
    double fy = (1.0 - std::abs(px)) * (std::signbit(py) ? -1.0 : 1.0);
    px = fx;
    py = fy;
  }
  // The four snorm16 lattice points around (px, py); keep the one whose decoded normal (exactly
  // as the kernel decodes it) makes the smallest angle with n. Ties keep the first, which is the
  // nearest lattice point when it is among the best.
  const glm::dvec3 target = d / std::sqrt(glm::dot(d, d));
  const double sx = std::clamp(px, -1.0, 1.0) * 32767.0, sy = std::clamp(py, -1.0, 1.0) * 32767.0;
  const double rx = std::nearbyint(sx), ry = std::nearbyint(sy);
  const double ox = rx == std::floor(sx) ? std::ceil(sx) : std::floor(sx);
  const double oy = ry == std::floor(sy) ? std::ceil(sy) : std::floor(sy);
  uint32_t best = 0u;
  double bestCos = -2.0;
  for (double cx : {rx, ox})
    for (double cy : {ry, oy}) {
      const int ix = int(std::clamp(cx, -32767.0, 32767.0));
      const int iy = int(std::clamp(cy, -32767.0, 32767.0));
      const uint32_t v = uint32_t(uint16_t(int16_t(ix))) | uint32_t(uint16_t(int16_t(iy))) << 16;
      const glm::dvec3 m(decodeNormalUnnormalized(v));
      const double len = std::sqrt(glm::dot(m, m));
      const double c = len > 0.0 ? glm::dot(m, target) / len : -2.0;
      if (c > bestCos) {
        bestCos = c;
        best = v;
      }
    }
  return best;
}

uint8_t encodeUnorm8(float c) {
  if (!(c > 0.0f)) return 0;  // negative, zero or NaN
  if (c >= 1.0f) return 255;
  return uint8_t(std::floor(double(c) * 255.0 + 0.5));  // round half up, in double: exact
}

float decodeUnorm8(uint8_t b) { return codecs::ts_decode_unorm8(b); }

uint8_t encodeShininess(float s) {
  const double c = std::isnan(s) ? 1.0 : std::clamp(double(s), 1.0, 2048.0);
  return uint8_t(std::clamp(std::round(255.0 * std::log2(c) / 11.0), 0.0, 255.0));
}

float decodeShininess(uint8_t b) { return codecs::ts_decode_shininess(b); }

}  // namespace packed

const EnumNames<GBufferFormat>& gbufferFormatNames() {
  static const EnumNames<GBufferFormat> names(
      "G-buffer format", {{GBufferFormat::FP32, "fp32"},
                          {GBufferFormat::FP16, "fp16"},
                          {GBufferFormat::PACKED, "packed", "octahedral normals, unorm8 colours"}});
  return names;
}

std::string toString(GBufferFormat format) { return gbufferFormatNames().name(format); }

GBufferFormat parseGBufferFormat(const std::string& name) {
  return gbufferFormatNames().parse(name);
}

std::string gbufferKernelDefines(GBufferFormat format) { return layoutRow(format).kernelDefine; }

bool EncodedGBuffer::hasSpecularPlane() const {
  if (model == ShadingModel::MetallicRoughness) return format == GBufferFormat::PACKED;
  return hasSpecular;
}

size_t EncodedGBuffer::bytesPerPixel() const {
  size_t bytes = sizeof(float) + 2 * elementBytes(format);  // depth, normal, diffuse
  if (hasSpecularPlane())
    bytes += model == ShadingModel::MetallicRoughness ? 1 : elementBytes(format);
  if (hasEmissive) bytes += emissiveBytes(format);
  return bytes;
}

std::string EncodedGBuffer::kernelDefines() const { return gbufferKernelDefines(format); }

EncodedGBuffer encode(const GBuffer& gbuffer, GBufferFormat format) {
  return encode(gbuffer, format, SceneFeatures::general(gbuffer.model));
}

EncodedGBuffer encode(const GBuffer& gbuffer, GBufferFormat format, const SceneFeatures& features) {
  const size_t n = gbuffer.pixelCount();
  if (gbuffer.depth.size() != n || gbuffer.normal.size() != n || gbuffer.diffuse.size() != n ||
      gbuffer.specular.size() != n || gbuffer.emissive.size() != n)
    throw Error("G-buffer planes do not match its size " + std::to_string(gbuffer.width) + "x" +
                std::to_string(gbuffer.height));
  if (features.model != gbuffer.model)
    throw Error("G-buffer rasterized for " + toString(gbuffer.model) + " cannot be stored for " +
                toString(features.model));
  EncodedGBuffer e;
  e.format = format;
  e.model = gbuffer.model;
  e.hasSpecular = features.specular || gbuffer.model == ShadingModel::MetallicRoughness;
  e.hasEmissive = features.emissive;
  e.width = gbuffer.width;
  e.height = gbuffer.height;
  const bool mr = gbuffer.model == ShadingModel::MetallicRoughness;
  plane_alloc::assignRange(e.depth, gbuffer.depth.begin(), gbuffer.depth.end());
  if (format == GBufferFormat::PACKED) {
    e.normal = encodePacked(gbuffer.normal, n,
                            [](const glm::vec4& v) { return packed::encodeNormal(glm::vec3(v)); });
    // Blinn-Phong: kd rgb (alpha 1); metallic-roughness: base rgb + metallic.
    e.diffuse = encodePacked(gbuffer.diffuse, n, packUnorm8x4);
    if (mr) {
      plane_alloc::assignZeroed(e.specular, n);
      for (size_t i = 0; i < n; ++i) e.specular[i] = packed::encodeUnorm8(gbuffer.specular[i].x);
    } else if (e.hasSpecularPlane()) {
      e.specular = encodePacked(gbuffer.specular, n, [](const glm::vec4& v) {
        return (packUnorm8x4(v) & 0x00ffffffu) | uint32_t(packed::encodeShininess(v.w)) << 24;
      });
    }
    if (e.hasEmissive) e.emissive = encodePlane(gbuffer.emissive, n, GBufferFormat::FP16);
    return e;
  }
  if (mr) {
    // Roughness rides in the normal's unused w.
    std::vector<glm::vec4> normal(gbuffer.normal.begin(), gbuffer.normal.end());
    for (size_t i = 0; i < n; ++i) normal[i].w = gbuffer.specular[i].x;
    e.normal = encodePlane(normal, n, format);
  } else {
    e.normal = encodePlane(gbuffer.normal, n, format);
  }
  e.diffuse = encodePlane(gbuffer.diffuse, n, format);
  if (e.hasSpecularPlane()) e.specular = encodePlane(gbuffer.specular, n, format);
  if (e.hasEmissive) e.emissive = encodePlane(gbuffer.emissive, n, format);
  return e;
}

glm::vec4 decodeStored(const EncodedGBuffer& gbuffer, GBufferPlane plane, size_t i) {
  const bool mr = gbuffer.model == ShadingModel::MetallicRoughness;
  // Metallic-roughness keeps roughness in the normal's w (fp32, fp16) or in a byte plane
  // (packed); as a raster G-buffer holds it: (roughness, 0, 0, 0).
  if (mr && plane == GBufferPlane::Specular) {
    float roughness = gbuffer.format == GBufferFormat::PACKED
                          ? codecs::ts_decode_roughness_byte(gbuffer.specular[i])
                          : load4(gbuffer.normal, i, gbuffer.format).w;
    return glm::vec4(roughness, 0.0f, 0.0f, 0.0f);
  }
  // Absent planes hold what a material without the term has.
  if (plane == GBufferPlane::Specular && !gbuffer.hasSpecularPlane())
    return glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
  if (plane == GBufferPlane::Emissive && !gbuffer.hasEmissive) return glm::vec4(0.0f);
  const auto& bytes = plane == GBufferPlane::Normal     ? gbuffer.normal
                      : plane == GBufferPlane::Diffuse  ? gbuffer.diffuse
                      : plane == GBufferPlane::Specular ? gbuffer.specular
                                                        : gbuffer.emissive;
  if (gbuffer.format != GBufferFormat::PACKED) {
    glm::vec4 v = load4(bytes, i, gbuffer.format);
    if (mr && plane == GBufferPlane::Normal) v.w = 0.0f;
    return v;
  }
  if (plane == GBufferPlane::Emissive) return load4(bytes, i, GBufferFormat::FP16);
  const uint32_t v = loadPacked(bytes, i);
  switch (plane) {
    case GBufferPlane::Normal: return glm::vec4(codecs::ts_decode_octahedral(v), 0.0f);
    case GBufferPlane::Diffuse:
      return glm::vec4(codecs::ts_decode_unorm8x3(v), codecs::ts_decode_unorm8(v >> 24));
    default: return glm::vec4(codecs::ts_decode_unorm8x3(v), codecs::ts_decode_shininess(v >> 24));
  }
}

bool decodeSurface(const EncodedGBuffer& gbuffer, const CameraIntrinsics& camera, int x, int y,
                   SurfaceD& surface) {
  if (camera.width != gbuffer.width || camera.height != gbuffer.height)
    throw Error("camera is " + std::to_string(camera.width) + "x" + std::to_string(camera.height) +
                " but the G-buffer is " + std::to_string(gbuffer.width) + "x" +
                std::to_string(gbuffer.height));
  if (x < 0 || y < 0 || x >= gbuffer.width || y >= gbuffer.height)
    throw std::out_of_range("decodeSurface: pixel outside the G-buffer");
  // ts_load_surface, step by step: the stored values as the kernels decode them (in float), then
  // widened; the derived terms in double.
  const size_t i = size_t(y) * size_t(camera.width) + size_t(x);
  const float depth = gbuffer.depth[i];
  if (depth <= 0.0f) return false;
  surface.P = shading_d::ts_view_position(x, y, double(depth), double(camera.tanHalfFovX),
                                          double(camera.tanHalfFovY), camera.width, camera.height);
  surface.V = normalizeLikeOpenCL(-surface.P);
  const bool packedLayout = gbuffer.format == GBufferFormat::PACKED;
  glm::vec4 normal(0.0f), diffuse(0.0f), specular(0.0f, 0.0f, 0.0f, 1.0f);
  if (packedLayout) {
    normal = glm::vec4(codecs::ts_decode_octahedral(loadPacked(gbuffer.normal, i)), 0.0f);
    const uint32_t d = loadPacked(gbuffer.diffuse, i);
    diffuse = glm::vec4(codecs::ts_decode_unorm8x3(d), codecs::ts_decode_unorm8(d >> 24));
    if (gbuffer.model == ShadingModel::MetallicRoughness) {
      specular.x = codecs::ts_decode_roughness_byte(gbuffer.specular[i]);
    } else if (gbuffer.hasSpecularPlane()) {
      const uint32_t spec = loadPacked(gbuffer.specular, i);
      specular =
          glm::vec4(codecs::ts_decode_unorm8x3(spec), codecs::ts_decode_shininess(spec >> 24));
    }
  } else {
    normal = load4(gbuffer.normal, i, gbuffer.format);
    diffuse = load4(gbuffer.diffuse, i, gbuffer.format);
    if (gbuffer.model == ShadingModel::MetallicRoughness) specular.x = normal.w;
    else if (gbuffer.hasSpecularPlane()) specular = load4(gbuffer.specular, i, gbuffer.format);
  }
  const glm::vec4 emissive =
      gbuffer.hasEmissive
          ? load4(gbuffer.emissive, i, packedLayout ? GBufferFormat::FP16 : gbuffer.format)
          : glm::vec4(0.0f);
  surfaceTerms(normal, diffuse, specular, emissive, gbuffer.model, gbuffer.hasSpecularPlane(),
               surface);
  return true;
}

void surfaceTerms(glm::vec4 normal, glm::vec4 diffuse, glm::vec4 specular, glm::vec4 emissive,
                  ShadingModel model, bool hasSpecular, SurfaceD& surface) {
  surface.N = normalizeLikeOpenCL(glm::dvec3(glm::vec3(normal)));
  if (model == ShadingModel::MetallicRoughness) {
    shading_d::ts_metallic_roughness_terms(glm::dvec3(glm::vec3(diffuse)), double(diffuse.w),
                                           double(specular.x), &surface.cDiff, &surface.kd,
                                           &surface.ks, &surface.gloss);
    surface.viewTerm = shading_d::ts_smith_view_term(surface.N, surface.V, surface.gloss);
  } else {
    surface.kd = surface.cDiff = glm::dvec3(glm::vec3(diffuse));
    surface.ks = hasSpecular ? glm::dvec3(glm::vec3(specular)) : glm::dvec3(0.0);
    surface.gloss = hasSpecular ? double(specular.w) : 1.0;
    surface.viewTerm = 1.0;
  }
  surface.ke = glm::dvec3(glm::vec3(emissive));
}

}  // namespace ts
