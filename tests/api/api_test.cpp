// The public API (include/tileshade/tileshade.h) as an engine uses it: frames from host planes
// equal the render command's own frames bit for bit in every layout, cl_mem planes equal host
// planes, bad input is one ts::Error line, the check is render --check's, runBench returns rows.
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "api/api_internal.h"
#include "require_gl.h"
#include "test_support.h"
#include "tileshade/tileshade.h"

namespace ts {
namespace {

// One Device per process, never destroyed (as test::context(), for the same reason).
Device& device() {
  static Device* d = new Device(std::getenv("TILESHADE_DEVICE") ? "" : "cpu");
  return *d;
}

constexpr int kWidth = 64, kHeight = 36;

SceneRequest smallScene(const std::string& layout, const std::string& variant = "") {
  SceneRequest r;
  r.scene = variant.empty() ? "builtin:street" : "builtin:atrium";
  r.variant = variant;
  r.width = kWidth;
  r.height = kHeight;
  r.layout = layout;
  r.lightCount = 60;
  return r;
}

// The planes, camera and lights of a frame as an engine would hand them over: the stored bytes of
// its G-buffer, its intrinsics and its (view-space) lights, point and directional ones exactly.
struct HostCopy {
  EncodedGBuffer encoded;
  HostGBuffer planes;
  Camera camera;
  Lights lights;
};

HostCopy hostCopyOf(const Frame& frame) {
  HostCopy c;
  const PreparedFrame& p = frame.impl()->prepared;
  c.encoded = p.encoded;
  const EncodedGBuffer& e = c.encoded;
  c.planes.width = e.width;
  c.planes.height = e.height;
  c.planes.layout = toString(e.format);
  c.planes.shadingModel = toString(e.model);
  c.planes.depth = e.depth.data();
  c.planes.normal = e.normal.data();
  c.planes.diffuse = e.diffuse.data();
  c.planes.specular = e.specular.empty() ? nullptr : e.specular.data();
  c.planes.emissive = e.emissive.empty() ? nullptr : e.emissive.data();
  c.camera.width = p.intrinsics.width;
  c.camera.height = p.intrinsics.height;
  c.camera.tanHalfFovX = p.intrinsics.tanHalfFovX;
  c.camera.tanHalfFovY = p.intrinsics.tanHalfFovY;
  c.camera.znear = p.intrinsics.znear;
  c.camera.zfar = p.intrinsics.zfar;
  for (size_t i = 0; i < p.lights.size(); ++i) {
    EXPECT_FALSE(p.lights.isSpot(i)) << "spot lights do not round-trip exactly through angles";
    const glm::vec4 pr = p.lights.positionRange[i], col = p.lights.color[i];
    c.lights.lights.push_back(Light::point({pr.x, pr.y, pr.z}, {col.x, col.y, col.z}, pr.w));
  }
  for (size_t i = 0; i < p.lights.directionalCount(); ++i) {
    const glm::vec4 d = -p.lights.directionalDir[i], col = p.lights.directionalColor[i];
    c.lights.lights.push_back(Light::directional({d.x, d.y, d.z}, {col.x, col.y, col.z}));
  }
  c.lights.ambient = {p.ambient.x, p.ambient.y, p.ambient.z};
  return c;
}

std::vector<float> shadeImage(const Frame& frame, const std::string& technique = "tiled") {
  Settings s;
  s.technique = technique;
  Renderer renderer(device(), s);
  return renderer.shade(frame).rgba;
}

bool sameBits(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

// The message of the ts::Error that f throws (one line, not empty); "" when it throws none.
template <typename F>
std::string errorOf(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_FALSE(m.empty());
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    return m;
  }
  return "";
}

TEST(Api, HostPlanesOfADumpShadeAsTheDumpItself) {
  const auto dir = test::freshDir("api", "dump");
  Frame scene = Frame::fromScene(device(), smallScene("fp32"));
  scene.dump(dir.string());
  Frame files = Frame::fromFiles(device(), dir.string());
  EXPECT_EQ(files.info().source, "import");
  HostCopy copy = hostCopyOf(files);
  Frame host = Frame::fromHost(device(), copy.planes, copy.camera, copy.lights);
  EXPECT_EQ(host.info().source, "host");
  const std::vector<float> fromFiles = shadeImage(files), fromHost = shadeImage(host);
  ASSERT_EQ(fromHost.size(), size_t(4 * kWidth * kHeight));
  EXPECT_TRUE(sameBits(fromFiles, fromHost));
  EXPECT_TRUE(sameBits(shadeImage(scene), fromHost));  // and the dump itself is exact
}

TEST(Api, EveryLayoutThroughHostPlanesEqualsTheRenderPath) {
  struct Case {
    std::string layout, variant;
  };
  for (const Case& c : {Case{"fp32", ""}, Case{"fp16", ""}, Case{"packed", ""},
                        Case{"fp32", "metallic-roughness"}, Case{"packed", "metallic-roughness"}}) {
    SCOPED_TRACE(c.layout + " " + c.variant);
    Frame scene = Frame::fromScene(device(), smallScene(c.layout, c.variant));
    HostCopy copy = hostCopyOf(scene);
    Frame host = Frame::fromHost(device(), copy.planes, copy.camera, copy.lights);
    EXPECT_EQ(host.info().layout, c.layout);
    EXPECT_EQ(host.info().bytesPerPixel, scene.info().bytesPerPixel);
    EXPECT_TRUE(sameBits(shadeImage(scene, "clustered"), shadeImage(host, "clustered")));
  }
}

TEST(Api, BadHostPlanesAreOneLineErrors) {
  Frame scene = Frame::fromScene(device(), smallScene("fp32"));
  HostCopy copy = hostCopyOf(scene);
  auto fromHost = [&](const HostGBuffer& planes) {
    return errorOf([&] { Frame::fromHost(device(), planes, copy.camera, copy.lights); });
  };
  EXPECT_EQ(fromHost(copy.planes), "");

  // A NaN in the normal of a geometry pixel.
  std::vector<uint8_t> normal = copy.encoded.normal;
  size_t geometry = 0;
  while (copy.encoded.depth[geometry] <= 0.0f) ++geometry;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(&normal[geometry * 16 + 4], &nan, sizeof nan);
  HostGBuffer bad = copy.planes;
  bad.normal = normal.data();
  EXPECT_NE(fromHost(bad).find("plane 'normal' component 1 is NaN at pixel"), std::string::npos)
      << fromHost(bad);

  bad = copy.planes;
  bad.layout = "fp24";
  EXPECT_NE(fromHost(bad).find("'fp24'"), std::string::npos) << fromHost(bad);
  bad = copy.planes;
  bad.depth = nullptr;
  EXPECT_NE(fromHost(bad).find("depth plane is null"), std::string::npos) << fromHost(bad);
  bad = copy.planes;
  bad.width = 0;
  EXPECT_NE(fromHost(bad).find("width"), std::string::npos) << fromHost(bad);
  bad = copy.planes;
  bad.width = bad.height = 1 << 20;  // never read: refused for its size
  EXPECT_NE(fromHost(bad).find("1048576"), std::string::npos) << fromHost(bad);
  bad = copy.planes;
  bad.shadingModel = "lambert";
  EXPECT_NE(fromHost(bad).find("'lambert'"), std::string::npos) << fromHost(bad);

  Camera camera = copy.camera;
  camera.width = kWidth + 1;
  EXPECT_NE(errorOf([&] {
              Frame::fromHost(device(), copy.planes, camera, copy.lights);
            }).find("camera is 65x36"),
            std::string::npos);
  Lights lights = copy.lights;
  lights.lights[0].range = -1.0f;
  EXPECT_NE(errorOf([&] {
              Frame::fromHost(device(), copy.planes, copy.camera, lights);
            }).find("light 0 (point): range must be finite and > 0"),
            std::string::npos);
  lights = copy.lights;
  lights.lights.push_back(Light::spot({0, 0, -5}, {0, 0, -1}, {1, 1, 1}, 5.0f, 0.6f, 0.5f));
  EXPECT_NE(errorOf([&] {
              Frame::fromHost(device(), copy.planes, copy.camera, lights);
            }).find("innerConeAngle < outerConeAngle"),
            std::string::npos);
}

TEST(Api, BadKnobNamesAreTheCommandsErrors) {
  auto renderer = [](void (*change)(Settings&)) {
    Settings s;
    change(s);
    return errorOf([&] { Renderer(device(), s); });
  };
  EXPECT_EQ(renderer([](Settings&) {}), "");
  EXPECT_EQ(renderer([](Settings& s) { s.culling = "bogus"; }),
            "--culling: expected one of rect, frustum, aabb, got 'bogus'");
  EXPECT_NE(renderer([](Settings& s) { s.technique = "nope"; }).find("nope"), std::string::npos);
  EXPECT_NE(renderer([](Settings& s) { s.lanes = "3"; }).find("--lanes"), std::string::npos);
  EXPECT_NE(renderer([](Settings& s) { s.math = "sloppy"; }).find("--math"), std::string::npos);
  EXPECT_NE(renderer([](Settings& s) { s.tileWidth = 0; }).find("--tile"), std::string::npos);
  EXPECT_NE(errorOf([] {
              SceneRequest r = smallScene("fp32");
              r.raster = "vulkan";
              Frame::fromScene(device(), r);
            }).find("--raster"),
            std::string::npos);
}

// The caller's own OpenCL objects: the test context's device and context, a queue of our own.
struct OwnQueue {
  cl::CommandQueue queue;
  explicit OwnQueue(cl_command_queue_properties properties)
      : queue(test::context().context(), test::context().device(), properties) {}
};

// A frame's stored planes copied into cl_mem buffers of `cl`'s context, as an engine holds its
// G-buffer: `planes` names them for Frame::fromDevice.
struct BuffersOf {
  BuffersOf(ClContext& cl, const EncodedGBuffer& e, const std::string& layout) {
    auto buffer = [&](const void* data, size_t bytes) {
      return cl::Buffer(cl.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, bytes,
                        const_cast<void*>(data));
    };
    depth = buffer(e.depth.data(), e.depth.size() * sizeof(float));
    normal = buffer(e.normal.data(), e.normal.size());
    diffuse = buffer(e.diffuse.data(), e.diffuse.size());
    specular = buffer(e.specular.data(), e.specular.size());
    emissive = buffer(e.emissive.data(), e.emissive.size());
    planes.width = e.width;
    planes.height = e.height;
    planes.layout = layout;
    planes.depth = depth();
    planes.normal = normal();
    planes.diffuse = diffuse();
    planes.specular = specular();
    planes.emissive = emissive();
  }
  cl::Buffer depth, normal, diffuse, specular, emissive;
  DeviceGBuffer planes;
};

TEST(Api, DevicePlanesShadeAsHostPlanes) {
  Frame scene = Frame::fromScene(device(), smallScene("packed"));
  HostCopy copy = hostCopyOf(scene);
  OwnQueue own(CL_QUEUE_PROFILING_ENABLE);
  ClContext& cl = test::context();
  Device mine = Device::fromOpenCL(cl.context()(), cl.device()(), own.queue());
  EXPECT_EQ(mine.name(), device().name());

  const EncodedGBuffer& e = copy.encoded;
  ASSERT_FALSE(e.specular.empty());
  ASSERT_FALSE(e.emissive.empty());
  const BuffersOf buffers(cl, e, "packed");
  const DeviceGBuffer& planes = buffers.planes;
  Frame onDevice = Frame::fromDevice(mine, planes, copy.camera, copy.lights);
  Frame host = Frame::fromHost(mine, copy.planes, copy.camera, copy.lights);
  Settings s;
  Renderer renderer(mine, s);
  ShadeOptions check;
  check.check = true;
  const ShadeResult a = renderer.shade(onDevice, check), b = renderer.shade(host, check);
  EXPECT_TRUE(sameBits(a.rgba, b.rgba));
  EXPECT_EQ(a.counters.evaluations, b.counters.evaluations);
  ASSERT_TRUE(a.check && b.check);
  EXPECT_EQ(a.check->error.maxAbs, b.check->error.maxAbs);  // the planes read back for it
  EXPECT_EQ(a.check->missed, 0u);

  // A plane smaller than the frame, and the renderer's default device for cl_mem planes.
  DeviceGBuffer small = planes;
  small.normal = buffers.depth();  // 4 bytes a pixel, the packed normal's size: accepted
  EXPECT_EQ(errorOf([&] { Frame::fromDevice(mine, small, copy.camera, copy.lights); }), "");
  small.width = e.width * 2;
  small.height = e.height * 2;
  Camera bigger = copy.camera;
  bigger.width = small.width;
  bigger.height = small.height;
  EXPECT_NE(errorOf([&] {
              Frame::fromDevice(mine, small, bigger, copy.lights);
            }).find("depth buffer holds"),
            std::string::npos);
  EXPECT_NE(errorOf([&] {
              Frame::fromDevice(device(), planes, copy.camera, copy.lights);
            }).find("Device::fromOpenCL"),
            std::string::npos);
}

// The planes of a cl_mem frame are read back for a check, and checked then as host planes are at
// once: a NaN in the normal plane is one line naming the plane and the pixel.
TEST(Api, DevicePlanesValuesAreCheckedWhenReadBack) {
  Frame scene = Frame::fromScene(device(), smallScene("fp32"));
  HostCopy copy = hostCopyOf(scene);
  OwnQueue own(CL_QUEUE_PROFILING_ENABLE);
  ClContext& cl = test::context();
  Device mine = Device::fromOpenCL(cl.context()(), cl.device()(), own.queue());
  EncodedGBuffer e = copy.encoded;
  size_t geometry = 0;
  while (!(e.depth[geometry] > 0.0f)) ++geometry;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(e.normal.data() + geometry * 16, &nan, sizeof nan);
  const BuffersOf buffers(cl, e, "fp32");
  const DeviceGBuffer& planes = buffers.planes;
  Frame frame = Frame::fromDevice(mine, planes, copy.camera, copy.lights);
  Renderer renderer(mine, Settings{});
  ShadeOptions check;
  check.check = true;
  const std::string what = errorOf([&] { renderer.shade(frame, check); });
  EXPECT_NE(what.find("device G-buffer"), std::string::npos) << what;
  EXPECT_NE(what.find("normal"), std::string::npos) << what;
  EXPECT_EQ(what.find('\n'), std::string::npos) << what;
}

TEST(Api, AQueueWithoutProfilingIsRefused) {
  OwnQueue plain(0);
  ClContext& cl = test::context();
  EXPECT_NE(errorOf([&] {
              Device::fromOpenCL(cl.context()(), cl.device()(), plain.queue());
            }).find("CL_QUEUE_PROFILING_ENABLE"),
            std::string::npos);
  EXPECT_NE(
      errorOf([&] { Device::fromOpenCL(nullptr, cl.device()(), plain.queue()); }).find("null"),
      std::string::npos);
}

TEST(Api, CheckReportsRenderChecksFigures) {
  Frame frame = Frame::fromScene(device(), smallScene("fp32"));
  for (const char* technique : {"tiled", "deferred"}) {
    SCOPED_TRACE(technique);
    Settings s;
    s.technique = technique;
    Renderer renderer(device(), s);
    ShadeOptions check;
    check.check = true;
    const ShadeResult r = renderer.shade(frame, check);
    ASSERT_TRUE(r.check);
    EXPECT_TRUE(r.check->missedCounted);
    EXPECT_EQ(r.check->missed, 0u);
    EXPECT_GT(r.check->contributing, 0u);
    EXPECT_GT(r.check->error.peak, 0.0);
    EXPECT_LE(r.check->error.maxRelPeak, 2e-5);
    EXPECT_LE(r.check->shadingError.maxRelPeak, 2e-5);
    EXPECT_GT(r.check->physicalError.maxAbs, 0.0);  // the range cut's bias is there
    EXPECT_EQ(r.check->error.tolerance, 1e-4 * r.check->error.peak);
    EXPECT_GT(r.totalMs, 0.0);
    EXPECT_FALSE(r.kernels.empty());
    EXPECT_FALSE(renderer.shade(frame).check);  // no check unless asked
  }
}

TEST(Api, RunBenchReturnsTheRowsOfBenchCsv) {
  const auto dir = test::freshDir("api", "bench");
  BenchRequest request;
  request.configJson = R"({"technique": ["tiled", "brute"], "resolution": "64x36",
                           "light_count": 40, "frames": "1", "warmup": 0, "error": true})";
  request.outDir = dir.string();
  const auto rows = runBench(request);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].at("technique"), "tiled");
  EXPECT_EQ(rows[1].at("technique"), "brute");
  EXPECT_EQ(rows[0].at("resolution"), "64x36");
  EXPECT_FALSE(rows[0].at("total_ms").empty());
  EXPECT_TRUE(std::filesystem::exists(dir / "bench.csv"));
  request.configJson = R"({"technique": "nope"})";
  EXPECT_NE(errorOf([&] { runBench(request); }).find("nope"), std::string::npos);
}

// The document's origin in its errors: the configJson text or the file; a folder given as the
// file is one line saying so, not a JSON parse error of nothing.
TEST(Api, RunBenchNamesWhereItsConfigCameFrom) {
  const auto dir = test::freshDir("api", "bench-config");
  BenchRequest request;
  request.outDir = (dir / "out").string();
  request.configJson = R"({"technique": ["tiled"], "technique": ["brute"]})";
  const std::string twice = errorOf([&] { runBench(request); });
  EXPECT_NE(twice.find("(runBench's configJson)"), std::string::npos) << twice;
  EXPECT_NE(twice.find("appears twice"), std::string::npos) << twice;
  EXPECT_EQ(twice.find("bench config bench config"), std::string::npos) << twice;
  request.configPath = dir.string();
  EXPECT_NE(errorOf([&] { runBench(request); }).find("not both"), std::string::npos);
  request.configJson.clear();
  const std::string folder = errorOf([&] { runBench(request); });
  EXPECT_NE(folder.find("is a directory"), std::string::npos) << folder;
  const auto file = dir / "config.json";
  std::ofstream(file) << R"({"frames": "1", "frames": "2"})";
  request.configPath = file.string();
  const std::string bad = errorOf([&] { runBench(request); });
  EXPECT_NE(bad.find(file.string()), std::string::npos) << bad;
  EXPECT_NE(bad.find("\"frames\" appears twice"), std::string::npos) << bad;
}

// A technique that draws the scene reads no G-buffer, so the frame's layout does not quantize its
// surfaces: it is checked against the references of the rasterization's fp32 planes. Against the
// packed planes' reference tiled-forward read 8.6e-3 of the peak, an error it does not make.
TEST(Api, ForwardTechniquesAreCheckedAgainstTheFp32PlanesWhateverTheLayout) {
  REQUIRE_GL();
  ShadeOptions check;
  check.check = true;
  auto errorOn = [&](const std::string& layout, const std::string& technique) {
    SceneRequest r = smallScene(layout);
    r.raster = "gl";
    Frame frame = Frame::fromScene(device(), r);
    Settings s;
    s.technique = technique;
    const ShadeResult result = Renderer(device(), s).shade(frame, check);
    EXPECT_TRUE(result.check.has_value());
    EXPECT_EQ(result.check->missed, 0u) << technique << " on " << layout;
    return result.check->error.maxRelPeak;
  };
  const double fp32 = errorOn("fp32", "tiled-forward");
  EXPECT_LE(fp32, 1e-4);
  for (const char* layout : {"fp16", "packed"}) {
    EXPECT_EQ(errorOn(layout, "tiled-forward"), fp32) << layout;
    // A G-buffer technique on the same frame keeps the reference of its stored planes.
    EXPECT_LE(errorOn(layout, "tiled"), 2e-5) << layout;
  }
}

TEST(Api, ListsDevicesAndTechniques) {
  EXPECT_FALSE(listDeviceDescriptions().empty());
  const auto techniques = listTechniques();
  ASSERT_FALSE(techniques.empty());
  EXPECT_EQ(techniques.front().name, "tiled");
  EXPECT_FALSE(techniques.front().description.empty());
}

}  // namespace
}  // namespace ts
