#pragma once
// Exact visibility (issue #18): for every surface point of a frame and a light, whether the
// segment to the light crosses any of the scene's triangles, through Embree 3's ray queries. The
// answer a perfect shadow test gives, the second reference that shadow maps are measured against
// (docs/shadows.md, "Exact visibility").
#include <cstdint>
#include <memory>
#include <vector>

#include <glm/glm.hpp>

#include "gbuffer/gbuffer.h"
#include "scene/scene.h"

namespace ts {

// One value per (surface point, light).
enum : uint8_t {
  kVisibilityOccluded = 0,       // a triangle lies between the point and the light
  kVisibilityLit = 1,            // nothing does
  kVisibilityNotApplicable = 2,  // background, outside the light's range or cone, or on it
};

// World-space surface points: one per pixel of a G-buffer, row 0 at the top.
struct SurfacePoints {
  int width = 0;
  int height = 0;
  std::vector<glm::dvec3> position;  // world space
  std::vector<glm::vec3> normal;     // world space, unit; (0, 0, 0) = background
  std::vector<uint8_t> geometry;     // 1 where the pixel holds a surface, 0 = background
  size_t size() const { return position.size(); }
};

// The G-buffer's points in world space: the view-space position from depth as the reference
// reconstructs it (ts_view_position, in double), then the camera's inverse view matrix (double);
// the normal by the inverse view's rotation (the view is rigid).
SurfacePoints surfacePoints(const GBuffer& gbuffer, const SceneCamera& camera);

// How far a query's origin moves along the point's normal, and how much short of the light its
// segment stops: the points come from fp32 G-buffer planes (depth rounded to float's 2^-24
// relative, the triangles' vertices to float), so a point can lie a few ulps behind its own
// surface. 1e-4 of the scene's bounding-box diagonal, plus 64 float ulps of the point's largest
// coordinate (a scene far from the origin: at x = 1e4 an ulp is 1e-3).
double visibilityEpsilon(double sceneDiagonal, glm::dvec3 point);

// One Embree scene of all the triangles of `scene` (world space), built once (robust, watertight
// intersection: RTC_SCENE_FLAG_ROBUST; build quality high). Triangles are opaque occluders except
// where an alpha-tested material (glTF MASK) leaves its surface out: there the ray goes through,
// by the rasterizers' own test (ts_material_covered) at the hit's UV. Throws ts::Error for a
// scene without triangles or when Embree cannot start.
class ExactVisibility {
 public:
  explicit ExactVisibility(const Scene& scene);
  ~ExactVisibility();
  ExactVisibility(const ExactVisibility&) = delete;
  ExactVisibility& operator=(const ExactVisibility&) = delete;

  // kVisibility* per point of `points` for `light`: the segment from the point (moved by
  // visibilityEpsilon along its normal) to a point or spot light's position (stopping
  // visibilityEpsilon short), or towards −direction without end for a directional light.
  // Not applicable: background, a point at or beyond a point/spot light's range, outside a spot's
  // outer cone (where the shading gives the light no weight: kernels/shading.h). `threads` (0:
  // the hardware's) share the rows; the answer does not depend on their number.
  std::vector<uint8_t> visibility(const SurfacePoints& points, const SceneLight& light,
                                  int threads = 0) const;

  double buildMs() const { return buildMs_; }
  size_t triangles() const { return triangles_; }

  struct Impl;  // public for Embree's filter callback (exact_visibility.cpp)

 private:
  std::unique_ptr<Impl> impl_;
  double buildMs_ = 0.0;
  size_t triangles_ = 0;
  double diagonal_ = 0.0;
};

}  // namespace ts
