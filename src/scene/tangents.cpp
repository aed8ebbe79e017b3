#include "scene/tangents.h"

#include <cmath>

namespace ts {

std::vector<glm::vec4> generateTangents(const std::vector<glm::vec3>& positions,
                                        const std::vector<glm::vec3>& normals,
                                        const std::vector<glm::vec2>& uvs,
                                        const std::vector<uint32_t>& triangles,
                                        size_t* withoutFrame) {
  const size_t n = positions.size();
  // In double: the sums of many small triangles' terms, and far-from-origin positions.
  std::vector<glm::dvec3> sumU(n, glm::dvec3(0.0)), sumV(n, glm::dvec3(0.0));
  for (size_t t = 0; t + 2 < triangles.size(); t += 3) {
    const uint32_t i0 = triangles[t], i1 = triangles[t + 1], i2 = triangles[t + 2];
    const glm::dvec3 e1 = glm::dvec3(positions[i1]) - glm::dvec3(positions[i0]);
    const glm::dvec3 e2 = glm::dvec3(positions[i2]) - glm::dvec3(positions[i0]);
    const glm::dvec2 d1 = glm::dvec2(uvs[i1]) - glm::dvec2(uvs[i0]);
    const glm::dvec2 d2 = glm::dvec2(uvs[i2]) - glm::dvec2(uvs[i0]);
    // e = dP/du du + dP/dv dv for both edges; dP/du = (e1 d2.v - e2 d1.v) / det. Summed without
    // the 1/|det| (which would weight by inverse UV area) but with its sign: each triangle's
    // terms then weigh by its area in position space over its area in UV space times that UV
    // area, i.e. by its position-space area.
    const double det = d1.x * d2.y - d2.x * d1.y;
    if (!(det != 0.0) || !std::isfinite(det)) continue;  // degenerate UVs: no frame from it
    const double sign = det > 0.0 ? 1.0 : -1.0;
    const glm::dvec3 du = (e1 * d2.y - e2 * d1.y) * sign;
    const glm::dvec3 dv = (e2 * d1.x - e1 * d2.x) * sign;
    for (uint32_t i : {i0, i1, i2}) {
      sumU[i] += du;
      sumV[i] += dv;
    }
  }
  std::vector<glm::vec4> out(n, glm::vec4(0.0f));
  size_t missing = 0;
  for (size_t i = 0; i < n; ++i) {
    const glm::dvec3 normal(normals[i]);
    const glm::dvec3 t = sumU[i] - normal * glm::dot(normal, sumU[i]);  // Gram-Schmidt
    const double length = glm::length(t);
    if (!(length > 1e-12 * glm::length(sumU[i])) || !std::isfinite(length)) {
      ++missing;
      continue;
    }
    const glm::dvec3 tangent = t / length;
    // glTF's bitangent points to -v: +1 when cross(N, T) runs against dP/dv.
    const double w = glm::dot(glm::cross(normal, tangent), sumV[i]) <= 0.0 ? 1.0 : -1.0;
    out[i] = glm::vec4(glm::vec3(tangent), float(w));
  }
  if (withoutFrame) *withoutFrame = missing;
  return out;
}

}  // namespace ts
