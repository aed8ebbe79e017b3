#pragma once
// EXR files the G-buffer reader must cope with, written through OpenImageIO directly (uint
// channels, a cropped data window), for the import tests.
#ifndef TILESHADE_NO_OIIO
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>

#include "gbuffer/image_io.h"

namespace ts::test {

// Writes `image` as an EXR whose channels named in `uintChannels` are stored as uint, and whose
// data window is offset by (dx, dy) inside a display window `border` pixels larger on each side.
inline void writeExrWith(const std::filesystem::path& path, const FloatImage& image,
                         const std::vector<std::string>& uintChannels, int border = 0) {
  OIIO::ImageSpec spec(image.width, image.height, int(image.channels.size()),
                       OIIO::TypeDesc::FLOAT);
  spec.channelnames = image.channels;
  spec.alpha_channel = -1;
  std::vector<bool> isUint;
  for (const auto& c : image.channels) {
    isUint.push_back(std::count(uintChannels.begin(), uintChannels.end(), c) > 0);
    spec.channelformats.push_back(isUint.back() ? OIIO::TypeDesc::UINT32 : OIIO::TypeDesc::FLOAT);
  }
  spec.x = spec.y = border;
  spec.full_width = image.width + 2 * border;
  spec.full_height = image.height + 2 * border;
  // float and uint32 are both 4 bytes: one native buffer, each value in its channel's type
  std::vector<uint32_t> native(image.data.size());
  for (size_t i = 0; i < native.size(); ++i) {
    const float v = image.data[i];
    if (isUint[i % image.channels.size()]) native[i] = uint32_t(v);
    else std::memcpy(&native[i], &v, 4);
  }
  auto out = OIIO::ImageOutput::create(path.string());
  ASSERT_TRUE(out && out->open(path.string(), spec) &&
              out->write_image(OIIO::TypeDesc::UNKNOWN, native.data()) && out->close())
      << OIIO::geterror();
}

}  // namespace ts::test
#endif
