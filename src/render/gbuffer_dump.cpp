#include "render/gbuffer_dump.h"

#include <fstream>

#include <nlohmann/json.hpp>

#include "gbuffer/gbuffer_files.h"
#include "cl/kernel_args.h"
#include "cl/work_group.h"
#include "gbuffer/image_io.h"
#include "util/file_write.h"
#include "techniques/device_frame.h"
#include "util/error.h"

namespace ts {

std::vector<float> decodeOnDevice(ClContext& cl, const DeviceFrame& frame, GBufferFormat format,
                                  const SceneFeatures& features) {
  TechniqueConfig config;  // only the layout and the features decide how the planes decode
  config.format = format;
  config.features = features;
  cl::Program program = cl.build("dump.cl", config.kernelOptions());
  cl::Kernel kernel(program, "decode_gbuffer");
  const size_t channels = dumpKernelChannels().size();
  const size_t pixels = size_t(frame.width()) * size_t(frame.height());
  cl::Buffer out(cl.context(), CL_MEM_WRITE_ONLY, pixels * channels * sizeof(float));
  KernelArgs(kernel)
      .add(toCl(frame.camera.kernelCamera()))
      .add(frame.gbufferArgs())
      .add(out)
      .done();
  GroupShape group = fitGroup(8, 8, groupLimit(cl, kernel));
  cl.queue().enqueueNDRangeKernel(kernel, cl::NullRange,
                                  group.global(frame.width(), frame.height()), group.local());
  std::vector<float> data(pixels * channels);
  cl.queue().enqueueReadBuffer(out, CL_TRUE, 0, data.size() * sizeof(float), data.data());
  return data;
}

void writeGBufferDump(ClContext& cl, const DeviceFrame& frame, const PreparedFrame& prepared,
                      const std::string& scene, const std::string& raster, const std::string& dir) {
  const EncodedGBuffer& encoded = prepared.encoded;
  const ShadingModel model = prepared.gbuffer.model;
  const size_t pixels = encoded.pixelCount();

  // Host channels: those the field table names that dump.cl does not write, from decodeStored.
  struct HostChannel {
    std::string name;
    GBufferPlane plane;
    int component;
  };
  std::vector<HostChannel> host;
  for (const GBufferField* f : gbufferFields(model))
    for (int c = 0; c < f->components; ++c)
      if (isHostDumpChannel(f->dumpChannels[c]))
        host.push_back({f->dumpChannels[c], f->plane, f->first + c});

  const std::vector<float> kernel = decodeOnDevice(cl, frame, encoded.format, prepared.features);
  const size_t kc = dumpKernelChannels().size(), channels = kc + host.size();
  std::vector<float> data(pixels * channels, 0.0f);
  for (size_t i = 0; i < pixels; ++i) {
    std::copy_n(kernel.begin() + std::ptrdiff_t(i * kc), kc,
                data.begin() + std::ptrdiff_t(i * channels));
    if (encoded.depth[i] <= 0.0f) continue;  // background: zeros, as the kernel writes
    for (size_t h = 0; h < host.size(); ++h)
      data[i * channels + kc + h] = decodeStored(encoded, host[h].plane, i)[host[h].component];
  }
  std::vector<std::string> names = dumpKernelChannels();
  for (const auto& h : host) names.push_back(h.name);
  writeExr(dir + "/gbuffer.exr", encoded.width, encoded.height, names, data);

  writeFile(dir + "/lights.json", lightsJson(*frame.lights, frame.ambient).dump(2) + "\n");

  const CameraIntrinsics& in = prepared.intrinsics;
  nlohmann::json d = {
      {"tileshade_gbuffer", kGBufferFilesVersion},
      {"image", "gbuffer.exr"},
      {"lights", "lights.json"},
      {"width", encoded.width},
      {"height", encoded.height},
      {"origin", "top"},
      {"camera",
       {{"tan_half_fov", {in.tanHalfFovX, in.tanHalfFovY}},
        {"znear", in.znear},
        {"zfar", in.zfar}}},
      {"depth", {{"channel", "P.z"}, {"encoding", "view_z"}}},
      {"mask", "mask"},
      {"shading_model", toString(model)},
      {"layout", toString(encoded.format)},
      {"scene", scene},
      {"frame", prepared.frame},
      {"raster", raster},
  };
  if (frame.lights->hasShadows()) d["shadow_atlas"] = "shadow_atlas.json";
  for (const GBufferField* f : gbufferFields(model)) {
    if (f->components == 1) {
      d[f->key] = f->dumpChannels[0];
    } else {
      nlohmann::json list = nlohmann::json::array();
      for (int c = 0; c < f->components; ++c) list.push_back(f->dumpChannels[c]);
      d[f->key] = list;
    }
  }
  writeFile(dir + "/gbuffer.json", d.dump(2) + "\n");
}

void writeShadowAtlasDump(const ViewLights& lights, const ShadowAtlas* atlas,
                          const std::string& dir) {
  nlohmann::json world = nullptr;
  if (atlas) {
    world = nlohmann::json::array();
    for (const ShadowFace& f : atlas->layout.faces) {
      nlohmann::json m = nlohmann::json::array();  // column-major, as glm and OpenGL
      for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) m.push_back(f.mapFromWorld[c][r]);
      world.push_back({{"light", f.light},
                       {"face", f.face},
                       {"orthographic", f.view.orthographic},
                       {"znear", f.view.znear},
                       {"zfar", f.view.zfar},
                       {"map_from_world", m}});
    }
  }
  const int taps = int(lights.shadowFaces.at(6).x);  // record 6 of face 0 (kernels/shadows.h)
  const nlohmann::json d = shadowAtlasJson(lights, shadowFilterName(taps), world);
  writeExr(dir + "/shadow_atlas.exr", d["width"].get<int>(), d["height"].get<int>(), {"depth"},
           *lights.shadowAtlas);
  writeFile(dir + "/shadow_atlas.json", d.dump(2) + "\n");
}

}  // namespace ts
