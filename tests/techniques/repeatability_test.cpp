// Repeatable results (issue #16, item 8): rendering one frame again gives the same image bit for
// bit, for every technique of the registry, every G-buffer layout and lanes width. Tiled and
// clustered once filled their light lists with atomics, so a pixel summed its lights in an order
// that changed from run to run (thousands of pixels off by an ulp on the atrium, mixed lights);
// tiled-single appended to its local list with an atomic, in an order PoCL happens to keep but
// a GPU does not. Light lists are now in light index order by construction (docs/techniques.md).
#include <gtest/gtest.h>

#include <cstring>
#include <string>

#include "gl_frame.h"
#include "render/frame_setup.h"
#include "techniques/technique.h"
#include "reference_check.h"
#include "require_gl.h"
#include "test_support.h"

namespace ts {
namespace {

constexpr int kRuns = 3;

bool sameBits(const std::vector<glm::vec4>& a, const std::vector<glm::vec4>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(a[0])) == 0;
}

// Renders `f` kRuns times with every technique, layout-matching config and lanes width 1 and 16,
// and expects every run's image to equal the first one's bits.
void expectRepeatable(const Scene& scene, int width, int height, const std::string& label) {
  for (GBufferFormat format : {GBufferFormat::FP32, GBufferFormat::FP16, GBufferFormat::PACKED}) {
    PreparedFrame f = prepareFrame(scene, 0, width, height, format);
    for (const std::string& name : gbufferTechniqueNames()) {
      for (int lanes : {1, 16}) {
        TechniqueConfig config;
        config.format = format;
        config.lanes = lanes;
        Technique& t = test::cachedTechnique(name, config);
        std::string what =
            label + ": " + name + " " + toString(format) + " lanes " + std::to_string(lanes);
        const FrameResult first = test::renderOnly(f, t, false);
        for (int run = 1; run < kRuns; ++run)
          EXPECT_TRUE(sameBits(first.image, test::renderOnly(f, t, false).image))
              << what << ", run " << run + 1 << " differs from run 1";
      }
    }
  }
}

// Long lists: the reproduction (every light of atrium/mixed reaches many tiles).
TEST(Repeatability, AtriumMixedSameBitsOnEveryRun) {
  expectRepeatable(test::builtinScene("atrium", "mixed"), 160, 90, "atrium mixed 160x90");
}

// A list longer than tiled-single's local chunk (256 lights): 300 huge lights reach every tile,
// so tiled-single shades two chunks and tiled and clustered fill lists of 300 from 300 lights at
// once (the most contention on each bin's cursor).
TEST(Repeatability, ListsLongerThanTheLocalChunkSameBitsOnEveryRun) {
  Scene scene = test::atriumLatticeLights(300);
  expectRepeatable(scene, 64, 36, "atrium 64x36, 300 lights in every tile");
}

// The techniques that draw the scene (OpenGL passes on the OpenCL grid): the same bits on every
// run too, on the long lists of atrium/mixed (llvmpipe here; a driver's blending order is fixed
// per pixel by the API, so this holds on any conformant one).
TEST(Repeatability, ForwardTechniquesSameBitsOnEveryRun) {
  REQUIRE_GL();
  test::GlFrame g(test::builtinScene("atrium", "mixed"), 0, 96, 54,
                  SceneFeatures::general(ShadingModel::BlinnPhong));
  ASSERT_NE(g.forward, nullptr);
  for (const TechniqueInfo& info : techniqueRegistry()) {
    if (!info.drawsScene) continue;
    std::unique_ptr<Technique> t = createTechnique(info.name, test::context(), g.config());
    const FrameResult first = g.render(*t);
    for (int run = 1; run < kRuns; ++run)
      EXPECT_TRUE(sameBits(first.image, g.render(*t).image))
          << info.name << ", run " << run + 1 << " differs from run 1";
  }
}

// The order itself, where an image may not tell it: every bin of tiled, tiled-single and
// clustered lists its lights in strictly increasing index order, on every run: atrium/mixed, and
// 300 lights reaching every bin (two local chunks of tiled-single). Without the presized list,
// the first frame overflows the list buffer, is sorted as far as it was written, and is re-run.
TEST(Repeatability, BinListsInLightIndexOrder) {
  for (const PreparedFrame& f :
       {prepareFrame(test::builtinScene("atrium", "mixed"), 0, 160, 90, GBufferFormat::FP32),
        test::hugeLightsFrame(300)})
    for (bool presize : {true, false})
      for (const char* name : {"tiled", "tiled-single", "clustered"}) {
        TechniqueConfig config;
        config.presizeLists = presize;
        auto fresh = createTechnique(name, test::context(), config);  // its list starts small
        Technique& t = *fresh;
        for (int run = 0; run < kRuns; ++run) {
          FrameResult r = test::renderOnly(f, t, true);
          ASSERT_TRUE(r.assignment.has_value()) << name;
          const LightAssignment& a = *r.assignment;
          size_t unordered = 0, listed = 0;
          for (size_t b = 0; b < a.binCount.size(); ++b) {
            listed += a.binCount[b];
            for (uint32_t k = 1; k < a.binCount[b]; ++k)
              unordered += a.binLights[a.binOffset[b] + k - 1] >= a.binLights[a.binOffset[b] + k];
          }
          EXPECT_GT(listed, 0u) << name;
          bool outgrewFirstBuffer = listed > 8 * a.binCount.size();  // it starts at 8 per tile
          if (!presize && run == 0 && std::string(name) != "tiled-single" && outgrewFirstBuffer) {
            EXPECT_FALSE(r.counters.notes.empty()) << name << ": the list did not grow";
          }
          EXPECT_EQ(unordered, 0u) << name << (presize ? "" : " (grown list)") << ", run "
                                   << run + 1 << ": entries out of order";
        }
      }
}

}  // namespace
}  // namespace ts
