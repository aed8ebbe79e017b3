// --gbuffer-in's EXR reading on the host: OpenEXR's uint channels keep their integer values (the
// rest of what the import refuses or warns about: gbuffer_import_trust_test.cpp).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "render/imported_frame.h"
#include "exr_writer.h"
#include "test_support.h"

namespace ts {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;
using test::writeExrWith;

fs::path freshDir(const std::string& name) { return ts::test::freshDir("gbuffer_trust", name); }

#ifndef TILESHADE_NO_OIIO
// Every channel uint (one format for the whole file: OpenImageIO then lists no per-channel
// formats): integer depths, axis normals, a 0/1 mask.
TEST(GBufferImportTrust, AllUintExrKeepsItsIntegerValues) {
  FloatImage image;
  image.width = 8;
  image.height = 4;
  image.channels = {"Z", "nx", "ny", "nz", "r", "g", "b", "mask"};
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const bool geometry = x < 3;
      image.data.insert(image.data.end(),
                        {geometry ? 5.0f : 0.0f, 0, 0, 1, 1, 1, 1, geometry ? 1.0f : 0.0f});
    }
  const fs::path dir = freshDir("all_uint");
  writeExrWith(dir / "frame.exr", image, image.channels);
  std::ofstream(dir / "lights.json") << json{{"lights", json::array()}}.dump();
  std::ofstream(dir / "gbuffer.json") << json{
      {"tileshade_gbuffer", 1},
      {"image", "frame.exr"},
      {"camera", {{"yfov", 1.0}}},
      {"depth", {{"channel", "Z"}, {"encoding", "linear"}}},
      {"mask", "mask"},
      {"normal", {"nx", "ny", "nz"}},
      {"diffuse", {"r", "g", "b"}}}.dump();
  const ImportedFrame imported = importGBuffer(dir.string());
  EXPECT_EQ(imported.frame.gbuffer.geometryPixels(), 3u * 4u);
  EXPECT_EQ(imported.frame.gbuffer.depth[0], 5.0f);
  EXPECT_EQ(imported.frame.intrinsics.znear, 5.0f);
}
#endif

}  // namespace
}  // namespace ts
