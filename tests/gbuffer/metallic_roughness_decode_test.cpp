// The metallic-roughness planes' per-element decoders of the kernels (kernels/gbuffer.h, through
// decode_gbuffer in kernels/dump.cl) against the host's (decodeStored, gbuffer/gbuffer_layout.cpp),
// bit for bit, for every stored value: each of the 256 bytes of the packed base colour and
// roughness, and spreads of fp16 and fp32 values (every finite half). GBufferDecode in
// gbuffer_decode_test.cpp checks the Blinn-Phong layouts end to end on a rendered scene.
#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <vector>

#include "gbuffer/gbuffer_layout.h"
#include "render/gbuffer_dump.h"
#include "scene/scene_features.h"
#include "techniques/device_frame.h"
#include "test_support.h"

namespace ts {
namespace {

constexpr int kW = 256, kH = 256;  // one pixel per half bit pattern; 256 rows of every byte
constexpr size_t kPixels = size_t(kW) * kH;

template <typename T>
void store(std::vector<uint8_t>& plane, size_t element, T value) {
  std::memcpy(&plane[element * sizeof(T)], &value, sizeof(T));
}

// Pixel i's stored value of channel c: every half bit pattern once per channel (rotated per
// channel), the non-finite ones replaced by 0 (encode() never stores them).
uint16_t halfBits(size_t i, int c) {
  const uint16_t h = uint16_t(i * 0x9e5u + size_t(c) * 0x3c01u);  // odd step: a permutation
  return (h & 0x7c00u) == 0x7c00u ? 0 : h;
}

// Finite floats of every exponent, both signs; roughness and colours as [0, 1] in the first row.
float floatValue(std::mt19937& rng, size_t i) {
  if (i < 256) return float(i) / 255.0f;
  uint32_t bits = rng();
  if ((bits & 0x7f800000u) == 0x7f800000u) bits &= 0xbfffffffu;  // inf/NaN -> finite
  float f;
  std::memcpy(&f, &bits, 4);
  return f;
}

EncodedGBuffer metallicRoughness(GBufferFormat format) {
  EncodedGBuffer e;
  e.format = format;
  e.model = ShadingModel::MetallicRoughness;
  e.width = kW;
  e.height = kH;
  e.depth.assign(kPixels, 3.0f);
  std::mt19937 rng(15);
  if (format == GBufferFormat::PACKED) {
    e.normal.resize(kPixels * 4);
    e.diffuse.resize(kPixels * 4);
    e.specular.resize(kPixels);
    e.emissive.resize(kPixels * 8);
    for (size_t i = 0; i < kPixels; ++i) {
      const uint32_t b = uint32_t(i & 255u), row = uint32_t(i >> 8);
      store(e.normal, i, packed::encodeNormal(glm::vec3(0.0f, 0.0f, 1.0f)));
      // Base colour (rgb) and metallic (a): every byte in each channel, in other pairings per row.
      store(e.diffuse, i, b | (255u - b) << 8 | ((b * 7u + row) & 255u) << 16 | (b ^ row) << 24);
      store(e.specular, i, uint8_t(b + row));  // roughness
      for (int c = 0; c < 4; ++c) store(e.emissive, i * 4 + size_t(c), halfBits(i, c));
    }
    return e;
  }
  // fp32/fp16: roughness in the normal's w, metallic in the diffuse's w, no specular plane.
  const bool fp16 = format == GBufferFormat::FP16;
  const size_t element = fp16 ? 8 : 16;
  e.normal.resize(kPixels * element);
  e.diffuse.resize(kPixels * element);
  e.emissive.resize(kPixels * element);
  for (size_t i = 0; i < kPixels; ++i)
    for (int c = 0; c < 4; ++c) {
      const size_t k = i * 4 + size_t(c);
      if (fp16) {
        store(e.normal, k, c == 3 ? halfBits(i, 0) : uint16_t(c == 2 ? 0x3c00u : 0u));
        store(e.diffuse, k, halfBits(i, c + 1));
        store(e.emissive, k, halfBits(i, c + 2));
      } else {
        const float roughness = floatValue(rng, i);
        const float diffuse = floatValue(rng, i);
        const float emissive = floatValue(rng, i);
        store(e.normal, k, c == 3 ? roughness : (c == 2 ? 1.0f : 0.0f));
        store(e.diffuse, k, diffuse);
        store(e.emissive, k, emissive);
      }
    }
  return e;
}

uint32_t bitsOf(float f) {
  uint32_t b;
  std::memcpy(&b, &f, 4);
  return b;
}

TEST(MetallicRoughnessDecode, KernelEqualsTheHostForEveryStoredValue) {
  for (GBufferFormat format : {GBufferFormat::FP32, GBufferFormat::FP16, GBufferFormat::PACKED}) {
    SCOPED_TRACE(toString(format));
    const EncodedGBuffer e = metallicRoughness(format);
    SceneCamera camera;
    const CameraIntrinsics intrinsics = CameraIntrinsics::from(camera, kW, kH);
    ViewLights lights;
    DeviceFrame frame =
        DeviceFrame::upload(test::context(), e, intrinsics, lights, glm::vec3(0.0f));
    const std::vector<float> d = decodeOnDevice(
        test::context(), frame, format, SceneFeatures::general(ShadingModel::MetallicRoughness));
    for (size_t i = 0; i < kPixels; ++i) {
      const float* o = &d[i * 17];
      const glm::vec4 base = decodeStored(e, GBufferPlane::Diffuse, i);
      const glm::vec4 roughness = decodeStored(e, GBufferPlane::Specular, i);
      const glm::vec4 emissive = decodeStored(e, GBufferPlane::Emissive, i);
      ASSERT_EQ(o[16], 1.0f) << i;
      ASSERT_EQ(bitsOf(o[9]), bitsOf(roughness.x)) << "roughness, pixel " << i;
      for (int c = 0; c < 3; ++c) {
        ASSERT_EQ(bitsOf(o[6 + c]), bitsOf(base[c])) << "base colour " << c << ", pixel " << i;
        ASSERT_EQ(bitsOf(o[13 + c]), bitsOf(emissive[c])) << "emission " << c << ", pixel " << i;
        ASSERT_EQ(o[10 + c], 0.0f) << i;
      }
    }
  }
}

}  // namespace
}  // namespace ts
