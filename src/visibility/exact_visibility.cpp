#include "visibility/exact_visibility.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <thread>

#ifndef TILESHADE_NO_EMBREE
#include <embree3/rtcore.h>
#endif

#include "shaders/material_planes.h"
#include "util/error.h"

namespace ts {

SurfacePoints surfacePoints(const GBuffer& g, const SceneCamera& camera) {
  const CameraIntrinsics in = CameraIntrinsics::from(camera, g.width, g.height);
  const glm::dmat4 worldFromView = glm::inverse(camera.viewFromWorld);
  const glm::dmat3 rotation(worldFromView);
  SurfacePoints s;
  s.width = g.width;
  s.height = g.height;
  s.position.assign(g.pixelCount(), glm::dvec3(0.0));
  s.normal.assign(g.pixelCount(), glm::vec3(0.0f));
  s.geometry.assign(g.pixelCount(), 0);
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      const size_t i = size_t(y) * size_t(g.width) + size_t(x);
      const double d = g.depth[i];
      if (!(d > 0.0)) continue;
      // ts_view_position in double (kernels/shading.h).
      const double nx = 2.0 * (x + 0.5) / g.width - 1.0, ny = 1.0 - 2.0 * (y + 0.5) / g.height;
      s.position[i] = glm::dvec3(
          worldFromView * glm::dvec4(nx * in.tanHalfFovX * d, ny * in.tanHalfFovY * d, -d, 1.0));
      const glm::dvec3 n = rotation * glm::dvec3(glm::vec3(g.normal[i]));
      const double len = glm::length(n);
      s.normal[i] = len > 0.0 ? glm::vec3(n / len) : glm::vec3(0.0f);
      s.geometry[i] = 1;
    }
  return s;
}

double visibilityEpsilon(double sceneDiagonal, glm::dvec3 p) {
  const double largest = std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)});
  return 1e-4 * sceneDiagonal + 64.0 * double(std::numeric_limits<float>::epsilon()) * largest;
}

#ifdef TILESHADE_NO_EMBREE

// A build without Embree (-DTILESHADE_WITH_EMBREE=OFF): refused in one line.
struct ExactVisibility::Impl {};

ExactVisibility::ExactVisibility(const Scene&) {
  throw Error("exact visibility: this tileshade is built without Embree (TILESHADE_WITH_EMBREE)");
}

ExactVisibility::~ExactVisibility() = default;

std::vector<uint8_t> ExactVisibility::visibility(const SurfacePoints&, const SceneLight&,
                                                 int) const {
  return {};
}

#else

struct ExactVisibility::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  // alphaMode MASK, for the occlusion filter: per triangle whether its material is alpha-tested,
  // its material and its vertices' UVs; the materials, and the textures the alpha test samples
  // (copied: the object does not keep the scene; the others are left empty).
  std::vector<uint8_t> masked;
  std::vector<uint32_t> material;
  std::vector<glm::vec2> uv;  // 3 per triangle
  std::vector<Material> materials;
  std::vector<Texture> textures;
  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

namespace {

std::string embreeError(RTCDevice device) {
  switch (rtcGetDeviceError(device)) {
    case RTC_ERROR_NONE: return "no error";
    case RTC_ERROR_INVALID_ARGUMENT: return "invalid argument";
    case RTC_ERROR_INVALID_OPERATION: return "invalid operation";
    case RTC_ERROR_OUT_OF_MEMORY: return "out of memory";
    case RTC_ERROR_UNSUPPORTED_CPU: return "unsupported CPU";
    case RTC_ERROR_CANCELLED: return "cancelled";
    default: return "unknown error";
  }
}

// The occlusion filter of an alpha-tested triangle: a hit where the material's alpha test leaves
// the surface out (ts_material_covered, the rasterizers' one test, at the hit's interpolated UV)
// is no occluder, so the ray goes on through the cut-out.
void maskedOccluderFilter(const RTCFilterFunctionNArguments* args) {
  const auto& impl = *static_cast<const ExactVisibility::Impl*>(args->geometryUserPtr);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    const uint32_t tri = RTCHitN_primID(args->hit, args->N, i);
    if (!impl.masked[tri]) continue;
    const double u = RTCHitN_u(args->hit, args->N, i), v = RTCHitN_v(args->hit, args->N, i);
    const glm::dvec2 uv0 = impl.uv[3 * tri], uv1 = impl.uv[3 * tri + 1], uv2 = impl.uv[3 * tri + 2];
    const glm::vec2 uv((1.0 - u - v) * uv0 + u * uv1 + v * uv2);  // Embree's barycentrics
    const Material& m = impl.materials[impl.material[tri]];
    const bool covered = ts_material_covered(m, [&](int slot) {
      const int texture = materialTexture(m, slot);
      return texture < 0 ? glm::vec4(1.0f) : impl.textures[size_t(texture)].sample(uv);
    });
    if (!covered) args->valid[i] = 0;
  }
}

}  // namespace

ExactVisibility::ExactVisibility(const Scene& scene) : impl_(std::make_unique<Impl>()) {
  triangles_ = scene.triangleCount();
  if (triangles_ == 0)
    throw Error("exact visibility: the scene has no triangles (nothing to cast a shadow)");
  const auto t0 = std::chrono::steady_clock::now();
  impl_->device = rtcNewDevice(nullptr);
  if (!impl_->device) throw Error("exact visibility: Embree could not create a device");
  RTCGeometry geometry = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  rtcSetGeometryBuildQuality(geometry, RTC_BUILD_QUALITY_HIGH);
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0,
                                                               RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                                               scene.vertices.size()));
  auto* indices = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(uint32_t), triangles_));
  if (!vertices || !indices) {
    const std::string why = embreeError(impl_->device);
    rtcReleaseGeometry(geometry);
    throw Error("exact visibility: Embree could not hold the scene's triangles: " + why);
  }
  Bounds bounds;
  for (size_t v = 0; v < scene.vertices.size(); ++v) {
    const glm::vec3 p = scene.vertices[v].position;
    std::memcpy(vertices + 3 * v, &p.x, 3 * sizeof(float));
    bounds.extend(p);
  }
  std::memcpy(indices, scene.indices.data(), scene.indices.size() * sizeof(uint32_t));
  diagonal_ = glm::length(glm::dvec3(bounds.extent()));
  // Alpha-tested triangles get the filter; a scene without any pays nothing.
  if (!scene.triangleMaterial.empty()) {
    impl_->masked.assign(triangles_, 0);
    bool any = false;
    for (size_t t = 0; t < triangles_; ++t) {
      impl_->masked[t] = scene.materials[scene.triangleMaterial[t]].alphaMode == AlphaMode::Mask;
      any = any || impl_->masked[t];
    }
    if (any) {
      Impl& m = *impl_;
      m.material = scene.triangleMaterial;
      m.materials = scene.materials;
      m.uv.resize(3 * triangles_);
      for (size_t k = 0; k < 3 * triangles_; ++k) m.uv[k] = scene.vertices[scene.indices[k]].uv;
      m.textures.resize(scene.textures.size());
      for (const Material& mat : scene.materials)
        if (mat.alphaMode == AlphaMode::Mask)
          for (int slot : {TS_TEXTURE_BASE_COLOR, TS_TEXTURE_DIFFUSE})
            if (const int t = materialTexture(mat, slot); t >= 0)
              m.textures[size_t(t)] = scene.textures[size_t(t)];
      rtcSetGeometryUserData(geometry, impl_.get());
      rtcSetGeometryOccludedFilterFunction(geometry, maskedOccluderFilter);
    } else {
      impl_->masked.clear();
    }
  }
  rtcCommitGeometry(geometry);
  impl_->scene = rtcNewScene(impl_->device);
  // Robust: watertight, so a ray through a shared edge or vertex hits one of its triangles.
  rtcSetSceneFlags(impl_->scene, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_HIGH);
  rtcAttachGeometry(impl_->scene, geometry);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(impl_->scene);
  if (rtcGetDeviceError(impl_->device) != RTC_ERROR_NONE)
    throw Error("exact visibility: Embree could not build its BVH: " + embreeError(impl_->device));
  buildMs_ =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

ExactVisibility::~ExactVisibility() = default;

std::vector<uint8_t> ExactVisibility::visibility(const SurfacePoints& points,
                                                 const SceneLight& light, int threads) const {
  std::vector<uint8_t> out(points.size(), kVisibilityNotApplicable);
  const bool directional = light.type == SceneLightType::Directional;
  const glm::dvec3 lightPos = light.position;
  const glm::dvec3 axis = glm::normalize(glm::dvec3(light.direction));
  const double range2 = double(light.range) * double(light.range);
  const double cosOuter = std::cos(double(light.outerConeAngle));
  RTCScene scene = impl_->scene;
  auto row = [&](int y) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    for (int x = 0; x < points.width; ++x) {
      const size_t i = size_t(y) * size_t(points.width) + size_t(x);
      if (!points.geometry[i]) continue;
      const glm::dvec3 p = points.position[i];
      const double eps = visibilityEpsilon(diagonal_, p);
      const glm::dvec3 origin = p + eps * glm::dvec3(points.normal[i]);
      glm::dvec3 dir;
      double tfar = std::numeric_limits<double>::infinity();
      if (directional) {
        dir = -axis;
      } else {
        // The shading's own applicability (ts_punctual_weights): inside the range, on no light.
        const glm::dvec3 v = lightPos - p;
        const double d2 = glm::dot(v, v);
        if (!(d2 < range2) || !(d2 > 0.0)) continue;
        if (light.type == SceneLightType::Spot && !(-glm::dot(axis, v / std::sqrt(d2)) > cosOuter))
          continue;
        const glm::dvec3 w = lightPos - origin;
        const double dist = glm::length(w);
        dir = w / dist;
        tfar = dist - eps;
        if (!(tfar > 0.0)) {  // the light within eps of the surface: nothing lies between
          out[i] = kVisibilityLit;
          continue;
        }
      }
      RTCRay ray;
      ray.org_x = float(origin.x);
      ray.org_y = float(origin.y);
      ray.org_z = float(origin.z);
      ray.dir_x = float(dir.x);
      ray.dir_y = float(dir.y);
      ray.dir_z = float(dir.z);
      ray.tnear = 0.0f;
      ray.tfar = float(tfar);
      ray.time = 0.0f;
      ray.mask = 0xFFFFFFFFu;
      ray.id = 0;
      ray.flags = 0;
      rtcOccluded1(scene, &context, &ray);
      // rtcOccluded1 sets tfar to -inf when something lies on the segment.
      out[i] = ray.tfar < 0.0f ? kVisibilityOccluded : kVisibilityLit;
    }
  };
  const int workers = std::max(
      1, std::min(points.height,
                  threads > 0 ? threads : int(std::max(1u, std::thread::hardware_concurrency()))));
  std::atomic<int> next{0};
  auto work = [&] {
    for (int y = next++; y < points.height; y = next++) row(y);
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < workers; ++t) pool.emplace_back(work);
  work();
  for (std::thread& t : pool) t.join();
  return out;
}

#endif  // TILESHADE_NO_EMBREE

}  // namespace ts
