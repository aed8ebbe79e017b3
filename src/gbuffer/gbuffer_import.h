#pragma once
// `--gbuffer-in`'s reader: the G-buffer files (src/gbuffer/gbuffer_files.h), from `render --dump`
// or from another renderer, read into the G-buffer module's types and checked. Their assembly
// into a frame the techniques run on is render/imported_frame.h.
#include <string>

#include "gbuffer/gbuffer.h"
#include "gbuffer/gbuffer_files.h"

namespace ts {

// The files' content: the planes at full precision (linear depth, normals as signed vectors),
// the camera and the view-space lights.
struct ImportedGBuffer {
  GBufferDescriptor descriptor;
  GBuffer gbuffer;              // as read (rows top first), fixed components filled in
  CameraIntrinsics intrinsics;  // near / far from the descriptor, else from the depths read
  LightsFile lights;
};

// Reads dirOrFile (a folder holding gbuffer.json, or a descriptor path), the image and the lights
// it names. Throws ts::Error naming the file and the channel or field: a missing channel, an
// image of the wrong size, a NaN or infinite value on a geometry pixel, NaN depth, geometry in
// front of the near plane, a hardware depth outside [0, 1], a normal far from unit length, a
// negative colour, values beyond the shading range (the glTF path's checkShadingRange), a depth
// of the wrong sign everywhere, a light without a range, ... A frame without geometry otherwise
// gets a one-line warning on stderr.
ImportedGBuffer readGBufferFiles(const std::string& dirOrFile);

}  // namespace ts
