#include "raster/shadow_map_compare.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

#include "util/error.h"

namespace ts {
namespace {

// One face of one atlas: its texels by face coordinates, and which are covered.
struct FaceTexels {
  const ShadowAtlas& atlas;
  const ShadowFace& face;
  float far;

  bool inside(int x, int y) const { return x >= 0 && y >= 0 && x < face.size && y < face.size; }
  float at(int x, int y) const { return atlas.at(face.x + x, face.y + y); }
  bool covered(int x, int y) const { return at(x, y) < far; }

  // Whether the 3x3 neighbourhood (within the face; without its centre unless `centre`) holds
  // both covered and empty texels.
  bool mixed(int x, int y, bool centre) const {
    bool some = false, none = false;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx)
        if (inside(x + dx, y + dy) && (centre || dx || dy))
          (covered(x + dx, y + dy) ? some : none) = true;
    return some && none;
  }

  // Whether a covered 8-neighbour holds `depth` within `bound` (relative).
  bool holdsNear(int x, int y, double depth, double bound) const {
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx)
        if ((dx || dy) && inside(x + dx, y + dy) && covered(x + dx, y + dy) &&
            std::abs(double(at(x + dx, y + dy)) - depth) <= bound * depth)
          return true;
    return false;
  }

  // Whether the texel lies on an edge between the surfaces at depths a and b: its 8 neighbours
  // hold both.
  bool edgeBetween(int x, int y, double a, double b, double bound) const {
    return holdsNear(x, y, a, bound) && holdsNear(x, y, b, bound);
  }

  // Whether the texel's surface is one texel thin: both neighbours along x, or both along y, are
  // empty (or outside the face), so the map shows no slope across it.
  bool thin(int x, int y) const {
    auto empty = [&](int u, int v) { return !inside(u, v) || !covered(u, v); };
    return (empty(x - 1, y) && empty(x + 1, y)) || (empty(x, y - 1) && empty(x, y + 1));
  }

  // The largest depth step to a covered 4-neighbour: the map's slope at the texel.
  double slope(int x, int y) const {
    const double d = at(x, y);
    double g = 0.0;
    const int step[4][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
    for (const auto& s : step)
      if (inside(x + s[0], y + s[1]) && covered(x + s[0], y + s[1]))
        g = std::max(g, std::abs(double(at(x + s[0], y + s[1])) - d));
    return g;
  }
};

double largestCoordinate(const Scene& scene) {
  double w = 0.0;
  for (const Vertex& v : scene.vertices)
    for (int c = 0; c < 3; ++c) w = std::max(w, std::abs(double(v.position[c])));
  return w;
}

void checkSameLayout(const ShadowAtlas& a, const ShadowAtlas& b) {
  bool same = a.layout.width == b.layout.width && a.layout.height == b.layout.height &&
              a.layout.faces.size() == b.layout.faces.size() && a.depth.size() == b.depth.size() &&
              a.depth.size() == size_t(a.layout.width) * size_t(a.layout.height);
  for (size_t k = 0; same && k < a.layout.faces.size(); ++k) {
    const ShadowFace &fa = a.layout.faces[k], &fb = b.layout.faces[k];
    same = fa.x == fb.x && fa.y == fb.y && fa.size == fb.size && fa.view.zfar == fb.view.zfar;
  }
  if (!same) throw Error("comparing shadow atlases of different layouts");
}

}  // namespace

ShadowAtlasComparison compareShadowAtlases(const ShadowAtlas& a, const ShadowAtlas& b,
                                           const Scene& scene) {
  checkSameLayout(a, b);
  ShadowAtlasComparison c;
  const double coordinates = largestCoordinate(scene);
  std::vector<bool> inFace(a.depth.size(), false);
  for (size_t k = 0; k < a.layout.faces.size(); ++k) {
    const ShadowFace& f = a.layout.faces[k];
    const FaceTexels ta{a, f, float(f.view.zfar)}, tb{b, f, float(f.view.zfar)};
    const glm::dvec3 t(f.view.viewFromWorld[3]);
    const double worldScale = coordinates + std::max({std::abs(t.x), std::abs(t.y), std::abs(t.z)});
    for (int y = 0; y < f.size; ++y)
      for (int x = 0; x < f.size; ++x) {
        inFace[size_t(f.y + y) * size_t(a.layout.width) + size_t(f.x + x)] = true;
        ++c.texels;
        const bool ca = ta.covered(x, y), cb = tb.covered(x, y);
        c.coveredA += ca;
        c.coveredB += cb;
        c.silhouetteA += ta.mixed(x, y, true);
        if (ca != cb) {
          (ca ? c.onlyA : c.onlyB) += 1;
          // The neighbours without the texel itself: a one-texel hole is no silhouette.
          if (!ta.mixed(x, y, false) && !tb.mixed(x, y, false)) ++c.mismatchesOffSilhouette;
          continue;
        }
        if (!ca) continue;
        ++c.bothCovered;
        const double da = ta.at(x, y), db = tb.at(x, y);
        const double bound =
            kShadowFloatRel * (1.0 + worldScale / da) + 2.0 * kShadowSnapMove * ta.slope(x, y) / da;
        const double rel = std::abs(da - db) / da;
        if (rel > bound) {
          ++c.depthDiffers;
          if (ta.edgeBetween(x, y, da, db, bound) || tb.edgeBetween(x, y, da, db, bound)) continue;
          if (ta.thin(x, y)) {
            ++c.thinDiffers;
            c.maxThinDepthRel = std::max(c.maxThinDepthRel, rel);
            continue;
          }
          ++c.depthDiffersOffEdge;
        }
        c.maxDepthRel = std::max(c.maxDepthRel, rel);
        if (rel / bound > c.worstRatio) {
          c.worstRatio = rel / bound;
          c.worstFace = int(k);
          c.worstX = x;
          c.worstY = y;
        }
      }
  }
  for (size_t i = 0; i < a.depth.size(); ++i)
    if (!inFace[i] && (a.depth[i] != 0.0f || b.depth[i] != 0.0f)) ++c.unusedNonZero;
  return c;
}

std::string ShadowAtlasComparison::summary() const {
  std::ostringstream s;
  s << texels << " texels: covered " << coveredA << " / " << coveredB << " (both " << bothCovered
    << "), only A " << onlyA << ", only B " << onlyB << " (silhouette texels of A " << silhouetteA
    << ", off silhouette " << mismatchesOffSilhouette << "); another surface " << depthDiffers
    << " (one texel thin " << thinDiffers << ", max rel " << maxThinDepthRel << "; off edge "
    << depthDiffersOffEdge << "); max depth rel " << maxDepthRel << ", worst / bound " << worstRatio
    << " (face " << worstFace << " texel " << worstX << "," << worstY
    << "); unused texels not 0: " << unusedNonZero;
  return s.str();
}

}  // namespace ts
