#pragma once
// The import path inside `tileshade check`: a rasterized frame written out as another renderer
// would write it (a reversed-Z depth buffer with an infinite far plane, normals as 0.5 n + 0.5,
// rows bottom first, the field of view in degrees) and read back through a descriptor by
// --gbuffer-in's reader, so the hard cases cover what the import does to depth, normals and the
// near plane the culling clips at.
#include "render/frame_setup.h"

namespace ts {

// Writes `frame`'s G-buffer (Blinn-Phong planes) and lights into a fresh temporary folder, imports
// it in `format` and removes the folder. Throws ts::Error when a file cannot be written or read.
PreparedFrame throughForeignGBufferFiles(const PreparedFrame& frame, GBufferFormat format);

}  // namespace ts
