#pragma once
// Comparing two shadow atlases of the same layout drawn by different rasterizers (OpenGL against
// software), as gbuffer/gbuffer_compare.h compares their G-buffers: which texels each covers,
// and how far their depths differ where both do. The bound is derived in docs/shadows.md ("The
// maps from OpenGL"); tests/raster/gl_shadow_maps_test.cpp checks it.
#include <cstdint>
#include <string>

#include "raster/shadow_maps.h"
#include "scene/scene.h"

namespace ts {

// The per-texel bound on |depth A - depth B| / depth A where both cover a texel with the same
// surface: float rounding of the view transform and interpolation, kShadowFloatRel (1 + W / d)
// (W: the largest coordinate entering the face's float view transform), plus the snapped
// vertices' move of kShadowSnapMove texels times the depth's slope: 2 kShadowSnapMove g / d, g
// the largest depth step from the texel to a covered 4-neighbour in A.
constexpr double kShadowFloatRel = 8.0 * 1.1920929e-7;
constexpr double kShadowSnapMove = 1.0 / 128.0;

struct ShadowAtlasComparison {
  uint64_t texels = 0;  // of the faces
  uint64_t coveredA = 0, coveredB = 0, bothCovered = 0;
  uint64_t onlyA = 0, onlyB = 0;  // covered (depth < the face's far) by one map only
  // Texels of A on a silhouette: a 3x3 neighbourhood (within its face) holding both covered and
  // empty texels.
  uint64_t silhouetteA = 0;
  // Coverage differences whose 3x3 neighbourhood (the 8 neighbours) is mixed in neither map: a
  // hole or a lost triangle, not an edge (or a sliver's edge) that moved.
  uint64_t mismatchesOffSilhouette = 0;
  // Texels both cover whose depths differ beyond the bound: another surface won ...
  uint64_t depthDiffers = 0;
  // ... of which on a surface one texel thin in A (both neighbours along x or along y empty: a
  // sliver seen edge-on, whose slope across the texel the map does not show, so the snap term
  // cannot be evaluated there; counted, not bounded), and the largest |dA - dB| / dA there ...
  uint64_t thinDiffers = 0;
  double maxThinDepthRel = 0.0;
  // ... and the rest, where neither map's 8 neighbours hold both depths (each within the bound):
  // not an edge between two surfaces that moved, nor a sliver.
  uint64_t depthDiffersOffEdge = 0;
  // Texels of no face that are not 0 in both (the convention: 0 there).
  uint64_t unusedNonZero = 0;
  // Over the texels both cover but those on a moved edge or a sliver beyond the bound:
  double maxDepthRel = 0.0;  // |dA - dB| / dA
  double worstRatio = 0.0;   // the largest |dA - dB| / dA over its texel's bound
  int worstFace = -1, worstX = -1, worstY = -1;  // where (texel of the face), for messages

  std::string summary() const;  // one line of the figures above
};

// `scene`: the one both were drawn from (its vertices give W). Throws ts::Error when the atlases'
// sizes or faces differ.
ShadowAtlasComparison compareShadowAtlases(const ShadowAtlas& a, const ShadowAtlas& b,
                                           const Scene& scene);

}  // namespace ts
