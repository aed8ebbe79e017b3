#include "scene/tangents.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <unordered_map>

namespace ts {
namespace {

// A vertex's position, normal and UV as bits (-0 read as +0): equal keys are one vertex.
using WeldKey = std::array<uint32_t, 8>;

struct WeldKeyHash {
  size_t operator()(const WeldKey& key) const {
    uint64_t h = 1469598103934665603ull;  // FNV-1a over the words
    for (uint32_t word : key) h = (h ^ word) * 1099511628211ull;
    return size_t(h);
  }
};

WeldKey weldKey(const glm::vec3& p, const glm::vec3& n, const glm::vec2& uv) {
  const float values[8] = {p.x + 0.0f, p.y + 0.0f, p.z + 0.0f,  n.x + 0.0f,
                           n.y + 0.0f, n.z + 0.0f, uv.x + 0.0f, uv.y + 0.0f};
  WeldKey key;
  std::memcpy(key.data(), values, sizeof values);
  return key;
}

// The welded vertex of every input vertex (the first input vertex with its key).
std::vector<uint32_t> weld(const std::vector<glm::vec3>& positions,
                           const std::vector<glm::vec3>& normals,
                           const std::vector<glm::vec2>& uvs) {
  std::unordered_map<WeldKey, uint32_t, WeldKeyHash> first;
  std::vector<uint32_t> welded(positions.size());
  for (size_t i = 0; i < positions.size(); ++i)
    welded[i] = first.emplace(weldKey(positions[i], normals[i], uvs[i]), uint32_t(i)).first->second;
  return welded;
}

// A triangle's unit dP/du and dP/dv and the sign of its UV area; usable = false for degenerate
// UVs (or a degenerate triangle), which give no frame.
struct FaceFrame {
  glm::dvec3 du{0.0}, dv{0.0};
  bool preserving = false;  // UV area > 0
  bool usable = false;
};

FaceFrame faceFrame(const glm::dvec3 p[3], const glm::dvec2 uv[3]) {
  // In double: far-from-origin positions and tiny triangles.
  const glm::dvec3 e1 = p[1] - p[0], e2 = p[2] - p[0];
  const glm::dvec2 d1 = uv[1] - uv[0], d2 = uv[2] - uv[0];
  // e = dP/du du + dP/dv dv for both edges: dP/du = (e1 d2.v - e2 d1.v) / det, and so on; only
  // the directions matter, so det enters by its sign.
  const double det = d1.x * d2.y - d2.x * d1.y;
  FaceFrame f;
  if (!(det != 0.0) || !std::isfinite(det)) return f;
  const double sign = det > 0.0 ? 1.0 : -1.0;
  const glm::dvec3 du = (e1 * d2.y - e2 * d1.y) * sign, dv = (e2 * d1.x - e1 * d2.x) * sign;
  const double lu = glm::length(du), lv = glm::length(dv);
  if (!(lu > 0.0) || !(lv > 0.0) || !std::isfinite(lu) || !std::isfinite(lv)) return f;
  f.du = du / lu;
  f.dv = dv / lv;
  f.preserving = det > 0.0;
  f.usable = true;
  return f;
}

// v without its component along the unit n, normalised; zero where nothing is left.
glm::dvec3 inPlane(const glm::dvec3& v, const glm::dvec3& n) {
  const glm::dvec3 t = v - n * glm::dot(n, v);
  const double length = glm::length(t);
  return length > 1e-12 * glm::length(v) && std::isfinite(length) ? t / length : glm::dvec3(0.0);
}

// The angle at corner p[0] of a triangle, between its edges projected onto the plane of n.
double cornerAngle(const glm::dvec3& p0, const glm::dvec3& p1, const glm::dvec3& p2,
                   const glm::dvec3& n) {
  const glm::dvec3 a = inPlane(p1 - p0, n), b = inPlane(p2 - p0, n);
  if (a == glm::dvec3(0.0) || b == glm::dvec3(0.0)) return 0.0;
  return std::acos(std::clamp(glm::dot(a, b), -1.0, 1.0));
}

// The sums of one (welded vertex, UV orientation): its corners' weighted in-plane tangents and
// bitangents.
struct Group {
  glm::dvec3 tangent{0.0}, bitangent{0.0};
  uint32_t welded = 0;
};

}  // namespace

GeneratedTangents generateTangents(const std::vector<glm::vec3>& positions,
                                   const std::vector<glm::vec3>& normals,
                                   const std::vector<glm::vec2>& uvs,
                                   const std::vector<uint32_t>& triangles) {
  const size_t n = positions.size();
  const std::vector<uint32_t> welded = weld(positions, normals, uvs);
  const size_t faces = triangles.size() / 3;

  // Every corner's group (welded vertex, orientation); corners of faces with degenerate UVs get
  // theirs after, from their vertex's groups.
  std::vector<Group> groups;
  std::unordered_map<uint64_t, uint32_t> groupOf;  // welded * 2 + preserving -> groups index
  constexpr uint32_t kNone = UINT32_MAX;
  std::vector<uint32_t> cornerGroup(faces * 3, kNone);
  for (size_t f = 0; f < faces; ++f) {
    glm::dvec3 p[3];
    glm::dvec2 uv[3];
    for (int k = 0; k < 3; ++k) {
      p[k] = glm::dvec3(positions[triangles[3 * f + size_t(k)]]);
      uv[k] = glm::dvec2(uvs[triangles[3 * f + size_t(k)]]);
    }
    const FaceFrame frame = faceFrame(p, uv);
    if (!frame.usable) continue;
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = triangles[3 * f + size_t(k)];
      const uint64_t key = uint64_t(welded[v]) * 2 + (frame.preserving ? 1 : 0);
      auto [it, added] = groupOf.emplace(key, uint32_t(groups.size()));
      if (added) groups.push_back(Group{glm::dvec3(0.0), glm::dvec3(0.0), welded[v]});
      Group& g = groups[it->second];
      const glm::dvec3 normal(normals[v]);
      const double angle = cornerAngle(p[k], p[(k + 1) % 3], p[(k + 2) % 3], normal);
      g.tangent += inPlane(frame.du, normal) * angle;
      g.bitangent += inPlane(frame.dv, normal) * angle;
      cornerGroup[3 * f + size_t(k)] = it->second;
    }
  }
  for (size_t c = 0; c < cornerGroup.size(); ++c) {
    if (cornerGroup[c] != kNone) continue;
    const uint64_t w = welded[triangles[c]];
    for (uint64_t key : {w * 2 + 1, w * 2})  // either orientation; the preserving one first
      if (auto it = groupOf.find(key); it != groupOf.end()) {
        cornerGroup[c] = it->second;
        break;
      }
  }

  // A vertex keeps its index for the first group of its corners; another group is a copy.
  GeneratedTangents out;
  out.triangles = triangles;
  out.tangents.assign(n, glm::vec4(0.0f));
  std::vector<uint32_t> firstGroup(n, kNone);
  std::unordered_map<uint64_t, uint32_t> copyOf;  // vertex << 32 | group -> output vertex
  std::vector<uint32_t> outputGroup(n, kNone);
  for (size_t c = 0; c < cornerGroup.size(); ++c) {
    const uint32_t g = cornerGroup[c], v = triangles[c];
    if (g == kNone) continue;
    if (firstGroup[v] == kNone) firstGroup[v] = outputGroup[v] = g;
    if (firstGroup[v] == g) continue;
    auto [it, added] = copyOf.emplace(uint64_t(v) << 32 | g, uint32_t(n + out.copies.size()));
    if (added) {
      out.copies.push_back(v);
      outputGroup.push_back(g);
      out.tangents.emplace_back(0.0f);
    }
    out.triangles[c] = it->second;
  }

  for (size_t i = 0; i < out.tangents.size(); ++i) {
    const uint32_t g = outputGroup[i];
    const uint32_t source = i < n ? uint32_t(i) : out.copies[i - n];
    const glm::dvec3 normal(normals[source]);
    const glm::dvec3 tangent = g == kNone ? glm::dvec3(0.0) : inPlane(groups[g].tangent, normal);
    if (tangent == glm::dvec3(0.0)) {
      ++out.withoutFrame;
      continue;
    }
    // glTF's bitangent points to -v: +1 when cross(N, T) runs against dP/dv.
    const double w = glm::dot(glm::cross(normal, tangent), groups[g].bitangent) <= 0.0 ? 1.0 : -1.0;
    out.tangents[i] = glm::vec4(glm::vec3(tangent), float(w));
  }
  return out;
}

}  // namespace ts
