#pragma once
// Image files through OpenImageIO: linear float EXR and tone-mapped 8-bit PNG.
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace ts {

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
