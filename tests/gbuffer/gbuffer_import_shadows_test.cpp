// A dump of a frame with shadow-casting lights comes back through --gbuffer-in with its shadow
// maps (shadow_atlas.json and .exr, each light's "shadow_face" in lights.json): the same face
// table, atlas and image bit for bit; spoiled shadow files are refused in one line, never shaded
// as if the lights cast no shadow.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "gbuffer/image_io.h"
#include "reference_check.h"
#include "render/gbuffer_dump.h"
#include "render/imported_frame.h"
#include "render/render_input.h"
#include "test_support.h"
#include "util/error.h"

namespace ts {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

// The atrium's big lights (points and spots) and a sun, all casting, pcf3: a dump in `dir`.
RenderInput shadowedInput() {
  PipelineOptions o;
  o.scene = "builtin:atrium";
  o.variant = "sun";
  o.lightSet = "big";
  o.shadows = "all";
  o.shadowMapSize = 32;
  o.shadowFilter = "pcf3";
  o.shadowBias = "2,1";
  o.width = 64;
  o.height = 36;
  return loadSceneInput(o, 0);
}

struct Dumped {
  RenderInput input;
  fs::path dir;
};

const Dumped& dumped() {
  static const Dumped d = [] {
    Dumped out{shadowedInput(), test::freshDir("gbuffer_shadows", "dump")};
    DeviceFrame device = out.input.frame.upload(test::context());
    writeGBufferDump(test::context(), device, out.input.frame, "test", "software",
                     out.dir.string());
    writeShadowAtlasDump(out.input.frame.lights, out.input.shadowAtlas.get(), out.dir.string());
    return out;
  }();
  return d;
}

std::vector<glm::vec4> tiledImage(const PreparedFrame& f) {
  TechniqueConfig config;
  config.features = f.features;
  config.format = f.encoded.format;
  return test::renderOnly(f, test::cachedTechnique("tiled", config), false).image;
}

TEST(GBufferImportShadows, ADumpComesBackWithItsShadowMaps) {
  const Dumped& d = dumped();
  const ViewLights& original = d.input.frame.lights;
  ASSERT_TRUE(original.hasShadows());
  ASSERT_GT(original.directionalCount(), 0u);
  const ImportedFrame imported = importGBuffer(d.dir.string());
  const ViewLights& back = imported.frame.lights;
  EXPECT_TRUE(imported.frame.features.shadows);
  EXPECT_EQ(back.shadow, original.shadow);
  EXPECT_EQ(back.directionalShadow, original.directionalShadow);
  ASSERT_EQ(back.shadowFaces.size(), original.shadowFaces.size());
  for (size_t i = 0; i < back.shadowFaces.size(); ++i)
    EXPECT_EQ(back.shadowFaces[i], original.shadowFaces[i]) << "record " << i;
  EXPECT_EQ(back.shadowAtlasWidth, original.shadowAtlasWidth);
  EXPECT_TRUE(*back.shadowAtlas == *original.shadowAtlas);

  // The same image, and one that the shadows change (the maps are not a no-op here).
  const std::vector<glm::vec4> a = tiledImage(d.input.frame), b = tiledImage(imported.frame);
  EXPECT_TRUE(a == b) << test::relativeDifference(a, b);
  PreparedFrame unshadowed = imported.frame;
  unshadowed.lights.shadowFaces.clear();
  std::fill(unshadowed.lights.shadow.begin(), unshadowed.lights.shadow.end(), -1);
  std::fill(unshadowed.lights.directionalShadow.begin(), unshadowed.lights.directionalShadow.end(),
            -1);
  unshadowed.features.shadows = false;
  EXPECT_GT(test::relativeDifference(a, tiledImage(unshadowed)), 1e-3);
}

// The dump's files, spoiled one way each: every import fails with one line naming `mentions`.
struct Spoiled {
  std::string name;
  std::function<void(json& descriptor, json& lights, json& atlas, FloatImage& image)> spoil;
  std::vector<std::string> mentions;
};

void expectRefused(const Spoiled& bad) {
  SCOPED_TRACE(bad.name);
  const fs::path from = dumped().dir, dir = test::freshDir("gbuffer_shadows", "spoiled");
  for (const char* f : {"gbuffer.exr"}) fs::copy_file(from / f, dir / f);
  json d, l, a;
  std::ifstream(from / "gbuffer.json") >> d;
  std::ifstream(from / "lights.json") >> l;
  std::ifstream(from / "shadow_atlas.json") >> a;
  FloatImage image = readImage((from / "shadow_atlas.exr").string());
  bad.spoil(d, l, a, image);
  std::ofstream(dir / "gbuffer.json") << d.dump(2);
  std::ofstream(dir / "lights.json") << l.dump(2);
  std::ofstream(dir / "shadow_atlas.json") << a.dump(2);
  if (image.width > 0)
    writeExr((dir / "shadow_atlas.exr").string(), image.width, image.height, image.channels,
             image.data);
  try {
    importGBuffer(dir.string());
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    for (const auto& m : bad.mentions)
      EXPECT_NE(msg.find(m), std::string::npos) << m << ": " << msg;
  }
}

json& firstCaster(json& lights) {
  for (json& l : lights["lights"])
    if (l.contains("shadow_face")) return l;
  throw Error("no caster in the dump");
}

TEST(GBufferImportShadows, SpoiledShadowFilesAreRefused) {
  const std::vector<Spoiled> cases = {
      {"casting lights, no atlas named",
       [](json& d, json&, json&, FloatImage&) { d.erase("shadow_atlas"); },
       {"lights.json", "shadow_face", "shadow_atlas"}},
      {"an atlas but no casting light",
       [](json&, json& l, json&, FloatImage&) {
         for (json& x : l["lights"]) x.erase("shadow_face");
       },
       {"gbuffer.json", "no light", "shadow_face"}},
      {"the atlas names a folder",
       [](json& d, json&, json&, FloatImage&) { d["shadow_atlas"] = "."; },
       {"shadow atlas"}},
      {"a face outside the atlas",
       [](json&, json&, json& a, FloatImage&) { a["faces"][0]["x"] = a["width"]; },
       {"shadow_atlas.json", "face 0", "\"x\""}},
      {"a face overhanging the atlas",
       [](json&, json&, json& a, FloatImage&) { a["faces"][0]["x"] = a["width"].get<int>() - 1; },
       {"face 0", "outside"}},
      {"a light's faces beyond the list",
       [](json&, json& l, json& a, FloatImage&) {
         firstCaster(l)["shadow_face"] = a["faces"].size();
       },
       {"lights.json", "beyond"}},
      {"two lights on one face",
       [](json&, json& l, json&, FloatImage&) {
         int n = 0;
         for (json& x : l["lights"])
           if (x.contains("shadow_face") && n++ < 2) x["shadow_face"] = 0;
       },
       {"two lights"}},
      {"a face of no light",
       [](json&, json& l, json&, FloatImage&) { firstCaster(l).erase("shadow_face"); },
       {"belongs to no light"}},
      {"a negative shadow_face",
       [](json&, json& l, json&, FloatImage&) { firstCaster(l)["shadow_face"] = -1; },
       {"shadow_face", "whole number"}},
      {"an unknown filter",
       [](json&, json&, json& a, FloatImage&) { a["filter"] = "pcf4"; },
       {"shadow_atlas.json", "filter", "pcf4"}},
      {"a NaN in a clip row",
       [](json&, json&, json& a, FloatImage&) { a["faces"][1]["clip_from_view"][2][0] = "nan"; },
       {"face 1", "clip_from_view"}},
      {"a NaN texel",
       [](json&, json&, json&, FloatImage& img) { img.data[7] = std::nanf(""); },
       {"shadow_atlas.exr", "texel (7, 0)"}},
      {"an atlas image of the wrong size",
       [](json&, json&, json& a, FloatImage&) { a["height"] = a["height"].get<int>() * 2; },
       {"shadow_atlas.exr", "must be one channel"}},
      {"a missing atlas image",
       [](json&, json&, json&, FloatImage& img) { img.width = 0; },
       {"shadow_atlas.exr"}},
      {"an unknown key",
       [](json&, json&, json& a, FloatImage&) { a["faces"][0]["sise"] = 32; },
       {"face 0", "sise"}},
  };
  for (const Spoiled& c : cases) expectRefused(c);
}

}  // namespace
}  // namespace ts
