#pragma once
// Image files through OpenImageIO: linear float EXR and tone-mapped 8-bit PNG.
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace ts {

// An image read back: every channel converted to float, interleaved, row 0 = the file's top row.
struct FloatImage {
  int width = 0, height = 0;
  std::vector<std::string> channels;  // names, in the file's order
  std::vector<float> data;            // width * height * channels.size()
  // Index of a channel by name, -1 when absent.
  int channel(const std::string& name) const;
};

// Reads any image OpenImageIO reads (OpenEXR with half, float or uint channels, ...); its first
// subimage. OpenEXR's 32-bit uint channels keep their values (1 is 1.0, not
// 1/2^32); 8- and 16-bit ones (PNG, TIFF) are normalised to [0, 1]. Throws ts::Error
// naming the file: unreadable, a data window that is not the display window (a crop), or a
// build without OpenImageIO.
FloatImage readImage(const std::string& path);

// Writes `channels` named float channels per pixel (interleaved) to an OpenEXR file.
void writeExr(const std::string& path, int width, int height,
              const std::vector<std::string>& channels, const std::vector<float>& data);

void writeExrRgb(const std::string& path, int width, int height,
                 const std::vector<glm::vec4>& image);

// Tone map 1 - exp(-exposure * x), then sRGB encode, 8 bits per channel.
void writePngToneMapped(const std::string& path, int width, int height,
                        const std::vector<glm::vec4>& image, float exposure = 1.0f);

// A heat map of a scalar per pixel (0 = black ... max = white through red/yellow), log scale
// between `lo` and `hi`.
void writeHeatMapPng(const std::string& path, int width, int height, const std::vector<float>& v,
                     float lo, float hi);

}  // namespace ts
