#pragma once
// The double-precision reference: every light for every pixel, from the same stored G-buffer
// values the kernels read, shaded by kernels/shading.h compiled as C++ with TS_REAL = double, in
// the G-buffer's shading model. `model` is the range model (TS_MODEL_WINDOWED / _PHYSICAL).
#include <cstdint>
#include <functional>
#include <vector>

#include <glm/glm.hpp>

#include "raster/gbuffer_layout.h"
#include "techniques/device_frame.h"
#include "techniques/technique.h"

namespace ts {

struct ReferenceImage {
  int width = 0, height = 0;
  std::vector<glm::dvec3> rgb;    // row 0 = top
  uint64_t contributing = 0;      // (pixel, light) pairs with a non-zero contribution (every
                                  // light type): the ideal
  double peak = 0.0;              // largest channel value
};

// Called from the worker threads (one call at a time) after each image row with the rows done so
// far and the total, so that a long reference (1e5-1e6 lights) can show progress; may be empty.
using RowProgress = std::function<void(int rowsDone, int rows)>;

ReferenceImage shadeReference(const EncodedGBuffer& gbuffer, const CameraIntrinsics& camera,
                              const ViewLights& lights, glm::vec3 ambient, int model,
                              int threads = 0, const RowProgress& progress = {});

// For every geometry pixel and every point or spot light whose reference contribution is non-zero
// (directional lights are never culled), checks that
// the technique's assignment lets the pixel see the light (its bin lists it, or its screen
// rectangle covers the pixel). Returns the number of misses: 0 = conservative culling.
uint64_t countMissedContributions(const LightAssignment& assignment, const EncodedGBuffer& gbuffer,
                                  const CameraIntrinsics& camera, const ViewLights& lights,
                                  int model, const RowProgress& progress = {});

}  // namespace ts
