#pragma once
// PNG files for tests that build glTF scenes with textures (gltf_builder.h), encoded in memory by
// OpenImageIO as the exporter does. Empty where tileshade is built without OpenImageIO (the
// callers skip).
#include <string>
#include <vector>

#ifndef TILESHADE_NO_OIIO
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#endif

#include "gltf_builder.h"

namespace ts::test {

// An 8-bit RGB PNG of width x height texels, every one `rgb`, as a data URI ("" without OIIO).
inline std::string uniformPngUri(int width, int height, const std::vector<unsigned char>& rgb) {
#ifdef TILESHADE_NO_OIIO
  (void)width, (void)height, (void)rgb;
  return "";
#else
  std::vector<unsigned char> pixels;
  for (int i = 0; i < width * height; ++i) pixels.insert(pixels.end(), rgb.begin(), rgb.end());
  std::vector<unsigned char> png;
  OIIO::Filesystem::IOVecOutput out(png);
  auto writer = OIIO::ImageOutput::create("png", &out);
  OIIO::ImageSpec spec(width, height, 3, OIIO::TypeDesc::UINT8);
  if (!writer || !writer->open("texture.png", spec) ||
      !writer->write_image(OIIO::TypeDesc::UINT8, pixels.data()) || !writer->close())
    return "";
  return "data:image/png;base64," + base64(png);
#endif
}

}  // namespace ts::test
