// What --gbuffer-in refuses or warns about that would otherwise render a wrong image with exit 0
// (issue #16): geometry in front of the near plane, hardware depths outside [0, 1], frames with no
// geometry (uint masks read normalised, view_z of the wrong sign), cropped EXRs, normals and
// colours the layouts or fp32 shading cannot hold, and render options that cannot apply.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>

#include <nlohmann/json.hpp>

#include "render/gbuffer_dump.h"
#include "render/imported_frame.h"
#include "gbuffer/image_io.h"
#include "exr_writer.h"
#include "reference_check.h"
#include "test_support.h"
#include "util/error.h"
#include "util/stderr_capture.h"

namespace ts {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

fs::path freshDir(const std::string& name) { return ts::test::freshDir("gbuffer_trust", name); }

// A dump of the street (few lights) as the files to spoil: descriptor, lights, image.
struct DumpFiles {
  PreparedFrame frame;
  json descriptor, lights;
  FloatImage image;
  double minDepth = 1e30, maxDepth = 0.0;

  size_t channel(const std::string& name) const {
    return size_t(std::find(image.channels.begin(), image.channels.end(), name) -
                  image.channels.begin());
  }
  // Index of the first value of the first geometry pixel in image.data.
  size_t firstGeometry() const {
    const size_t stride = image.channels.size(), mask = channel("mask");
    for (size_t i = 0; i < image.data.size() / stride; ++i)
      if (image.data[i * stride + mask] > 0.5f) return i * stride;
    return 0;
  }
};

const DumpFiles& dumpFiles() {
  static const DumpFiles files = [] {
    DumpFiles f;
    f.frame = prepareFrame(test::builtinScene("street", "few"), 0, 64, 36, GBufferFormat::FP32);
    const fs::path dir = freshDir("base");
    DeviceFrame device = f.frame.upload(test::context());
    writeGBufferDump(test::context(), device, f.frame, "test", "software", dir.string());
    std::ifstream(dir / "gbuffer.json") >> f.descriptor;
    std::ifstream(dir / "lights.json") >> f.lights;
    f.image = readImage((dir / "gbuffer.exr").string());
    for (float z : f.frame.gbuffer.depth)
      if (z > 0.0f) {
        f.minDepth = std::min(f.minDepth, double(z));
        f.maxDepth = std::max(f.maxDepth, double(z));
      }
    return f;
  }();
  return files;
}

// The dump with its depth as a zero_to_one hardware depth buffer in channel "Z" (1 = cleared).
void toHardwareDepth(const DumpFiles& f, json& d, FloatImage& image) {
  const double n = f.frame.intrinsics.znear, far = f.frame.intrinsics.zfar;
  const size_t stride = image.channels.size(), pz = f.channel("P.z"), mask = f.channel("mask");
  for (size_t i = 0; i < image.data.size() / stride; ++i) {
    const double depth = -double(image.data[i * stride + pz]);
    const bool geometry = image.data[i * stride + mask] > 0.5f;
    image.data[i * stride + pz] = geometry ? float(far * (depth - n) / (depth * (far - n))) : 1.0f;
  }
  image.channels[pz] = "Z";
  d["depth"] = {{"channel", "Z"},
                {"encoding", "hardware"},
                {"near", n},
                {"far", far},
                {"range", "zero_to_one"}};
  d.erase("mask");
  d["camera"].erase("znear");
}

void writeFiles(const fs::path& dir, const json& d, const json& l, const FloatImage& image) {
  writeExr((dir / "gbuffer.exr").string(), image.width, image.height, image.channels, image.data);
  std::ofstream(dir / "gbuffer.json") << d.dump(2);
  std::ofstream(dir / "lights.json") << l.dump(2);
}

struct Spoiled {
  std::string name;
  std::function<void(const DumpFiles&, json& descriptor, json& lights, FloatImage& image)> spoil;
  std::vector<std::string> mentions;  // the one-line message names these
};

void expectRefused(const Spoiled& bad) {
  const DumpFiles& f = dumpFiles();
  json d = f.descriptor, l = f.lights;
  FloatImage image = f.image;
  bad.spoil(f, d, l, image);
  const fs::path dir = freshDir("spoiled");
  writeFiles(dir, d, l, image);
  try {
    importGBuffer(dir.string());
    ADD_FAILURE() << bad.name << ": no error";
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.find('\n'), std::string::npos) << bad.name << ": " << msg;
    for (const auto& m : bad.mentions)
      EXPECT_NE(msg.find(m), std::string::npos) << bad.name << ": '" << m << "' not in: " << msg;
  }
}

TEST(GBufferImportTrust, GeometryInFrontOfTheNearPlaneIsAnError) {
  const double beyond = 0.5 * (dumpFiles().minDepth + dumpFiles().maxDepth);
  ASSERT_GT(beyond, dumpFiles().minDepth * 1.01);
  for (const Spoiled& bad : std::vector<Spoiled>{
           {"descriptor znear inside the depth range",
            [&](const DumpFiles&, json&d, json&, FloatImage&) { d["camera"]["znear"] = beyond; },
            {"gbuffer.exr", "near plane", "pixel (", "\"znear\""}},
           {"descriptor znear beyond every surface",
            [&](const DumpFiles&f, json&d, json&, FloatImage&) {
              d["camera"]["znear"] = 2.0 * f.maxDepth;
              d["camera"]["zfar"] = 4.0 * f.maxDepth;
            },
            {"near plane", "pixel ("}},
           {"hardware depth below 0",
            [](const DumpFiles&f, json&d, json&, FloatImage&image) {
              toHardwareDepth(f, d, image);
              image.data[f.firstGeometry() + f.channel("P.z")] = -0.5f;
            },
            {"gbuffer.exr", "'Z'", "-0.5", "pixel (", "outside [0, 1]"}},
           {"hardware depth above 1",
            [](const DumpFiles&f, json&d, json&, FloatImage&image) {
              toHardwareDepth(f, d, image);
              image.data[f.channel("P.z")] = 1.5f;
            },
            {"'Z'", "1.5", "pixel (0, 0)", "outside [0, 1]"}},
           {"camera znear beyond the hardware near plane",
            [](const DumpFiles&f, json&d, json&, FloatImage&image) {
              toHardwareDepth(f, d, image);
              d["camera"]["znear"] = 0.5 * (f.minDepth + f.maxDepth);
            },
            {"near plane", "\"znear\""}},
       })
    expectRefused(bad);
}

TEST(GBufferImportTrust, NearPlaneOnTheNearestSurfaceAndHardwareDepthAreAccepted) {
  const DumpFiles& f = dumpFiles();
  for (int hardware = 0; hardware < 2; ++hardware) {
    json d = f.descriptor, l = f.lights;
    FloatImage image = f.image;
    if (hardware) toHardwareDepth(f, d, image);
    else d["camera"]["znear"] = f.minDepth;  // a surface on the near plane is drawn
    const fs::path dir = freshDir("near_ok");
    writeFiles(dir, d, l, image);
    const ImportedFrame imported = importGBuffer(dir.string());
    EXPECT_EQ(imported.frame.gbuffer.geometryPixels(), f.frame.gbuffer.geometryPixels());
    // The culling now keeps every light of the original frame.
    TechniqueConfig config;
    test::Checked c = test::renderAndCheck(imported.frame, test::cachedTechnique("tiled", config));
    EXPECT_EQ(c.missed, 0u) << (hardware ? "hardware" : "linear");
  }
}

TEST(GBufferImportTrust, DepthOfTheWrongSignIsAnErrorAndAnEmptyFrameAWarning) {
  for (const Spoiled& bad : std::vector<Spoiled>{
           {"view_z holding positive depths",
            [](const DumpFiles&f, json&d, json&, FloatImage&image) {
              d.erase("mask");
              const size_t stride = image.channels.size();
              for (size_t i = 0; i < image.data.size(); i += stride)
                image.data[i + f.channel("P.z")] *= -1.0f;
            },
            {"gbuffer.exr", "'P.z'", "view_z", "\"linear\"?"}},
           {"linear holding view-space z",
            [](const DumpFiles&, json&d, json&, FloatImage&) {
              d.erase("mask");
              d["depth"]["encoding"] = "linear";
            },
            {"'P.z'", "\"view_z\"?"}},
       })
    expectRefused(bad);

  const DumpFiles& f = dumpFiles();
  json d = f.descriptor;
  FloatImage image = f.image;
  const size_t stride = image.channels.size();
  for (size_t i = 0; i < image.data.size(); i += stride) image.data[i + f.channel("mask")] = 2e-10f;
  const fs::path dir = freshDir("empty");
  writeFiles(dir, d, f.lights, image);
  StderrCapture err;
  const ImportedFrame imported = importGBuffer(dir.string());
  const std::string said = err.text();
  EXPECT_EQ(imported.frame.gbuffer.geometryPixels(), 0u);
  EXPECT_NE(said.find("tileshade: warning: "), std::string::npos) << said;
  EXPECT_NE(said.find("no pixel holds geometry"), std::string::npos) << said;
  EXPECT_NE(said.find("'mask'"), std::string::npos) << said;
}

TEST(GBufferImportTrust, ValuesTheGltfPathRefusesAreRefused) {
  auto scaleNormal = [](float s) {
    return [s](const DumpFiles& f, json&, json&, FloatImage& image) {
      for (const char* c : {"Nraw.x", "Nraw.y", "Nraw.z"})
        image.data[f.firstGeometry() + f.channel(c)] *= s;
    };
  };
  for (const Spoiled& bad : std::vector<Spoiled>{
           {"normal x1e6", scaleNormal(1e6f), {"gbuffer.exr", "normal", "pixel (", "length"}},
           {"normal x1e-40", scaleNormal(1e-40f), {"normal", "pixel (", "length"}},
           {"unorm normal outside [0, 1]",
            [](const DumpFiles&f, json&d, json&, FloatImage&image) {
              d["normal_encoding"] = "unorm";
              const size_t stride = image.channels.size();
              for (size_t i = 0; i < image.data.size(); i += stride)
                for (const char* c : {"Nraw.x", "Nraw.y", "Nraw.z"})
                  image.data[i + f.channel(c)] = 0.5f * image.data[i + f.channel(c)] + 0.5f;
              image.data[f.firstGeometry() + f.channel("Nraw.y")] = 1.25f;
            },
            {"'Nraw.y'", "unorm", "1.25", "outside [0, 1]"}},
           {"negative colour",
            [](const DumpFiles&f, json&, json&, FloatImage&image) {
              image.data[f.firstGeometry() + f.channel("kd.G")] = -0.5f;
            },
            {"'kd.G'", "diffuse", "-0.5", "below 0"}},
           {"diffuse 3e38 (inf pixels)",
            [](const DumpFiles&f, json&, json&, FloatImage&image) {
              image.data[f.firstGeometry() + f.channel("kd.R")] = 3e38f;
            },
            {"gbuffer.json", "lights.json", "fp32 shading holds"}},
           {"ambient 1e39",
            [](const DumpFiles&, json&, json&l, FloatImage&) {
              l["ambient"] = {1e39, 0.0, 0.0};
            },
            {"lights.json", "ambient", "float range"}},
           {"ambient 3e38 (finite, but times the diffuse beyond fp32 shading)",
            [](const DumpFiles&, json&, json&l, FloatImage&) {
              l["ambient"] = {3e38, 0.0, 0.0};
            },
            {"fp32 shading holds"}},
           {"negative ambient",
            [](const DumpFiles&, json&, json&l, FloatImage&) {
              l["ambient"] = {0.1, -0.1, 0.0};
            },
            {"lights.json", "ambient", ">= 0"}},
           {"negative light colour",
            [](const DumpFiles&, json&, json&l, FloatImage&) {
              l["lights"][0]["color"] = {1.0, -1.0, 1.0};
            },
            {"lights.json", "light 0", "color", ">= 0"}},
           {"light at 1e39",
            [](const DumpFiles&, json&, json&l, FloatImage&) {
              l["lights"][0]["position"] = {1e39, 0.0, 0.0};
            },
            {"lights.json", "light 0", "position", "float range"}},
           {"light range 1e39",
            [](const DumpFiles&, json&, json&l, FloatImage&) { l["lights"][0]["range"] = 1e39; },
            {"lights.json", "light 0", "range", "float range"}},
           {"znear that rounds to float 0",
            [](const DumpFiles&, json&d, json&, FloatImage&) { d["camera"]["znear"] = 1e-46; },
            {"gbuffer.json", "\"znear\"", "1e-46", "smallest normal"}},
           {"field of view beyond float",
            [](const DumpFiles&, json&d, json&, FloatImage&) {
              d["camera"]["tan_half_fov"] = {1e39, 1.0};
            },
            {"gbuffer.json", "\"tan_half_fov\"", "3.40282347e+38"}},
           {"hardware near that rounds to float 0",
            [](const DumpFiles&f, json&d, json&, FloatImage&image) {
              toHardwareDepth(f, d, image);
              d["depth"]["near"] = 1e-46;
            },
            {"gbuffer.json", "\"near\"", "smallest normal"}},
           {"light colour 1e36 (x 1/dmin^2 = 1e38)",
            [](const DumpFiles&, json&, json&l, FloatImage&) {
              l["lights"][0]["color"] = {1e36, 0.0, 0.0};
            },
            {"lights.json", "fp32 shading holds"}},
       })
    expectRefused(bad);
}

#ifndef TILESHADE_NO_OIIO
using test::writeExrWith;

TEST(GBufferImportTrust, UintMaskChannelKeepsItsIntegerValues) {
  const DumpFiles& f = dumpFiles();
  const fs::path dir = freshDir("uint_mask");
  writeExrWith(dir / "gbuffer.exr", f.image, {"mask"});
  std::ofstream(dir / "gbuffer.json") << f.descriptor.dump(2);
  std::ofstream(dir / "lights.json") << f.lights.dump(2);
  const FloatImage read = readImage((dir / "gbuffer.exr").string());
  ASSERT_EQ(read.data, f.image.data);  // mask 1 is 1, not 2.3e-10
  EXPECT_EQ(importGBuffer(dir.string()).frame.gbuffer.geometryPixels(),
            f.frame.gbuffer.geometryPixels());
}

TEST(GBufferImportTrust, CroppedExrIsRefusedInOneLine) {
  const DumpFiles& f = dumpFiles();
  const fs::path dir = freshDir("crop");
  writeExrWith(dir / "gbuffer.exr", f.image, {}, 4);
  try {
    readImage((dir / "gbuffer.exr").string());
    ADD_FAILURE() << "a data window inside a larger display window was read";
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    for (const char* m : {"gbuffer.exr", "data window (4, 4) 64x36", "display window (0, 0) 72x44"})
      EXPECT_NE(msg.find(m), std::string::npos) << m << " not in: " << msg;
  }
}
#endif

TEST(GBufferImportTrust, RenderOptionsThatCannotApplyAreRefused) {
  if (!fs::exists(TILESHADE_BINARY)) GTEST_SKIP() << "tileshade binary not built";
  const fs::path dumped = fs::temp_directory_path() / "tileshade_gbuffer_trust_cli";
  fs::remove_all(dumped);
  test::CliRun r = test::runTileshade(
      "render --lights few --width 48 --height 27 --device cpu "
      "--dump --out " +
      dumped.string());
  ASSERT_EQ(r.status, 0) << r.output;
  const std::string in = "render --gbuffer-in " + dumped.string() + " --device cpu --out " +
                         (dumped / "again").string() + " ";
  for (const char* option :
       {"--variant spot", "--shading-model blinn-phong", "--scene builtin:atrium", "--lights many",
        "--light-count 3", "--light-range 2", "--light-threshold 0.01", "--seed 2", "--width 48",
        "--height 27", "--frame 1", "--raster gl"}) {
    r = test::runTileshade(in + option);
    EXPECT_EQ(r.exitCode(), 1) << option << ": " << r.output;
    const std::string name = std::string(option).substr(0, std::string(option).find(' '));
    EXPECT_NE(r.output.find("tileshade: error: "), std::string::npos) << option << ": " << r.output;
    EXPECT_NE(r.output.find(name), std::string::npos) << option << ": " << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << option << ": " << r.output;
  }
  // Options that apply keep working.
  r = test::runTileshade(in +
                         "--technique tiled --technique deferred --gbuffer fp16 "
                         "--features general --tile 8 --math fast --check --exposure 2");
  EXPECT_EQ(r.status, 0) << r.output;
}

}  // namespace
}  // namespace ts
