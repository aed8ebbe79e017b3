#include "gbuffer/image_io.h"

#include <algorithm>
#include <cmath>
#include <memory>

#include <iostream>

#ifndef TILESHADE_NO_OIIO
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#endif

#include "util/error.h"
#include "util/file_read.h"
#include "util/file_write.h"
#include "util/stderr_capture.h"

namespace ts {
namespace {

#ifndef TILESHADE_NO_OIIO
// Encodes in memory (the format from the extension), then writes the file with a checked write:
// OpenImageIO's PNG writer reports success on a full disk. What libpng prints itself goes into
// the error message instead of a raw "libpng error:" line.
void write(const std::string& path, const OIIO::ImageSpec& spec, const void* data) {
  std::vector<unsigned char> bytes;
  OIIO::Filesystem::IOVecOutput memory(bytes);
  StderrCapture libraryMessages;
  auto out = OIIO::ImageOutput::create(path, &memory);
  bool ok = out && out->supports("ioproxy") && out->open(path, spec) &&
            out->write_image(spec.format, data) && out->close();
  std::string printed = libraryMessages.text();
  if (!ok) {
    std::string why = !out                        ? OIIO::geterror()
                      : !out->supports("ioproxy") ? "OpenImageIO cannot encode it in memory"
                                                  : out->geterror();
    throw Error("cannot write " + path + ": " + why +
                (printed.empty() ? "" : " (" + printed + ")"));
  }
  writeFile(path, bytes.data(), bytes.size());
}
#else
// A measurement build (TILESHADE_WITH_OIIO=OFF) says once that it writes no images.
struct ImageSpec {
  ImageSpec(int, int, int, int) {}
};
constexpr int kFloat = 0, kUint8 = 0;
void write(const std::string& path, const ImageSpec&, const void*) {
  static bool said = false;
  if (!said)
    std::cerr << "tileshade: warning: built without OpenImageIO; not writing " << path
              << " (nor any other image)\n";
  said = true;
}
#endif

#ifndef TILESHADE_NO_OIIO
OIIO::ImageSpec PngSpec(int width, int height) {
  return OIIO::ImageSpec(width, height, 3, OIIO::TypeDesc::UINT8);
}
#else
ImageSpec PngSpec(int width, int height) { return ImageSpec(width, height, 3, kUint8); }
#endif

uint8_t srgb8(float linear) {
  float v = std::isnan(linear) ? 0.0f : std::clamp(linear, 0.0f, 1.0f);  // NaN: black
  v = v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
  return uint8_t(std::lround(v * 255.0f));
}

}  // namespace

void writeExr(const std::string& path, int width, int height,
              const std::vector<std::string>& channels, const std::vector<float>& data) {
#ifndef TILESHADE_NO_OIIO
  OIIO::ImageSpec spec(width, height, int(channels.size()), OIIO::TypeDesc::FLOAT);
  spec.channelnames = channels;
  spec.alpha_channel = -1;
#else
  ImageSpec spec(width, height, int(channels.size()), kFloat);
#endif
  write(path, spec, data.data());
}

void writeExrRgb(const std::string& path, int width, int height,
                 const std::vector<glm::vec4>& image) {
  std::vector<float> rgb;
  rgb.reserve(image.size() * 3);
  for (const auto& p : image) rgb.insert(rgb.end(), {p.x, p.y, p.z});
  writeExr(path, width, height, {"R", "G", "B"}, rgb);
}

void writePngToneMapped(const std::string& path, int width, int height,
                        const std::vector<glm::vec4>& image, float exposure) {
  std::vector<uint8_t> rgb;
  rgb.reserve(image.size() * 3);
  for (const auto& p : image)
    for (int c = 0; c < 3; ++c) rgb.push_back(srgb8(1.0f - std::exp(-exposure * p[c])));
  write(path, PngSpec(width, height), rgb.data());
}

void writeHeatMapPng(const std::string& path, int width, int height, const std::vector<float>& v,
                     float lo, float hi) {
  std::vector<uint8_t> rgb;
  rgb.reserve(v.size() * 3);
  float llo = std::log10(std::max(lo, 1e-30f)), lhi = std::log10(std::max(hi, lo * 10.0f));
  for (float e : v) {
    float t = e <= lo ? 0.0f : std::clamp((std::log10(e) - llo) / (lhi - llo), 0.0f, 1.0f);
    // black -> red -> yellow -> white
    float r = std::clamp(3.0f * t, 0.0f, 1.0f), g = std::clamp(3.0f * t - 1.0f, 0.0f, 1.0f),
          b = std::clamp(3.0f * t - 2.0f, 0.0f, 1.0f);
    rgb.insert(rgb.end(), {uint8_t(r * 255), uint8_t(g * 255), uint8_t(b * 255)});
  }
  write(path, PngSpec(width, height), rgb.data());
}

int FloatImage::channel(const std::string& name) const {
  for (size_t i = 0; i < channels.size(); ++i)
    if (channels[i] == name) return int(i);
  return -1;
}

#ifndef TILESHADE_NO_OIIO
namespace {

// A crop (data window) inside a larger display window would be read as a full frame with the
// full frame's field of view: refused rather than guessed at (which pixels are background depends
// on the depth encoding).
void refuseCrop(const std::string& path, const OIIO::ImageSpec& spec) {
  if (spec.x == spec.full_x && spec.y == spec.full_y && spec.width == spec.full_width &&
      spec.height == spec.full_height)
    return;
  auto window = [](int x, int y, int w, int h) {
    return "(" + std::to_string(x) + ", " + std::to_string(y) + ") " + std::to_string(w) + "x" +
           std::to_string(h);
  };
  throw Error(path + ": its data window " + window(spec.x, spec.y, spec.width, spec.height) +
              " is not its display window " +
              window(spec.full_x, spec.full_y, spec.full_width, spec.full_height) +
              "; cropped images are not read: write the full frame");
}

// OpenEXR's uint channels (masks, ids) hold integers; 8- and 16-bit channels (PNG, TIFF) hold
// normalised colours.
bool isIntegerValued(OIIO::TypeDesc t) {
  return t.basetype == OIIO::TypeDesc::UINT32 || t.basetype == OIIO::TypeDesc::INT32;
}

}  // namespace
#endif

FloatImage readImage(const std::string& path) {
  checkReadableFile(path, "image");
#ifndef TILESHADE_NO_OIIO
  auto in = OIIO::ImageInput::open(path);
  if (!in) throw Error("cannot read " + path + ": " + OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  refuseCrop(path, spec);
  FloatImage image;
  image.width = spec.width;
  image.height = spec.height;
  image.channels = spec.channelnames;
  const size_t pixels = size_t(spec.width) * size_t(spec.height), stride = size_t(spec.nchannels);
  image.data.resize(pixels * stride);
  auto fail = [&] { throw Error("cannot read " + path + ": " + in->geterror()); };
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, image.data.data())) fail();
  // OpenImageIO converts 32-bit integer channels to float normalised (uint 1 -> 2.3e-10): a
  // mask or an id channel means its integer values, so those channels are read again as they are.
  std::vector<uint32_t> values(pixels);
  for (int c = 0; c < spec.nchannels; ++c) {
    const OIIO::TypeDesc type = spec.channelformat(c);
    if (!isIntegerValued(type)) continue;
    if (!in->read_image(0, 0, c, c + 1, type, values.data())) fail();
    for (size_t i = 0; i < pixels; ++i)
      image.data[i * stride + size_t(c)] =
          type.basetype == OIIO::TypeDesc::INT32 ? float(int32_t(values[i])) : float(values[i]);
  }
  in->close();
  return image;
#else
  throw Error("cannot read " + path + ": this build has no OpenImageIO (TILESHADE_WITH_OIIO=OFF)");
#endif
}

}  // namespace ts
