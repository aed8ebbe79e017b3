#pragma once
// The multi-kernel tiled technique in one G-buffer layout and tile size, built once per process:
// what the end-to-end tests (tiled against the reference, third-party content) render with.
#include "techniques/technique.h"
#include "reference_check.h"

namespace ts::test {

inline Technique& tiledTechnique(GBufferFormat format, int tile) {
  TechniqueConfig config;
  config.format = format;
  config.tileWidth = config.tileHeight = tile;
  return test::cachedTechnique("tiled", config);
}

}  // namespace ts::test
