#pragma once
// The shadow maps of a frame, planned (issue #18): which faces each shadow-casting light has, how
// big, where in the one atlas, and the view each is drawn with (raster/shadow_maps.h draws them).
// docs/shadows.md has the rules; in short:
//   - a point light has 6 cube faces (+X, -X, +Y, -Y, +Z, -Z: OpenGL's cube-map order and
//     orientations), 90 degrees each, near = range * 1e-3, far = range;
//   - a spot light one perspective face over its cone (2 * outerConeAngle, at most 170 degrees);
//   - a directional light one orthographic face: across its direction fitted to the view's
//     geometry (the frame's visible surfaces, the receivers; the scene's bounds when none is
//     given), along it to the scene's bounds (every caster between the light and them);
//   - sizes: --shadow-map-size for point and spot faces, 4x that (at most 8192) for directional
//     ones; while the atlas exceeds --shadow-budget, lights lose resolution in rounds of one
//     halving each, the least important first (importance: screen coverage x range), never
//     below 16x16 (then: an error naming the budget and what it would need);
//   - the atlas is one float32 texture of a power of two texels (W x W or W x W/2), the faces
//     packed largest first in Morton order (exact for powers of two: no gaps, no overlaps).
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "gbuffer/gbuffer.h"
#include "raster/rasterizer.h"
#include "scene/scene.h"

namespace ts {

constexpr int kShadowMinFaceSize = 16;
constexpr int kShadowMaxFaceSize = 8192;
constexpr int kShadowMaxAtlasSide = 16384;
constexpr double kShadowMaxBudgetMB = 4096.0;  // the 16384^2 float atlas
constexpr int kDefaultShadowMapSize = 512;
constexpr double kDefaultShadowBudgetMB = 64.0;

struct ShadowAtlasOptions {
  int mapSize = kDefaultShadowMapSize;       // point and spot faces: a power of two, 16..8192
  double budgetMB = kDefaultShadowBudgetMB;  // the atlas's bytes, in MiB (2^20 bytes)
};

// One face of one light's shadow map. Its texels hold the nearest linear depth -Z of the face's
// view space (the distance along the face's axis, world units; not NDC depth), `far` where
// nothing is drawn: the same convention for the software maps and the OpenGL ones
// (GlRasterizer::drawShadowAtlas).
struct ShadowFace {
  uint32_t light = 0;  // index into the scene's lights
  int face = 0;        // cube face 0..5 (+X, -X, +Y, -Y, +Z, -Z); 0 for spot and directional
  DepthView view;      // what rasterizeDepth draws it with
  // World -> clip of the face (OpenGL conventions: projection * view; NDC x, y in [-1, 1] cover
  // the face, NDC y = +1 its top row). A world point p lies at texel column
  // x + (ndc.x + 1) / 2 * size, row y + (1 - ndc.y) / 2 * size, with linear depth -(view * p).z.
  glm::dmat4 mapFromWorld{1.0};
  int x = 0, y = 0, size = 0;  // the atlas rectangle (texels; row 0 = the atlas's top row)
};

// One shadow-casting light's share of the atlas.
struct ShadowLightMap {
  uint32_t light = 0;
  SceneLightType type = SceneLightType::Point;
  int faces = 0;          // 6, or 1
  int requestedSize = 0;  // before the budget
  int size = 0;           // per face, as drawn
  double importance = 0;  // screen coverage x range; directional lights: infinite
};

struct ShadowAtlasLayout {
  int width = 0, height = 0;
  std::vector<ShadowFace> faces;
  std::vector<ShadowLightMap> lights;  // in light order
  // One line each, for stderr and stats.json: lights that lost resolution to the budget, spot
  // cones wider than a map covers.
  std::vector<std::string> notes;
  uint64_t bytes() const { return uint64_t(width) * uint64_t(height) * sizeof(float); }
};

// The atlas for the lights with castsShadow (none: an empty layout, 0x0). `geometry`: the scene's
// bounds (Scene::bounds()); `receivers`: the view's geometry (viewGeometryBounds), which
// directional maps are fitted to across the light (empty: `geometry`); `camera`: the frame's, for
// the lights' screen coverage. Throws ts::Error (one line) for options out of range, a budget too
// small for every face at 16x16, or a shadow-casting directional light with no geometry.
ShadowAtlasLayout planShadowAtlas(const std::vector<SceneLight>& lights, const Bounds& geometry,
                                  const SceneCamera& camera, const ShadowAtlasOptions& options,
                                  const Bounds& receivers = Bounds{});

// The world-space box around the surfaces a G-buffer sees (its pixels with depth > 0, widened by
// a pixel's footprint at their depth); empty (min > max) when it sees none.
Bounds viewGeometryBounds(const GBuffer& gbuffer, const SceneCamera& camera);

// Checks --shadow-map-size and --shadow-budget (one-line ts::Error naming the option).
void checkShadowAtlasOptions(const ShadowAtlasOptions& options);

}  // namespace ts
