#pragma once
// `--gbuffer-in`: a G-buffer and its lights from files (src/render/gbuffer_files.h), from
// `render --dump` or from another renderer, as a frame every technique, `--check`, `--heatmap`
// and `bench` work on.
#include <optional>
#include <string>

#include "render/frame_setup.h"
#include "render/gbuffer_files.h"

namespace ts {

struct ImportedFrame {
  GBufferDescriptor descriptor;
  PreparedFrame frame;  // gbuffer as read, encoded in the chosen layout; camera = identity view
};

// Reads dirOrFile (a folder holding gbuffer.json, or a descriptor path), the image and the lights
// it names, and encodes the G-buffer in `format` (default: the descriptor's "layout", else fp32).
// A `render --dump` folder comes back exactly: the same encoded planes, lights and camera.
// Throws ts::Error naming the file and the channel or field: a missing channel, an image of the
// wrong size, a NaN or infinite value on a geometry pixel, NaN depth, geometry in front of the
// near plane, a hardware depth outside [0, 1], a normal far from unit length, a negative colour,
// values beyond the shading range (the glTF path's checkShadingRange), a depth of the wrong sign
// everywhere, a light without a range, ... A frame without geometry otherwise gets a one-line
// warning on stderr.
ImportedFrame importGBuffer(const std::string& dirOrFile,
                            std::optional<GBufferFormat> format = std::nullopt);

}  // namespace ts
