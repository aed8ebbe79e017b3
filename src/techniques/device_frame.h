#pragma once
// One frame's inputs on the device, uploaded once and shared by every technique of a run.
#include <tuple>
#include <vector>

#include <glm/glm.hpp>

#include "cl/cl_context.h"
#include "gbuffer/gbuffer_layout.h"
#include "scene/scene.h"
#include "raster/forward_scene.h"
#include "raster/per_light_shadows.h"
#include "raster/sample_gbuffers.h"
#include "shading/view_lights.h"

namespace ts {

inline cl_float4 toCl(glm::vec4 v) { return {{v.x, v.y, v.z, v.w}}; }

struct DeviceFrame {
  const EncodedGBuffer* gbuffer = nullptr;  // host copy of what was uploaded
  const ViewLights* lights = nullptr;       // host copy of what was uploaded
  CameraIntrinsics camera;
  glm::vec3 ambient{0.0f};
  // The scene to draw, for the forward techniques (raster/forward_scene.h): set where the frame
  // was rasterized from a scene with OpenGL, null otherwise (software raster, imported G-buffer).
  ForwardScene* forward = nullptr;
  // The frame's shadow maps one light at a time, for a technique built with
  // ShadowStorage::PerLight (it draws them itself): set where the frame came from a scene with
  // shadow-casting lights, null otherwise.
  const PerLightShadowMaps* perLightShadows = nullptr;
  // --msaa: the frame's G-buffer per sample (raster/sample_gbuffers.h), for a G-buffer technique
  // that shades a multisampled G-buffer (tiled): set with `forward` where it has samples() > 1.
  SampleGBuffers* samples = nullptr;

  cl::Buffer depth, normal, diffuse, specular, emissive;  // G-buffer planes (absent: 1 element)
  cl::Buffer lightPositionRange, lightColor, lightSpot;   // at least one element each
  cl::Buffer directionalDir, directionalColor;            // at least one element each
  // Shadows (kernels/shadows.h): per light its first face (-1: none), the face table and the
  // atlas; one element each without shadows. Bound only by kernels built with TS_HAS_SHADOWS.
  cl::Buffer lightShadow, directionalShadow, shadowFaces, shadowAtlas;

  int width() const { return camera.width; }
  int height() const { return camera.height; }
  int lightCount() const { return int(lights->size()); }  // point and spot lights
  int directionalCount() const { return int(lights->directionalCount()); }

  // Kernel argument groups for KernelArgs::add: the five G-buffer planes (kernels/gbuffer.h
  // order), TS_LIGHT_PARAMS (position+range, colour, spot) and TS_DIRECTIONAL_PARAMS (direction,
  // colour, count).
  auto gbufferArgs() const { return std::tie(depth, normal, diffuse, specular, emissive); }
  auto lightArgs() const { return std::tie(lightPositionRange, lightColor, lightSpot); }
  std::tuple<const cl::Buffer&, const cl::Buffer&, int> directionalArgs() const {
    return {directionalDir, directionalColor, directionalCount()};
  }
  // What TS_LIGHT_PARAMS and TS_DIRECTIONAL_PARAMS add in a build with shadows (the features'
  // `shadows`): each group's first faces, the face table, the atlas. KernelArgs::addIf binds them
  // after lightArgs / directionalArgs.
  auto lightShadowArgs() const { return std::tie(lightShadow, shadowFaces, shadowAtlas); }
  auto directionalShadowArgs() const {
    return std::tie(directionalShadow, shadowFaces, shadowAtlas);
  }

  // The caller keeps gbuffer and lights alive while the frame is used.
  static DeviceFrame upload(ClContext& cl, const EncodedGBuffer& gbuffer,
                            const CameraIntrinsics& camera, const ViewLights& lights,
                            glm::vec3 ambient);
};

}  // namespace ts
