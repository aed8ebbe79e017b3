#pragma once
// The shadow maps of a frame drawn into their atlas (raster/shadow_atlas.h plans it): depth-only
// software rasterization (rasterizeDepth) of each face's triangles, those of the draw batches
// (raster/draw_batches.h) whose boxes touch the face's frustum; attachShadowMaps hands them to
// the lights that the kernels and the reference shade (kernels/shadows.h).
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "raster/draw_batches.h"
#include "raster/shadow_atlas.h"
#include "scene/scene.h"
#include "shading/view_lights.h"

namespace ts {

struct ShadowAtlas {
  ShadowAtlasLayout layout;
  // width x height floats, row 0 = the top: each face's linear depths (ShadowFace), 0 in texels
  // that belong to no face.
  std::vector<float> depth;
  std::vector<uint64_t> faceTriangles;  // per face of layout.faces: the triangles drawn
  // Culling and drawing every face (not the planning); OpenGL: the host's wall clock from
  // glFinish to glFinish around the pass (docs/techniques.md), the read-back not included.
  double drawMs = 0.0;
  std::string rasterizer = "software";  // who drew it: "software" or "gl" (--raster)
  double readMs = 0.0;                  // OpenGL: reading the atlas back (0 for software)

  uint64_t trianglesDrawn() const;
  float at(int x, int y) const { return depth[size_t(y) * size_t(layout.width) + size_t(x)]; }
};

// Draws every face of `layout` (planned for this scene's lights). threads: 0 = all hardware
// threads; the same atlas for any count. Throws ts::Error for a scene the rasterizer refuses.
ShadowAtlas drawShadowAtlas(const Scene& scene, ShadowAtlasLayout layout, int threads = 0);
// The same with the scene's draw batches (drawBatches of a scene that passed validateForRaster)
// given: for callers that draw many layouts of one scene (raster/per_light_shadows.h).
ShadowAtlas drawShadowAtlas(const Scene& scene, const std::vector<DrawBatch>& batches,
                            ShadowAtlasLayout layout, int threads = 0);

// How the maps are sampled (kernels/shadows.h; docs/shadows.md): --shadow-filter's taps a side
// (1: none, one texel's comparison; 2, 3, 5: pcfN, N x N comparisons averaged) and --shadow-bias
// (constant, slope; in a texel's world footprint at the receiver), or "receiver,C": each tap
// compares the receiver plane's depth at its texel, with the constant C only (no slope).
struct ShadowSampling {
  int taps = 1;
  float biasConstant = 1.5f, biasSlope = 1.5f;
  bool receiverPlane = false;  // biasSlope is then 0 (not used)
};
// --shadow-filter none|pcf2|pcf3|pcf5 -> taps, and back; --shadow-bias "C,S" or "receiver,C"
// (finite, >= 0), and back (shadowBiasText: the canonical "C,S" / "receiver,C").
// Throw ts::Error (one line naming the option) for anything else.
int parseShadowFilter(const std::string& name);
std::string shadowFilterName(int taps);
void parseShadowBias(const std::string& text, ShadowSampling& sampling);
std::string shadowBiasText(const ShadowSampling& sampling);

// Gives `lights` (toViewSpace of `sceneLights` with `viewFromWorld`) the atlas's faces in view
// space and each shadow-casting light its first face: the kernels' face table and atlas.
void attachShadowMaps(const std::shared_ptr<const ShadowAtlas>& atlas,
                      const std::vector<SceneLight>& sceneLights, const glm::dmat4& viewFromWorld,
                      const ShadowSampling& sampling, ViewLights& lights);

// Whether a world box may hold something `face` sees (its frustum against the box's view-space
// box; conservative: false only when the box lies wholly outside one plane).
bool touchesFace(const Bounds& world, const ShadowFace& face);

}  // namespace ts
