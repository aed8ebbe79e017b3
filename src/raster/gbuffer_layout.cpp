#include "raster/gbuffer_layout.h"

#include <cstring>
#include <stdexcept>

// The half <-> float conversions are computed, not looked up, so no libImath symbol is needed.
#ifndef IMATH_HALF_NO_LOOKUP_TABLE
#define IMATH_HALF_NO_LOOKUP_TABLE
#endif
#include <Imath/half.h>

#include "raster/plane_alloc.h"
#include "reference/shading_cpu.h"
#include "util/error.h"

namespace ts {
namespace {

constexpr size_t kFp32Element = 4 * sizeof(float);     // float4
constexpr size_t kFp16Element = 4 * sizeof(uint16_t);  // half4

size_t elementBytes(GBufferFormat format) {
  return format == GBufferFormat::FP16 ? kFp16Element : kFp32Element;
}

std::vector<uint8_t> encodePlane(const std::vector<glm::vec4>& plane, size_t pixels,
                                 GBufferFormat format) {
  std::vector<uint8_t> out;
  if (format == GBufferFormat::FP32) {
    static_assert(sizeof(glm::vec4) == kFp32Element, "glm::vec4 must be 4 packed floats");
    const uint8_t* bytes = reinterpret_cast<const uint8_t*>(plane.data());
    raster_detail::assignRange(out, bytes, bytes + pixels * kFp32Element);
  } else {
    raster_detail::assignZeroed(out, pixels * kFp16Element);
    uint16_t* dst = reinterpret_cast<uint16_t*>(out.data());
    for (size_t i = 0; i < pixels; ++i)
      for (int c = 0; c < 4; ++c)
        dst[4 * i + size_t(c)] = Imath::half(plane[i][c]).bits();  // round to nearest even
  }
  return out;
}

// The element at pixel i as the kernels read it (vload4 / vload_half4; both exact).
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

std::string toString(GBufferFormat format) {
  switch (format) {
    case GBufferFormat::FP32: return "fp32";
    case GBufferFormat::FP16: return "fp16";
  }
  return "?";
}

GBufferFormat parseGBufferFormat(const std::string& name) {
  if (name == "fp32") return GBufferFormat::FP32;
  if (name == "fp16") return GBufferFormat::FP16;
  throw Error("unknown G-buffer format '" + name + "' (expected fp32 or fp16)");
}

size_t EncodedGBuffer::bytesPerPixel() const {
  return sizeof(float) + 4 * elementBytes(format);  // depth + normal, diffuse, specular, emissive
}

std::string EncodedGBuffer::kernelDefines() const {
  return format == GBufferFormat::FP16 ? "-DTS_GBUFFER_FP16" : "";
}

EncodedGBuffer encode(const GBuffer& gbuffer, GBufferFormat format) {
  const size_t n = gbuffer.pixelCount();
  if (gbuffer.depth.size() != n || gbuffer.normal.size() != n || gbuffer.diffuse.size() != n ||
      gbuffer.specular.size() != n || gbuffer.emissive.size() != n)
    throw Error("G-buffer planes do not match its size " + std::to_string(gbuffer.width) + "x" +
                std::to_string(gbuffer.height));
  EncodedGBuffer e;
  e.format = format;
  e.width = gbuffer.width;
  e.height = gbuffer.height;
  raster_detail::assignRange(e.depth, gbuffer.depth.begin(), gbuffer.depth.end());
  e.normal = encodePlane(gbuffer.normal, n, format);
  e.diffuse = encodePlane(gbuffer.diffuse, n, format);
  e.specular = encodePlane(gbuffer.specular, n, format);
  e.emissive = encodePlane(gbuffer.emissive, n, format);
  return e;
}

bool decodeSurface(const EncodedGBuffer& gbuffer, const CameraIntrinsics& camera, int x, int y,
                   SurfaceD& surface) {
  if (camera.width != gbuffer.width || camera.height != gbuffer.height)
    throw Error("camera is " + std::to_string(camera.width) + "x" + std::to_string(camera.height) +
                " but the G-buffer is " + std::to_string(gbuffer.width) + "x" +
                std::to_string(gbuffer.height));
  if (x < 0 || y < 0 || x >= gbuffer.width || y >= gbuffer.height)
    throw std::out_of_range("decodeSurface: pixel outside the G-buffer");
  // ts_load_surface, step by step.
  const size_t i = size_t(y) * size_t(camera.width) + size_t(x);
  const float depth = gbuffer.depth[i];
  if (depth <= 0.0f) return false;
  surface.P = shading_d::ts_view_position(x, y, double(depth), double(camera.tanHalfFovX),
                                          double(camera.tanHalfFovY), camera.width, camera.height);
  surface.V = normalizeLikeOpenCL(-surface.P);
  surface.N = normalizeLikeOpenCL(glm::dvec3(glm::vec3(load4(gbuffer.normal, i, gbuffer.format))));
  surface.kd = glm::dvec3(glm::vec3(load4(gbuffer.diffuse, i, gbuffer.format)));
  const glm::vec4 spec = load4(gbuffer.specular, i, gbuffer.format);
  surface.ks = glm::dvec3(glm::vec3(spec));
  surface.shininess = double(spec.w);
  surface.ke = glm::dvec3(glm::vec3(load4(gbuffer.emissive, i, gbuffer.format)));
  return true;
}

}  // namespace ts
