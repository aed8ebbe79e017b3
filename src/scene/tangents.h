#pragma once
// Tangent frames for normal maps where a glTF file gives none (no TANGENT attribute). Not
// MikkTSpace (glTF's rule, which tileshade does not implement): per triangle, the tangent and
// bitangent that the UV mapping defines (dP/du, dP/dv), summed per vertex weighted by the
// triangle's area (the sums of unnormalised cross-product terms), then made orthogonal to the
// vertex normal (Gram-Schmidt). Where the two agree: meshes whose UVs are not mirrored or sheared
// within a smooth group. docs/features.md, "Normal maps", says where they differ.
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace ts {

// One tangent per vertex for the triangle list `triangles` (three vertex indices each, all below
// positions.size(); positions, normals and uvs have one entry per vertex): xyz unit and
// orthogonal to the (unit) normal, w = +1 or -1 the sign of glTF's bitangent, cross(normal,
// tangent) * w, so that it points towards -v (glTF's v runs down the image, its normal maps'
// green up). A vertex with no usable frame (every triangle at it has degenerate UVs, or its
// tangent is parallel to its normal) gets (0, 0, 0, 0) and is counted in *withoutFrame.
std::vector<glm::vec4> generateTangents(const std::vector<glm::vec3>& positions,
                                        const std::vector<glm::vec3>& normals,
                                        const std::vector<glm::vec2>& uvs,
                                        const std::vector<uint32_t>& triangles,
                                        size_t* withoutFrame = nullptr);

}  // namespace ts
