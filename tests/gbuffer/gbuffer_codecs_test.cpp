// The G-buffer's element decoders are written once (kernels/gbuffer_codecs.h) and compiled for
// both sides (kernels/gbuffer.h; src/gbuffer/gbuffer_codecs.h): the host's are the kernels' own,
// and no second copy of them creeps back. That the device computes what the host does is checked
// on the device for every stored code by AccuracyKnobs.PackedDecodeMatchesTheHostForEveryCode
// (Blinn-Phong packed) and MetallicRoughnessDecode (every metallic-roughness layout).
#include <gtest/gtest.h>

#include <filesystem>
#include <regex>
#include <string>

#include "test_support.h"
#include "util/file_read.h"

namespace ts {
namespace {

// The text without its comments (// to the end of the line, /* ... */), which may describe a
// decoder in words and formulas.
std::string withoutComments(const std::string& text) {
  std::string out;
  for (size_t i = 0; i < text.size();) {
    if (text.compare(i, 2, "//") == 0) {
      i = text.find('\n', i);
      if (i == std::string::npos) break;
    } else if (text.compare(i, 2, "/*") == 0) {
      i = text.find("*/", i + 2);
      if (i == std::string::npos) break;
      i += 2;
    } else {
      out += text[i++];
    }
  }
  return out;
}

// A decoder's signature: an integer code divided by the unorm8 or snorm16 scale in float (the
// host's encoders scale in double, and texture decoding in src/scene/ is not the G-buffer's).
TEST(GBufferCodecs, DecodersAreWrittenOnlyInTheCodecHeader) {
  namespace fs = std::filesystem;
  const fs::path root = test::sourceDir();
  const std::regex decoder(R"(/\s*\(?\s*(255|32767)\.0f)");
  int scanned = 0;
  for (const char* dir : {"kernels", "src"})
    for (const auto& entry : fs::recursive_directory_iterator(root / dir)) {
      const fs::path& p = entry.path();
      const std::string ext = p.extension().string();
      if (!entry.is_regular_file() || (ext != ".h" && ext != ".cl" && ext != ".cpp")) continue;
      const fs::path rel = fs::relative(p, root);
      const bool scene = rel.string().rfind("src/scene/", 0) == 0;
      if (rel == fs::path("kernels/gbuffer_codecs.h") || scene) continue;
      ++scanned;
      const std::string code = withoutComments(readTextFile(p.string(), "source file"));
      EXPECT_FALSE(std::regex_search(code, decoder))
          << rel.string() << " decodes a G-buffer element itself; use kernels/gbuffer_codecs.h";
    }
  EXPECT_GT(scanned, 20);
}

}  // namespace
}  // namespace ts
