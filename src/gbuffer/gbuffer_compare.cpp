#include "gbuffer/gbuffer_compare.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "util/error.h"

namespace ts {
namespace {

bool covered(const GBuffer& g, size_t i) { return g.depth[i] > 0.0f; }

// Whether any 8-neighbour of (x, y) (inside the image) satisfies `test(index)`.
template <typename Test>
bool anyNeighbour(const GBuffer& g, int x, int y, Test test) {
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      if (!dx && !dy) continue;
      const int nx = x + dx, ny = y + dy;
      if (nx < 0 || ny < 0 || nx >= g.width || ny >= g.height) continue;
      if (test(size_t(ny) * size_t(g.width) + size_t(nx))) return true;
    }
  return false;
}

bool onSilhouette(const GBuffer& g, int x, int y) {
  const bool c = covered(g, size_t(y) * size_t(g.width) + size_t(x));
  return anyNeighbour(g, x, y, [&](size_t j) { return covered(g, j) != c; });
}

double maxAbs(const glm::vec4& a, const glm::vec4& b) {
  double m = 0.0;
  for (int c = 0; c < 4; ++c) m = std::max(m, std::abs(double(a[c]) - double(b[c])));
  return m;
}

}  // namespace

GBufferComparison compareGBuffers(const GBuffer& a, const GBuffer& b) {
  if (a.width != b.width || a.height != b.height)
    throw Error("G-buffers of different sizes: " + std::to_string(a.width) + "x" +
                std::to_string(a.height) + " and " + std::to_string(b.width) + "x" +
                std::to_string(b.height));
  if (a.triangleId.size() != a.pixelCount() || b.triangleId.size() != b.pixelCount())
    throw Error("comparing G-buffers needs the triangle ids of both (RasterOptions::triangleIds)");
  GBufferComparison r;
  r.pixels = a.pixelCount();
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      const size_t i = size_t(y) * size_t(a.width) + size_t(x);
      const bool ca = covered(a, i), cb = covered(b, i);
      r.coveredA += ca;
      r.coveredB += cb;
      if (onSilhouette(a, x, y)) ++r.silhouetteA;
      if (ca != cb) {
        (ca ? r.onlyA : r.onlyB)++;
        if (!onSilhouette(a, x, y) && !onSilhouette(b, x, y)) ++r.mismatchesOffSilhouette;
        continue;
      }
      if (!ca) continue;
      ++r.bothCovered;
      const int32_t ta = a.triangleId[i], tb = b.triangleId[i];
      if (ta != tb) {
        ++r.triangleDiffers;
        const bool edge = anyNeighbour(a, x, y, [&](size_t j) { return a.triangleId[j] == tb; }) ||
                          anyNeighbour(b, x, y, [&](size_t j) { return b.triangleId[j] == ta; });
        if (!edge) ++r.triangleDiffersOffEdge;
        continue;
      }
      ++r.sameTriangle;
      const double da = a.depth[i], db = b.depth[i];
      const double rel = std::abs(da - db) / da;
      if (rel > r.maxDepthRel) {
        r.maxDepthRel = rel;
        r.worstDepthX = x;
        r.worstDepthY = y;
      }
      const glm::dvec3 na(a.normal[i]), nb(b.normal[i]);
      const double cosine = glm::dot(na, nb) / std::max(1e-300, glm::length(na) * glm::length(nb));
      // atan2 of |cross| and dot keeps precision for tiny angles (acos does not).
      const double angle =
          std::atan2(glm::length(glm::cross(na, nb)), cosine * glm::length(na) * glm::length(nb));
      if (angle > r.maxNormalRad) {
        r.maxNormalRad = angle;
        r.worstNormalX = x;
        r.worstNormalY = y;
      }
      const double dd = maxAbs(a.diffuse[i], b.diffuse[i]);
      const double ds = maxAbs(a.specular[i], b.specular[i]);
      const double de = maxAbs(a.emissive[i], b.emissive[i]);
      if (std::max({dd, ds, de}) > std::max({r.maxDiffuse, r.maxSpecular, r.maxEmissive})) {
        r.worstMaterialX = x;
        r.worstMaterialY = y;
      }
      r.maxDiffuse = std::max(r.maxDiffuse, dd);
      r.maxSpecular = std::max(r.maxSpecular, ds);
      r.maxEmissive = std::max(r.maxEmissive, de);
    }
  return r;
}

std::string GBufferComparison::summary() const {
  std::ostringstream s;
  s << "covered " << coveredA << " / " << coveredB << ", only-first " << onlyA << ", only-second "
    << onlyB << " (silhouette pixels " << silhouetteA << ", mismatches off silhouettes "
    << mismatchesOffSilhouette << "), other triangle " << triangleDiffers << " (off edges "
    << triangleDiffersOffEdge << "); same triangle " << sameTriangle << ": depth rel "
    << maxDepthRel << " at (" << worstDepthX << "," << worstDepthY << "), normal " << maxNormalRad
    << " rad at (" << worstNormalX << "," << worstNormalY << "), diffuse " << maxDiffuse
    << ", specular " << maxSpecular << ", emissive " << maxEmissive << " at (" << worstMaterialX
    << "," << worstMaterialY << ")";
  return s.str();
}

}  // namespace ts
