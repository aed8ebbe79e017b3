#pragma once
// The double-precision reference: every light for every pixel, from the same stored G-buffer
// values the kernels read, shaded by kernels/shading.h compiled as C++ with TS_REAL = double, in
// the G-buffer's shading model. `model` is the range model (TS_MODEL_WINDOWED / _PHYSICAL).
#include <cstdint>
#include <functional>
#include <vector>

#include <glm/glm.hpp>

#include "gbuffer/gbuffer_layout.h"
#include "shading/light_assignment.h"
#include "shading/view_lights.h"

namespace ts {

struct ReferenceImage {
  int width = 0, height = 0;
  std::vector<glm::dvec3> rgb;  // row 0 = top
  uint64_t contributing = 0;    // (pixel, light) pairs with a non-zero contribution (every
                                // light type): the ideal
  double peak = 0.0;            // largest channel value
  // With ReceiverRounding only (else empty / 0): per pixel and channel, how far the image of a
  // receiver within that rounding of this pixel's may lie from `rgb` through its shadow tests
  // alone (a shadow-casting light's unshadowed term times the range of its factor over the
  // rounding box), and the (pixel, light) pairs where that range is not 0.
  std::vector<glm::dvec3> receiverSlack;
  uint64_t ambiguousShadowPairs = 0;
};

// The forward techniques shade the fragment's interpolated float position, the reference the
// one rebuilt from the stored depth (issue #18): the same point within float rounding of OpenGL's
// vertex transform and interpolation, |dP| <= 8 eps (|P|max + W) per coordinate (eps = 2^-23, W
// the largest coordinate entering the float view transform: docs/opengl.md's depth bound times
// the depth). A receiver that close to a shadow-map texel edge (or to its texel's depth) may be
// decided either way; the reference then also gives the factor's range over that box of
// positions (ReferenceImage::receiverSlack), which a forward image's comparison allows.
// The G-buffer techniques' receivers differ from the reference's too, by less: the kernels
// rebuild the position from depth in float (the reference in double, or in float exactly as they
// do for its shading-only image) and take it to the light's map in float (the reference in
// double), a few eps (|P| + W) per coordinate, inside the same box: their comparisons allow the
// same slack (measured on Sponza's nave: one pixel 3.3e-4 of the peak off at 160x90 without it,
// docs/shadows.md).
struct ReceiverRounding {
  double worldMagnitude = 0.0;  // W
  // The box's half-side at view-space P.
  double halfSide(const glm::dvec3& P) const;
};

// Where the reference takes a pixel's view-space position from.
enum class ReferencePositions {
  // Rebuilt from the stored depth in double: the truth for the stored values. Near a light in or
  // on a surface, the kernels' float rounding of the position shows in the error against it.
  FromDepth,
  // Rebuilt in float exactly as the kernels do (ts_view_position in float, kernels/gbuffer.h),
  // then shaded in double: isolates the shading arithmetic from the position's rounding.
  KernelFloat,
};

// Called from the worker threads (one call at a time) after each image row with the rows done so
// far and the total, so that a long reference (1e5-1e6 lights) can show progress; may be empty.
using RowProgress = std::function<void(int rowsDone, int rows)>;

// The shadow maps against exact visibility (issue #18; docs/shadows.md "Map against exact"):
// per light, indexed punctual lights 0..size()-1 then directional ones size()+j, a plane of one
// value per pixel (row 0 at the top), or empty for a light left alone.
struct ReferenceShadowHook {
  // In: where a plane is given and its value is 0 or 1 (exact visibility's occluded / lit), the
  // shadow factor is that value instead of the map's; elsewhere (2, not applicable) the map's.
  std::vector<std::vector<uint8_t>> visibility;
  // Out, for every light with a shadow map: sized by shadeReference, the map's factor at each
  // pair where the light's unshadowed contribution is non-zero (N.L > 0, inside range and cone:
  // where the reference samples the map), NaN where it is zero.
  std::vector<std::vector<double>> factors;
};

// `shadows` (optional): the hook above; the same shading code either way.
ReferenceImage shadeReference(const EncodedGBuffer& gbuffer, const CameraIntrinsics& camera,
                              const ViewLights& lights, glm::vec3 ambient, int model,
                              int threads = 0, const RowProgress& progress = {},
                              ReferencePositions positions = ReferencePositions::FromDepth,
                              ReferenceShadowHook* shadows = nullptr,
                              const ReceiverRounding* rounding = nullptr);

// --msaa: the reference of a multisampled frame from its samples' own (one per sample, all of one
// size, shaded from each sample's G-buffer): each pixel the mean of its samples, with equal
// weights (the box filter of OpenGL's resolve); `contributing` their sum (pairs of a sample and a
// light), `peak` the mean image's. Throws ts::Error for none or unequal sizes.
ReferenceImage averageSamples(const std::vector<ReferenceImage>& samples);

// --msaa: the reference of a multisampled frame: every sample's planes (samples[k], sample k's)
// shaded by shadeReference (positions, rounding as there) and averaged (averageSamples).
// progress(k), where given, is sample k's row progress. The one loop render's check and bench
// share.
using SampleProgress = std::function<RowProgress(size_t sample)>;
ReferenceImage shadeSampleAverage(const std::vector<EncodedGBuffer>& samples,
                                  const CameraIntrinsics& camera, const ViewLights& lights,
                                  glm::vec3 ambient, int model, ReferencePositions positions,
                                  const ReceiverRounding* rounding,
                                  const SampleProgress& progress = {});

// For every geometry pixel and every point or spot light whose reference contribution is non-zero
// (directional lights are never culled), checks that
// the technique's assignment lets the pixel see the light (its bin lists it, or its screen
// rectangle covers the pixel). Returns the number of misses: 0 = conservative culling.
uint64_t countMissedContributions(const LightAssignment& assignment, const EncodedGBuffer& gbuffer,
                                  const CameraIntrinsics& camera, const ViewLights& lights,
                                  int model, const RowProgress& progress = {});

// --msaa: the misses of every sample, each against its own G-buffer (samples[k], sample k's): an
// assignment whose pixelBin holds one plane per sample (forward, forward-single: the batch of
// each sample's surface) is read per sample; a tile grid's bins are the same for every sample.
uint64_t countMissedOverSamples(const LightAssignment& assignment,
                                const std::vector<EncodedGBuffer>& samples,
                                const CameraIntrinsics& camera, const ViewLights& lights,
                                int model);

}  // namespace ts
