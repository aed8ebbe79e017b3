// ts::Frame of tileshade.h: a PreparedFrame (the render command's frame) on a device, made from a
// scene, from G-buffer files, from the caller's host planes or from the caller's cl_mem buffers.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <optional>

#include "api/api_internal.h"
#include "gbuffer/gbuffer_checks.h"
#include "render/gbuffer_dump.h"
#include "render/receiver_rounding.h"
#include "reference/transparent_composite.h"
#include "render/render_input.h"
#include "scene/scene_loader.h"
#include "scene/shading_range.h"
#include "scene/view_space_lights.h"
#include "util/error.h"
#include "util/float_limit.h"
#include "util/option_values.h"
#include "util/pi.h"

namespace ts {
namespace {

std::string sizeText(int width, int height) {
  return std::to_string(width) + "x" + std::to_string(height);
}

// The FrameInfo fields every source fills the same way.
FrameInfo describeFrame(const RenderInput& input) {
  const PreparedFrame& f = input.frame;
  FrameInfo info;
  info.sceneName = input.sceneName;
  info.source = input.raster;
  info.sourceDetail = input.rasterDetail;
  info.triangles = input.triangles;
  info.frame = f.frame;
  info.width = f.intrinsics.width;
  info.height = f.intrinsics.height;
  info.layout = toString(f.encoded.format);
  info.shadingModel = toString(f.features.model);
  info.features = f.features.describe();
  info.bytesPerPixel = f.encoded.bytesPerPixel();
  info.geometryPixels = f.gbuffer.geometryPixels();
  info.lights = f.lights.size() + f.lights.directionalCount();
  info.directionalLights = f.lights.directionalCount();
  info.lightSummary = input.lightSummary;
  info.shadowCastingLights = input.shadowCasters;
  if (input.shadowAtlas) {
    const ShadowAtlas& a = *input.shadowAtlas;
    ShadowMapsInfo s;
    s.faces = a.layout.faces.size();
    s.atlasWidth = a.layout.width;
    s.atlasHeight = a.layout.height;
    s.bytes = a.layout.bytes();
    s.trianglesDrawn = a.trianglesDrawn();
    s.drawMs = a.drawMs;
    s.rasterizer = a.rasterizer;
    s.readMs = a.readMs;
    for (const ShadowLightMap& m : a.layout.lights)
      s.lights.push_back({m.light, toString(m.type), m.faces, m.requestedSize, m.size});
    s.notes = a.layout.notes;
    info.shadowMaps = std::move(s);
  }
  info.rasterMs = f.rasterMs;
  info.rasterSetupMs = input.rasterSetupMs;
  return info;
}

std::shared_ptr<Frame::Impl> uploaded(Device& device, RenderInput input) {
  auto impl = std::make_shared<Frame::Impl>();
  impl->device = device.impl();
  impl->info = describeFrame(input);  // before the frame moves out of `input`
  impl->prepared = std::move(input.frame);
  impl->onDevice = impl->prepared.upload(device.impl()->cl);
  impl->scene = std::move(input.scene);
  impl->rasterizer = std::move(input.rasterizer);
  impl->forward = std::move(input.forward);
  impl->shadowAtlas = std::move(input.shadowAtlas);
  if (impl->shadowAtlas && impl->scene)
    impl->perLightShadows =
        std::make_unique<PerLightShadowMaps>(*impl->scene, impl->shadowAtlas->layout);
  impl->onDevice.perLightShadows = impl->perLightShadows.get();
  impl->onDevice.forward = impl->forward.get();
  if (impl->forward && impl->forward->samples() > 1)
    impl->sampleGBuffers =
        std::make_unique<SampleGBuffers>(*impl->forward, impl->prepared.features);
  impl->onDevice.samples = impl->sampleGBuffers.get();
  impl->info.drawsScene = impl->forward != nullptr;
  impl->info.transparentDraws = impl->forward ? impl->forward->transparentDraws() : 0;
  impl->info.msaa = impl->forward ? impl->forward->samples() : 1;
  return impl;
}

void checkCamera(const Camera& c, int width, int height) {
  if (c.width != width || c.height != height)
    throw Error("the camera is " + sizeText(c.width, c.height) + " but the G-buffer is " +
                sizeText(width, height));
  if (!(std::isfinite(c.tanHalfFovX) && c.tanHalfFovX > 0.0f && std::isfinite(c.tanHalfFovY) &&
        c.tanHalfFovY > 0.0f))
    throw Error("camera: tanHalfFovX and tanHalfFovY must be finite and > 0, got " +
                fullPrecision(c.tanHalfFovX) + " and " + fullPrecision(c.tanHalfFovY));
  if (!(std::isfinite(c.znear) && std::isfinite(c.zfar) && c.znear > 0.0f && c.zfar > c.znear))
    throw Error("camera: must have 0 < znear < zfar (finite), got znear " + fullPrecision(c.znear) +
                ", zfar " + fullPrecision(c.zfar));
  for (float v : c.viewFromWorld)
    if (!std::isfinite(v)) throw Error("camera: viewFromWorld holds a value that is not finite");
}

CameraIntrinsics intrinsicsOf(const Camera& c) {
  CameraIntrinsics in;
  in.width = c.width;
  in.height = c.height;
  in.tanHalfFovX = c.tanHalfFovX;
  in.tanHalfFovY = c.tanHalfFovY;
  in.znear = c.znear;
  in.zfar = c.zfar;
  return in;
}

glm::vec3 vec3(const Float3& v) { return {v[0], v[1], v[2]}; }

// What lights.json's reader checks of each light (gbuffer_files.cpp), for the API's lights; then
// the view transform and ViewLights' own layout (toViewSpace, as a scene's lights).
ViewLights viewLights(const Lights& lights, const Camera& camera, ShadingRangeTerms& range) {
  std::vector<SceneLight> scene;
  for (size_t i = 0; i < lights.lights.size(); ++i) {
    const Light& l = lights.lights[i];
    const char* type = l.type == LightType::Point  ? "point"
                       : l.type == LightType::Spot ? "spot"
                                                   : "directional";
    if (l.type != LightType::Point && l.type != LightType::Spot && l.type != LightType::Directional)
      throw Error("light " + std::to_string(i) + ": unknown type " + std::to_string(int(l.type)));
    const std::string where = "light " + std::to_string(i) + " (" + type + "): ";
    for (float c : l.color)
      if (!(std::isfinite(c) && c >= 0.0f))
        throw Error(where + "color must be finite and >= 0, got " + fullPrecision(c));
    SceneLight s;
    s.type = SceneLightType(int(l.type));
    s.color = vec3(l.color);
    if (l.type != LightType::Directional) {
      for (float p : l.position)
        if (!std::isfinite(p)) throw Error(where + "position must be finite");
      if (!(std::isfinite(l.range) && l.range > 0.0f))
        throw Error(where + "range must be finite and > 0, got " + fullPrecision(l.range));
      s.position = glm::dvec3(vec3(l.position));
      s.range = l.range;
    }
    if (l.type != LightType::Point) {
      const double length = glm::length(glm::dvec3(vec3(l.direction)));
      if (!(std::abs(length - 1.0) <= 1e-5))
        throw Error(where + "direction must be a unit vector, its length is " +
                    fullPrecision(length));
      s.direction = vec3(l.direction);
    }
    if (l.type == LightType::Spot) {
      const double inner = l.innerConeAngle, outer = l.outerConeAngle;
      if (!(withinFloatRounding(inner, 0.0, kHalfPi) && withinFloatRounding(outer, 0.0, kHalfPi) &&
            inner < outer))
        throw Error(where +
                    "must satisfy 0 <= innerConeAngle < outerConeAngle <= pi/2, got inner " +
                    fullPrecision(inner) + ", outer " + fullPrecision(outer));
      s.innerConeAngle = float(std::clamp(inner, 0.0, kHalfPi));
      s.outerConeAngle = float(std::clamp(outer, 0.0, kHalfPi));
    }
    range.addLight(s.color);
    scene.push_back(s);
  }
  for (float c : lights.ambient)
    if (!(std::isfinite(c) && c >= 0.0f))
      throw Error("ambient must be finite and >= 0, got " + fullPrecision(c));
  range.ambient = std::max({lights.ambient[0], lights.ambient[1], lights.ambient[2]});
  glm::mat4 view;
  std::memcpy(&view[0][0], camera.viewFromWorld.data(), sizeof(float) * 16);
  return toViewSpace(scene, glm::dmat4(view));
}

// The frame's features from what its planes and lights hold (as an imported frame's).
SceneFeatures featuresOf(const EncodedGBuffer& e, const ViewLights& lights) {
  SceneFeatures f = SceneFeatures::general(e.model);
  if (e.model == ShadingModel::BlinnPhong) f.specular = e.hasSpecular;
  f.emissive = e.hasEmissive;
  f.textures = false;  // nothing was sampled: the planes are the caller's
  f.point = f.spot = false;
  for (size_t i = 0; i < lights.size(); ++i) (lights.isSpot(i) ? f.spot : f.point) = true;
  f.directional = lights.directionalCount() > 0;
  f.normalMaps = false;  // nothing was rasterized
  return f;
}

// Bytes per pixel of each plane of `e` (depth, normal, diffuse, specular, emissive); 0 = absent.
std::array<size_t, 5> planeBytes(const EncodedGBuffer& e) {
  const bool packed = e.format == GBufferFormat::PACKED;
  const size_t element = e.format == GBufferFormat::FP32 ? 16 : packed ? 4 : 8;
  size_t specular = 0;
  if (e.hasSpecularPlane()) specular = e.model == ShadingModel::MetallicRoughness ? 1 : element;
  return {sizeof(float), element, element, specular, e.hasEmissive ? (packed ? 8 : element) : 0};
}

// The planes' layout, model and size as a HostGBuffer or DeviceGBuffer names them, checked.
EncodedGBuffer planesLayout(int width, int height, const std::string& layout,
                            const std::string& shadingModel, bool specular, bool emissive) {
  checkInteger("G-buffer width", width, 1, kMaxImageSide);
  checkInteger("G-buffer height", height, 1, kMaxImageSide);
  EncodedGBuffer e;
  e.width = width;
  e.height = height;
  e.format = gbufferFormatNames().parse(layout);
  e.model = parseShadingModel(shadingModel);
  if (e.model == ShadingModel::MetallicRoughness) {
    e.hasSpecular = true;  // the model always has its specular lobe (roughness)
    if (e.format != GBufferFormat::PACKED && specular)
      throw Error("metallic-roughness " + layout +
                  " keeps roughness in the normal's w: its specular plane must be null");
    if (e.format == GBufferFormat::PACKED && !specular)
      throw Error("metallic-roughness packed needs its specular plane (the roughness byte)");
  } else {
    e.hasSpecular = specular;
  }
  e.hasEmissive = emissive;
  return e;
}

// The full-precision G-buffer the encoded planes decode to (what the import would have read).
GBuffer decodePlanes(const EncodedGBuffer& e) {
  GBuffer g;
  g.resize(e.width, e.height);
  g.model = e.model;
  g.depth = e.depth;
  std::vector<glm::vec4>* planes[] = {&g.normal, &g.diffuse, &g.specular, &g.emissive};
  for (size_t i = 0; i < e.pixelCount(); ++i) {
    if (!(g.depth[i] > 0.0f)) continue;  // background stays zero, as rasterized
    for (int p = 0; p < 4; ++p) (*planes[p])[i] = decodeStored(e, GBufferPlane(p), i);
  }
  return g;
}

// The checks, features and bookkeeping shared by fromHost and fromDevice, once `encoded` holds at
// least depth; `values` = whether every plane is on the host to check.
std::shared_ptr<Frame::Impl> assemble(Device& device, EncodedGBuffer encoded, const Camera& camera,
                                      const Lights& lights, const std::string& source,
                                      bool values) {
  checkCamera(camera, encoded.width, encoded.height);
  auto impl = std::make_shared<Frame::Impl>();
  impl->device = device.impl();
  PreparedFrame& f = impl->prepared;
  f.intrinsics = intrinsicsOf(camera);
  f.camera.viewFromWorld = glm::dmat4(1.0);  // the lights are in view space from here on
  f.camera.yfov = 2.0f * std::atan(camera.tanHalfFovY);
  f.camera.znear = camera.znear;
  f.camera.zfar = camera.zfar;
  f.raster = RasterBackend::Software;
  ShadingRangeTerms range;
  if (values) {
    f.gbuffer = decodePlanes(encoded);
    range = checkGBufferValues(f.gbuffer, camera.znear, source + " G-buffer");
  } else {
    f.gbuffer.width = encoded.width;
    f.gbuffer.height = encoded.height;
    f.gbuffer.model = encoded.model;
    f.gbuffer.depth = encoded.depth;
  }
  f.lights = viewLights(lights, camera, range);
  f.ambient = vec3(lights.ambient);
  if (values) checkShadingRange(range, "the " + source + " G-buffer with its lights");
  f.encoded = std::move(encoded);
  f.features = featuresOf(f.encoded, f.lights);
  RenderInput described;
  described.sceneName = source;
  described.raster = source;
  described.rasterDetail = source + " planes";
  described.lightSummary = describeLights([&] {
    std::vector<SceneLight> types;
    for (const Light& l : lights.lights) types.emplace_back().type = SceneLightType(int(l.type));
    return types;
  }());
  described.frame.intrinsics = f.intrinsics;
  described.frame.encoded.format = f.encoded.format;
  impl->info = describeFrame(described);
  // describeFrame read an empty frame for what only the real one has.
  impl->info.layout = toString(f.encoded.format);
  impl->info.shadingModel = toString(f.features.model);
  impl->info.features = f.features.describe();
  impl->info.bytesPerPixel = f.encoded.bytesPerPixel();
  impl->info.geometryPixels = f.gbuffer.geometryPixels();
  impl->info.lights = f.lights.size() + f.lights.directionalCount();
  impl->info.directionalLights = f.lights.directionalCount();
  return impl;
}

size_t checkedPixels(int width, int height) { return size_t(width) * size_t(height); }

}  // namespace

const FrameInfo& Frame::info() const { return impl_->info; }

Frame Frame::fromScene(Device& device, const SceneRequest& r) {
  return openclErrorsAsTs([&] {
    checkInteger("--light-count", r.lightCount, -1, kMaxLightCount);
    checkNumber("--light-range", r.lightRange, NumberRule::AtLeastZero);
    checkNumber("--light-threshold", r.lightThreshold, NumberRule::AtLeastZero);
    checkInteger("--width", r.width, 1, kMaxImageSide);
    checkInteger("--height", r.height, 1, kMaxImageSide);
    checkInteger("--frame", r.frame, 0, INT32_MAX);
    if (r.shadingModel != "auto") parseShadingModel(r.shadingModel);
    PipelineOptions o;
    o.scene = r.scene;
    o.lightSet = r.lights;
    o.lightCount = r.lightCount;
    o.lightRange = r.lightRange;
    o.lightThreshold = r.lightThreshold;
    o.variant = r.variant;
    o.normalMaps = r.normalMaps;
    o.shadows = r.shadows;
    o.shadowMapSize = r.shadowMapSize;
    o.shadowBudgetMB = r.shadowBudgetMB;
    o.blend = blendPolicyNames().parseOption("--blend", r.blend);
    o.shadowFilter = r.shadowFilter;
    o.shadowBias = r.shadowBias;
    o.shadingModel = r.shadingModel;
    o.features = r.features;
    o.seed = r.seed;
    o.width = r.width;
    o.height = r.height;
    o.format = gbufferFormatNames().parseOption("--gbuffer", r.layout);
    o.raster = rasterBackendNames().parseOption("--raster", r.raster);
    o.msaa = r.msaa;
    checkMsaa(o.msaa, o.raster);
    RenderInput input = outOfMemoryAs("loading and rasterizing " + r.scene,
                                      [&] { return loadSceneInput(o, r.frame); });
    return Frame(uploaded(device, std::move(input)));
  });
}

Frame Frame::fromFiles(Device& device, const std::string& dirOrDescriptor,
                       const std::string& layout) {
  return openclErrorsAsTs([&] {
    std::optional<GBufferFormat> format;
    if (!layout.empty()) format = gbufferFormatNames().parseOption("--gbuffer", layout);
    RenderInput input = outOfMemoryAs("loading and rasterizing " + dirOrDescriptor, [&] {
      return loadImportedInput(dirOrDescriptor, format, "auto");
    });
    return Frame(uploaded(device, std::move(input)));
  });
}

Frame Frame::fromHost(Device& device, const HostGBuffer& planes, const Camera& camera,
                      const Lights& lights) {
  return openclErrorsAsTs([&] {
    EncodedGBuffer e = planesLayout(planes.width, planes.height, planes.layout, planes.shadingModel,
                                    planes.specular != nullptr, planes.emissive != nullptr);
    if (!planes.depth || !planes.normal || !planes.diffuse)
      throw Error(std::string("host G-buffer: the ") +
                  (!planes.depth    ? "depth"
                   : !planes.normal ? "normal"
                                    : "diffuse") +
                  " plane is null (depth, normal and diffuse are required)");
    const size_t n = checkedPixels(e.width, e.height);
    const std::array<size_t, 5> bytes = planeBytes(e);
    e.depth.assign(planes.depth, planes.depth + n);
    const void* sources[] = {planes.normal, planes.diffuse, planes.specular, planes.emissive};
    std::vector<uint8_t>* targets[] = {&e.normal, &e.diffuse, &e.specular, &e.emissive};
    for (int p = 0; p < 4; ++p)
      if (bytes[size_t(p) + 1] && sources[p]) {
        const auto* b = static_cast<const uint8_t*>(sources[p]);
        targets[p]->assign(b, b + n * bytes[size_t(p) + 1]);
      }
    auto impl = outOfMemoryAs("taking a " + sizeText(e.width, e.height) + " host G-buffer", [&] {
      return assemble(device, std::move(e), camera, lights, "host", true);
    });
    impl->onDevice = impl->prepared.upload(device.impl()->cl);
    return Frame(impl);
  });
}

namespace {

size_t memSize(cl_mem buffer) {
  size_t size = 0;
  if (clGetMemObjectInfo(buffer, CL_MEM_SIZE, sizeof size, &size, nullptr) != CL_SUCCESS)
    throw Error("device G-buffer: a plane is not a valid cl_mem buffer");
  return size;
}

cl_context memContext(cl_mem buffer) {
  cl_context context = nullptr;
  clGetMemObjectInfo(buffer, CL_MEM_CONTEXT, sizeof context, &context, nullptr);
  return context;
}

}  // namespace

Frame Frame::fromDevice(Device& device, const DeviceGBuffer& planes, const Camera& camera,
                        const Lights& lights) {
  return openclErrorsAsTs([&] {
    if (!device.impl()->own)
      throw Error(
          "Frame::fromDevice needs a Device made by Device::fromOpenCL (the buffers' "
          "context)");
    EncodedGBuffer e = planesLayout(planes.width, planes.height, planes.layout, planes.shadingModel,
                                    planes.specular != nullptr, planes.emissive != nullptr);
    if (!planes.depth || !planes.normal || !planes.diffuse)
      throw Error(std::string("device G-buffer: the ") +
                  (!planes.depth    ? "depth"
                   : !planes.normal ? "normal"
                                    : "diffuse") +
                  " buffer is null (depth, normal and diffuse are required)");
    const size_t n = checkedPixels(e.width, e.height);
    const std::array<size_t, 5> bytes = planeBytes(e);
    const cl_mem buffers[] = {planes.depth, planes.normal, planes.diffuse, planes.specular,
                              planes.emissive};
    static const char* const kNames[] = {"depth", "normal", "diffuse", "specular", "emissive"};
    ClContext& cl = device.impl()->cl;
    for (int p = 0; p < 5; ++p) {
      if (!buffers[p] || !bytes[size_t(p)]) continue;
      const size_t want = n * bytes[size_t(p)], have = memSize(buffers[p]);
      if (have < want)
        throw Error(std::string("device G-buffer: the ") + kNames[p] + " buffer holds " +
                    std::to_string(have) + " bytes, a " + sizeText(e.width, e.height) + " " +
                    planes.layout + " plane needs " + std::to_string(want));
      if (memContext(buffers[p]) != cl.context()())
        throw Error(std::string("device G-buffer: the ") + kNames[p] +
                    " buffer belongs to another OpenCL context than the Device's");
    }
    // The techniques' counters read the depth on the host (which pixels are geometry): 4 bytes a
    // pixel come back; the other planes stay where they are until a reference needs them.
    e.depth.resize(n);
    cl.queue().enqueueReadBuffer(cl::Buffer(planes.depth, true), CL_TRUE, 0, n * sizeof(float),
                                 e.depth.data());
    for (size_t i = 0; i < n; ++i)
      if (!std::isfinite(e.depth[i]) || e.depth[i] < 0.0f)
        throw Error("device G-buffer: depth " + fullPrecision(e.depth[i]) + " at " +
                    pixelText(int(i % size_t(e.width)), int(i / size_t(e.width))) +
                    " is not a linear view depth (finite, >= 0)");
    auto impl = assemble(device, std::move(e), camera, lights, "device", false);
    impl->devicePlanes = planes;
    impl->hostPlanesComplete = false;
    // The caller's buffers as the frame's planes; the lights are uploaded as any frame's.
    DeviceFrame& d = impl->onDevice;
    d = DeviceFrame::upload(cl, EncodedGBuffer{}, impl->prepared.intrinsics, impl->prepared.lights,
                            impl->prepared.ambient);
    d.gbuffer = &impl->prepared.encoded;
    d.lights = &impl->prepared.lights;
    cl::Buffer* targets[] = {&d.depth, &d.normal, &d.diffuse, &d.specular, &d.emissive};
    for (int p = 0; p < 5; ++p)
      if (buffers[p] && bytes[size_t(p)]) *targets[p] = cl::Buffer(buffers[p], true);
    return Frame(impl);
  });
}

void Frame::Impl::readHostPlanes() {
  if (hostPlanesComplete) return;
  ClContext& cl = device->cl;
  EncodedGBuffer& e = prepared.encoded;
  const size_t n = e.pixelCount();
  const std::array<size_t, 5> bytes = planeBytes(e);
  const cl_mem buffers[] = {devicePlanes->normal, devicePlanes->diffuse, devicePlanes->specular,
                            devicePlanes->emissive};
  std::vector<uint8_t>* targets[] = {&e.normal, &e.diffuse, &e.specular, &e.emissive};
  for (int p = 0; p < 4; ++p) {
    if (!buffers[p] || !bytes[size_t(p) + 1]) continue;
    targets[p]->resize(n * bytes[size_t(p) + 1]);
    cl.queue().enqueueReadBuffer(cl::Buffer(buffers[p], true), CL_TRUE, 0, targets[p]->size(),
                                 targets[p]->data());
  }
  prepared.gbuffer = decodePlanes(e);
  // The caller's planes are seen here for the first time: the checks fromHost makes, before a
  // reference or a dump is made of them (a NaN normal is one line naming its pixel).
  const ShadingRangeTerms range =
      checkGBufferValues(prepared.gbuffer, prepared.intrinsics.znear, "device G-buffer");
  checkShadingRange(range, "the device G-buffer with its lights");
  hostPlanesComplete = true;
}

const EncodedGBuffer& Frame::Impl::planesShadedBy(bool drawsScene) {
  readHostPlanes();
  if (!drawsScene || prepared.encoded.format == GBufferFormat::FP32) return prepared.encoded;
  if (!fp32Planes) fp32Planes = encode(prepared.gbuffer, GBufferFormat::FP32);
  return *fp32Planes;
}

void Frame::Impl::compositeTransparentSurfaces(FrameReferences& r, bool drawsScene) {
  // --blend blend: the G-buffer holds the opaque surfaces; the forward techniques and the
  // hybrid ones (tiled) blend the transparent ones over them, so their references composite the
  // same fragments in the same order (the other G-buffer techniques refuse such a frame).
  if (!forward || forward->transparentDraws() == 0) return;
  const PreparedFrame& p = prepared;
  std::vector<TransparentFragment> fragments =
      forward->captureTransparent(p.features, kCaptureBound);
  const EncodedGBuffer& planes = planesShadedBy(drawsScene);
  compositeTransparent(r.reference, fragments, p.lights, p.ambient, int(RangeModel::Windowed),
                       planes);
  compositeTransparent(r.shadingOnly, fragments, p.lights, p.ambient, int(RangeModel::Windowed),
                       planes);
  compositeTransparent(r.physical, fragments, p.lights, p.ambient, int(RangeModel::Physical),
                       planes);
  r.transparentFragments = fragments.size();
  r.fragments = std::move(fragments);
}

const std::vector<EncodedGBuffer>& Frame::Impl::samplePlanes(bool drawsScene) {
  return drawsScene ? sampleGBuffers->fp32() : sampleGBuffers->like(prepared.encoded);
}

const FrameReferences& Frame::Impl::ensureSampleReferences(const PassProgress& pass,
                                                           bool drawsScene) {
  std::optional<FrameReferences>& sampleReferences =
      drawsScene ? drawnSampleReferences : gbufferSampleReferences;
  if (sampleReferences) return *sampleReferences;
  const PreparedFrame& p = prepared;
  outOfMemoryAs("computing the per-sample references of a " +
                    sizeText(p.intrinsics.width, p.intrinsics.height) + " MSAA frame",
                [&] {
                  const std::vector<EncodedGBuffer>& planes = samplePlanes(drawsScene);
                  // The shadow tests get their slack, as without MSAA.
                  std::optional<ReceiverRounding> rounding;
                  if (scene) rounding = receiverRounding(*scene, p.camera.viewFromWorld);
                  const ReceiverRounding* slack = rounding ? &*rounding : nullptr;
                  auto shade = [&](int model, ReferencePositions positions, const char* label) {
                    auto progress = [&](size_t k) {
                      return pass ? pass(label + (", sample " + std::to_string(k))) : RowProgress();
                    };
                    return shadeSampleAverage(planes, p.intrinsics, p.lights, p.ambient, model,
                                              positions, slack, progress);
                  };
                  FrameReferences r;
                  r.reference = shade(int(RangeModel::Windowed), ReferencePositions::FromDepth,
                                      "windowed model");
                  r.shadingOnly = shade(int(RangeModel::Windowed), ReferencePositions::KernelFloat,
                                        "windowed model, kernel positions");
                  r.physical = shade(int(RangeModel::Physical), ReferencePositions::FromDepth,
                                     "physical model");
                  sampleReferences = std::move(r);
                });
  return *sampleReferences;
}

const FrameReferences& Frame::Impl::ensureReferences(const PassProgress& pass, bool drawsScene) {
  if (multisampled()) return ensureSampleReferences(pass, drawsScene);
  // The references of the techniques that draw the scene apart where they differ: other planes
  // than the frame's layout (transparent surfaces are composited over both).
  const bool drawn = drawsScene && prepared.encoded.format != GBufferFormat::FP32;
  std::optional<FrameReferences>& cached = drawn ? drawnReferences : references;
  if (cached) return *cached;
  const EncodedGBuffer& planes = planesShadedBy(drawsScene);
  const PreparedFrame& p = prepared;
  const int model = int(RangeModel::Windowed);
  auto progress = [&](const char* label) { return pass ? pass(label) : RowProgress(); };
  outOfMemoryAs("computing the double-precision reference of a " +
                    sizeText(p.intrinsics.width, p.intrinsics.height) + " frame",
                [&] {
                  FrameReferences r;
                  // The references also give the shadow tests' slack over the receiver's float
                  // rounding (a forward fragment's interpolation, a kernel's float position and
                  // light-space transform; reference.h, ReceiverRounding), which every comparison
                  // allows. An imported G-buffer has no scene to bound the view transform's
                  // coordinates by: no slack.
                  std::optional<ReceiverRounding> rounding;
                  if (scene) rounding = receiverRounding(*scene, p.camera.viewFromWorld);
                  const ReceiverRounding* slack = rounding ? &*rounding : nullptr;
                  r.reference = shadeReference(planes, p.intrinsics, p.lights, p.ambient, model, 0,
                                               progress("windowed model"),
                                               ReferencePositions::FromDepth, nullptr, slack);
                  r.shadingOnly = shadeReference(planes, p.intrinsics, p.lights, p.ambient, model,
                                                 0, progress("windowed model, kernel positions"),
                                                 ReferencePositions::KernelFloat, nullptr, slack);
                  if (drawn) {
                    r.physical = shadeReference(
                        planes, p.intrinsics, p.lights, p.ambient, int(RangeModel::Physical), 0,
                        progress("physical model"), ReferencePositions::FromDepth, nullptr, slack);
                  } else {
                    const EncodedGBuffer fp32 = p.encoded.format == GBufferFormat::FP32
                                                    ? p.encoded
                                                    : encode(p.gbuffer, GBufferFormat::FP32);
                    r.physical = shadeReference(
                        fp32, p.intrinsics, p.lights, p.ambient, int(RangeModel::Physical), 0,
                        progress("physical model"), ReferencePositions::FromDepth, nullptr, slack);
                  }
                  compositeTransparentSurfaces(r, drawsScene);
                  cached = std::move(r);
                });
  return *cached;
}

const FrameReferences& frameReferences(const Frame& frame, const PassProgress& pass,
                                       bool drawsScene) {
  return frame.impl()->ensureReferences(pass, drawsScene);
}

void overrideFrameFeatures(Frame& frame, const std::string& features) {
  Frame::Impl& f = *frame.impl();
  f.prepared.features = chooseFeatures(features, f.prepared.features);
  f.info.features = f.prepared.features.describe();
  f.info.shadingModel = toString(f.prepared.features.model);
}

void Frame::dump(const std::string& dir) const {
  openclErrorsAsTs([&] {
    impl_->readHostPlanes();
    writeGBufferDump(impl_->device->cl, impl_->onDevice, impl_->prepared, impl_->info.sceneName,
                     impl_->info.source, dir);
    // An imported frame's maps come from its files: the same view-space records, no scene.
    if (impl_->onDevice.lights->hasShadows())
      writeShadowAtlasDump(*impl_->onDevice.lights, impl_->shadowAtlas.get(), dir);
  });
}

}  // namespace ts
