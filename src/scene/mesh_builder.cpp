#include "scene/mesh_builder.h"

#include <cmath>

#include "util/pi.h"

namespace ts {

uint32_t MeshBuilder::addMaterial(const Material& m) {
  s_.materials.push_back(m);
  return uint32_t(s_.materials.size() - 1);
}

uint32_t MeshBuilder::vertex(glm::vec3 p, glm::vec3 n, glm::vec2 uv) {
  Vertex v;
  v.position = p;
  float len = glm::length(n);
  v.normal = len > 0.0f ? n / len : glm::vec3(0.0f, 1.0f, 0.0f);
  v.uv = uv;
  s_.vertices.push_back(v);
  return uint32_t(s_.vertices.size() - 1);
}

// The winding follows the normals: a triangle whose geometric normal points against its vertex
// normals is flipped, so every primitive is counter-clockwise seen from the side its normals face.
void MeshBuilder::triangle(uint32_t a, uint32_t b, uint32_t c, uint32_t material) {
  const Vertex& va = s_.vertices[a];
  const Vertex& vb = s_.vertices[b];
  const Vertex& vc = s_.vertices[c];
  glm::vec3 g = glm::cross(vb.position - va.position, vc.position - va.position);
  if (glm::dot(g, g) <= 0.0f) return;  // degenerate (e.g. a sphere pole's zero-area sliver)
  if (glm::dot(g, va.normal + vb.normal + vc.normal) < 0.0f) std::swap(b, c);
  s_.indices.insert(s_.indices.end(), {a, b, c});
  s_.triangleMaterial.push_back(material);
}

void MeshBuilder::quad(glm::vec3 p0, glm::vec3 p1, glm::vec3 p2, glm::vec3 p3, uint32_t material,
                       glm::vec2 uvScale) {
  glm::vec3 n = glm::cross(p1 - p0, p2 - p0) + glm::cross(p2 - p0, p3 - p0);
  uint32_t a = vertex(p0, n, glm::vec2(0.0f, 0.0f) * uvScale);
  uint32_t b = vertex(p1, n, glm::vec2(1.0f, 0.0f) * uvScale);
  uint32_t c = vertex(p2, n, glm::vec2(1.0f, 1.0f) * uvScale);
  uint32_t d = vertex(p3, n, glm::vec2(0.0f, 1.0f) * uvScale);
  triangle(a, b, c, material);
  triangle(a, c, d, material);
}

void MeshBuilder::box(glm::vec3 lo, glm::vec3 hi, uint32_t material, bool bottom) {
  glm::vec3 c = 0.5f * (lo + hi), h = 0.5f * (hi - lo);
  for (int axis = 0; axis < 3; ++axis) {
    for (int sign = -1; sign <= 1; sign += 2) {
      if (!bottom && axis == 1 && sign < 0) continue;
      int ua = (axis + 1) % 3, va = (axis + 2) % 3;
      if (sign < 0) std::swap(ua, va);
      glm::vec3 n(0.0f), u(0.0f), v(0.0f);
      n[axis] = float(sign) * h[axis];
      u[ua] = h[ua];
      v[va] = h[va];
      quad(c + n - u - v, c + n + u - v, c + n + u + v, c + n - u + v, material,
           glm::vec2(2.0f * h[ua], 2.0f * h[va]));
    }
  }
}

void MeshBuilder::box(const glm::mat4& xf, uint32_t material) {
  // A mirroring transform would turn the faces inside out: walk their corners the other way.
  bool mirror = glm::determinant(glm::mat3(xf)) < 0.0f;
  for (int axis = 0; axis < 3; ++axis) {
    for (int sign = -1; sign <= 1; sign += 2) {
      int ua = (axis + 1) % 3, va = (axis + 2) % 3;
      if (sign < 0) std::swap(ua, va);
      glm::vec3 n(0.0f), u(0.0f), v(0.0f);
      n[axis] = 0.5f * float(sign);
      u[ua] = 0.5f;
      v[va] = 0.5f;
      auto at = [&](glm::vec3 p) { return glm::vec3(xf * glm::vec4(p, 1.0f)); };
      if (mirror) quad(at(n - u - v), at(n - u + v), at(n + u + v), at(n + u - v), material);
      else quad(at(n - u - v), at(n + u - v), at(n + u + v), at(n - u + v), material);
    }
  }
}

void MeshBuilder::frustum(glm::vec3 base, float r0, float r1, float height, int segments,
                          uint32_t material, bool caps) {
  const glm::vec3 up(0.0f, 1.0f, 0.0f);
  std::vector<uint32_t> bottomRing, topRing;
  for (int i = 0; i <= segments; ++i) {
    float t = float(i) / float(segments), a = 2.0f * kPi * t;
    glm::vec3 radial(std::cos(a), 0.0f, -std::sin(a));
    glm::vec3 n = height * radial + (r0 - r1) * up;
    bottomRing.push_back(vertex(base + r0 * radial, n, glm::vec2(t, 1.0f)));
    topRing.push_back(vertex(base + r1 * radial + height * up, n, glm::vec2(t, 0.0f)));
  }
  for (int i = 0; i < segments; ++i) {
    if (r0 > 0.0f) triangle(bottomRing[i], bottomRing[i + 1], topRing[i + 1], material);
    if (r1 > 0.0f) triangle(bottomRing[i], topRing[i + 1], topRing[i], material);
  }
  if (!caps) return;
  for (int end = 0; end < 2; ++end) {
    float r = end ? r1 : r0;
    if (r <= 0.0f) continue;
    glm::vec3 n = end ? up : -up;
    glm::vec3 c = base + (end ? height : 0.0f) * up;
    uint32_t centre = vertex(c, n, glm::vec2(0.5f));
    std::vector<uint32_t> ring;
    for (int i = 0; i <= segments; ++i) {
      float a = 2.0f * kPi * float(i) / float(segments);
      glm::vec3 radial(std::cos(a), 0.0f, -std::sin(a));
      ring.push_back(vertex(c + r * radial, n, 0.5f + 0.5f * glm::vec2(radial.x, radial.z)));
    }
    for (int i = 0; i < segments; ++i) triangle(centre, ring[i], ring[i + 1], material);
  }
}

void MeshBuilder::cylinder(glm::vec3 base, float radius, float height, int segments,
                           uint32_t material, bool caps) {
  frustum(base, radius, radius, height, segments, material, caps);
}

void MeshBuilder::sphere(glm::vec3 center, glm::vec3 radii, int slices, int stacks,
                         uint32_t material) {
  uint32_t first = uint32_t(s_.vertices.size());
  for (int j = 0; j <= stacks; ++j) {
    float v = float(j) / float(stacks), theta = kPi * v;  // 0 = north pole
    for (int i = 0; i <= slices; ++i) {
      float u = float(i) / float(slices), phi = 2.0f * kPi * u;
      glm::vec3 d(std::sin(theta) * std::cos(phi), std::cos(theta),
                  -std::sin(theta) * std::sin(phi));
      // Normal of an ellipsoid: the gradient of its implicit function.
      vertex(center + radii * d, d / radii, glm::vec2(u, v));
    }
  }
  uint32_t row = uint32_t(slices + 1);
  for (int j = 0; j < stacks; ++j) {
    for (int i = 0; i < slices; ++i) {
      uint32_t a = first + uint32_t(j) * row + uint32_t(i);
      uint32_t b = a + 1, c = a + row, d = a + row + 1;
      triangle(a, c, d, material);
      triangle(a, d, b, material);
    }
  }
}

void MeshBuilder::arch(glm::vec3 center, glm::vec3 along, float radius, float thickness,
                       float depth, int segments, uint32_t material) {
  const glm::vec3 up(0.0f, 1.0f, 0.0f);
  along = glm::normalize(along);
  glm::vec3 across = glm::normalize(glm::cross(along, up));
  float step = kPi / float(segments);
  float outer = radius + thickness;
  for (int k = 0; k < segments; ++k) {
    float a = (float(k) + 0.5f) * step;
    glm::vec3 radial = std::cos(a) * along + std::sin(a) * up;
    glm::vec3 tangent = -std::sin(a) * along + std::cos(a) * up;
    float length = 2.0f * outer * std::sin(0.5f * step) * 1.02f;  // slight overlap, no gaps
    glm::mat4 xf(1.0f);
    xf[0] = glm::vec4(tangent * length, 0.0f);
    xf[1] = glm::vec4(radial * thickness, 0.0f);
    xf[2] = glm::vec4(across * depth, 0.0f);
    xf[3] = glm::vec4(center + (radius + 0.5f * thickness) * radial, 1.0f);
    box(xf, material);
  }
}

void MeshBuilder::curtain(glm::vec3 topCenter, glm::vec3 along, float width, float height,
                          float amplitude, float waves, int columns, uint32_t material) {
  const glm::vec3 up(0.0f, 1.0f, 0.0f);
  along = glm::normalize(along);
  glm::vec3 across = glm::normalize(glm::cross(along, up));
  std::vector<uint32_t> top, bottom;
  for (int i = 0; i <= columns; ++i) {
    float u = float(i) / float(columns);
    float w = 2.0f * kPi * waves * u;
    glm::vec3 p = topCenter + (u - 0.5f) * width * along + amplitude * std::sin(w) * across;
    glm::vec3 dpdu = width * along + amplitude * 2.0f * kPi * waves * std::cos(w) * across;
    glm::vec3 n = glm::cross(dpdu, up);
    top.push_back(vertex(p, n, glm::vec2(u, 0.0f)));
    bottom.push_back(vertex(p - height * up, n, glm::vec2(u, 1.0f)));
  }
  for (int i = 0; i < columns; ++i) {
    triangle(top[i], bottom[i], bottom[i + 1], material);
    triangle(top[i], bottom[i + 1], top[i + 1], material);
  }
}

}  // namespace ts
