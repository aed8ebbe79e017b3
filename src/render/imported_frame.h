#pragma once
// `--gbuffer-in`: a G-buffer and its lights from files (read by gbuffer/gbuffer_import.h), from
// `render --dump` or from another renderer, as a frame every technique, `--check`, `--heatmap`
// and `bench` work on.
#include <optional>
#include <string>

#include "gbuffer/gbuffer_files.h"
#include "render/frame_setup.h"

namespace ts {

struct ImportedFrame {
  GBufferDescriptor descriptor;
  PreparedFrame frame;  // gbuffer as read, encoded in the chosen layout; camera = identity view
};

// Reads the files (readGBufferFiles, which lists what it rejects) and encodes the G-buffer in
// `format` (default: the descriptor's "layout", else fp32). A `render --dump` folder comes back
// exactly: the same encoded planes, lights and camera.
ImportedFrame importGBuffer(const std::string& dirOrFile,
                            std::optional<GBufferFormat> format = std::nullopt);

}  // namespace ts
