#pragma once
// Tangent frames for normal maps where a glTF file gives none (no TANGENT attribute), by the
// rules of MikkTSpace (Mikkelsen, "Simulation of Wrinkled Surfaces Revisited", 2008), which glTF
// asks for, implemented here from those rules (not its code, and not bit for bit its output):
// - corners with equal position, normal and UV are one vertex (welded), whatever their indices;
// - each triangle's tangent is the unit dP/du its UV mapping defines; at a corner it is projected
//   onto the plane of the vertex normal, normalised, and weighted by the corner's angle in that
//   plane (not by the triangle's area, so splitting a triangle does not move a frame);
// - a vertex's corners are summed per UV orientation (the sign of the triangle's UV area): where
//   a mirrored mapping meets the original (a mirrored seam) the vertex gets one frame per side,
//   so such a vertex is split in two.
// Not reproduced: MikkTSpace also separates same-orientation corners that share a vertex but no
// edge around it (non-manifold fans), and lets a triangle with degenerate UVs borrow the frame of
// its neighbours across edges; here such a corner takes its vertex's frame (either orientation).
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace ts {

struct GeneratedTangents {
  // One per output vertex: the input vertices, then the copies. xyz unit and orthogonal to the
  // (unit) normal, w = +1 or -1 the sign of glTF's bitangent, cross(normal, tangent) * w, so
  // that it points towards -v (glTF's v runs down the image, its normal maps' green up).
  // (0, 0, 0, 0): no usable frame (every triangle at it has degenerate UVs, or its tangent is
  // parallel to its normal); such vertices are counted in withoutFrame.
  std::vector<glm::vec4> tangents;
  // For each output vertex past the input's, the input vertex it duplicates (same position,
  // normal and UV; its other orientation's frame).
  std::vector<uint32_t> copies;
  // The input triangles with the corners that use a copy renumbered to it.
  std::vector<uint32_t> triangles;
  size_t withoutFrame = 0;
};

// The frames of the triangle list `triangles` (three vertex indices each, all below
// positions.size(); positions, normals and uvs have one entry per vertex).
GeneratedTangents generateTangents(const std::vector<glm::vec3>& positions,
                                   const std::vector<glm::vec3>& normals,
                                   const std::vector<glm::vec2>& uvs,
                                   const std::vector<uint32_t>& triangles);

}  // namespace ts
