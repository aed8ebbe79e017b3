#pragma once
// Storage layouts of the G-buffer on the device, and the host decoder that mirrors
// kernels/gbuffer.h exactly (the reference shades the same values the kernels read).
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "raster/gbuffer.h"

namespace ts {

enum class GBufferFormat { FP32, FP16 };

std::string toString(GBufferFormat format);
GBufferFormat parseGBufferFormat(const std::string& name);  // "fp32" | "fp16", throws ts::Error

// The planes exactly as they are uploaded (see kernels/gbuffer.h for the layout).
struct EncodedGBuffer {
  GBufferFormat format = GBufferFormat::FP32;
  int width = 0;
  int height = 0;
  std::vector<float> depth;
  std::vector<uint8_t> normal, diffuse, specular, emissive;  // 4 elements per pixel each

  size_t pixelCount() const { return size_t(width) * size_t(height); }
  size_t bytesPerPixel() const;  // all planes together
  // OpenCL build options selecting the matching decoder in kernels/gbuffer.h.
  std::string kernelDefines() const;
};

EncodedGBuffer encode(const GBuffer& gbuffer, GBufferFormat format);

// A decoded pixel in double precision, from the stored values.
struct SurfaceD {
  glm::dvec3 P{0.0}, N{0.0}, V{0.0}, kd{0.0}, ks{0.0}, ke{0.0};
  double shininess = 0.0;
};

// Returns false for background. Mirrors ts_load_surface (kernels/gbuffer.h).
bool decodeSurface(const EncodedGBuffer& gbuffer, const CameraIntrinsics& camera, int x, int y,
                   SurfaceD& surface);

}  // namespace ts
