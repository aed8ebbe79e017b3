#pragma once
// Comparing two G-buffers of the same frame made by different rasterizers (the OpenGL one against
// the software one): where their coverage differs and by how much their values differ where both
// cover a pixel with the same triangle. Used by tests/raster/gl_raster_test.cpp; the bounds it is
// checked against are derived in docs/opengl.md.
#include <cstdint>
#include <string>

#include "gbuffer/gbuffer.h"

namespace ts {

struct GBufferComparison {
  uint64_t pixels = 0;
  uint64_t coveredA = 0, coveredB = 0;
  uint64_t bothCovered = 0;
  uint64_t onlyA = 0, onlyB = 0;  // covered by one rasterizer only
  // Pixels of A on a silhouette: covered with a background 8-neighbour, or background with a
  // covered one; the coverage mismatches expected from slightly different edges lie there.
  uint64_t silhouetteA = 0;
  // Coverage mismatches that are on no silhouette of A or B (a hole or a lost triangle, not an
  // edge that moved).
  uint64_t mismatchesOffSilhouette = 0;
  // Pixels both cover with different triangles (triangle ids of both needed): a shared edge that
  // moved, or two surfaces at (nearly) the same depth.
  uint64_t triangleDiffers = 0;
  // ... of which no 8-neighbour in A has B's triangle and no 8-neighbour in B has A's: not an
  // edge that moved.
  uint64_t triangleDiffersOffEdge = 0;
  // Over pixels both cover with the same triangle:
  uint64_t sameTriangle = 0;
  double maxDepthRel = 0.0;   // |dA - dB| / dA
  double maxNormalRad = 0.0;  // angle between the normals
  double maxDiffuse = 0.0;    // max abs channel difference (rgba)
  double maxSpecular = 0.0;
  double maxEmissive = 0.0;
  // Where the largest differences are (x, y), for messages.
  int worstDepthX = -1, worstDepthY = -1, worstNormalX = -1, worstNormalY = -1;
  int worstMaterialX = -1, worstMaterialY = -1;

  std::string summary() const;  // one line of the figures above
};

// Throws ts::Error when the sizes differ or a G-buffer lacks triangle ids.
GBufferComparison compareGBuffers(const GBuffer& a, const GBuffer& b);

}  // namespace ts
