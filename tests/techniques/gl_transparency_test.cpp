// Transparency in the forward family and tiled's hybrid (--blend blend, issue #17): the
// transparent draws blended back to front over the opaque scene by every forward technique, and by
// `tiled` in a tiled forward pass over its deferred image (techniques/transparent_hybrid.h),
// against the double reference that composites the captured fragments
// (GlRasterizer::captureTransparent, reference/transparent_composite.h) in the same order; the
// analytic "over" of known panes; the capture's overflow; the other G-buffer techniques' refusal;
// the counters. Skips, saying why, where no OpenGL context can be made.
#include <gtest/gtest.h>

#include <iostream>
#include <string>

#include "gl_frame.h"
#include "raster/scene_validation.h"
#include "reference/transparent_composite.h"
#include "reference_check.h"
#include "require_gl.h"
#include "scene/mesh_builder.h"
#include "scene/scene_loader.h"
#include "util/error.h"

namespace ts {
namespace {

using test::GlFrame;

// Issue #17's bound for forward images (gl_tiled_forward_test.cpp): the interpolated float
// position against the one rebuilt from depth, and fp32 sums and blends.
constexpr double kForwardBound = 1e-4;

const char* const kForwardTechniques[] = {"tiled-forward", "tiled-forward-prez", "forward",
                                          "forward-single"};
// The forward techniques and the G-buffer one with the hybrid: every technique that composites.
const char* const kCompositing[] = {"tiled-forward", "tiled-forward-prez", "forward",
                                    "forward-single", "tiled"};

bool hasRow(const FrameResult& r, const std::string& name) {
  for (const KernelTime& k : r.kernels)
    if (k.name == name && k.launches > 0) return true;
  return false;
}

Scene glassScene(const std::string& name, const std::string& variant = "glass") {
  SceneOptions options;
  options.lightSet = name == "street" ? "few" : "small";
  options.variant = variant;
  options.blend = BlendPolicy::Blend;
  return loadScene("builtin:" + name, options);
}

// The frame's opaque reference with its transparent fragments composited over it.
ReferenceImage compositedReference(const GlFrame& g, size_t* fragments = nullptr) {
  const PreparedFrame& f = g.prepared;
  ReferenceImage ref = shadeReference(f.encoded, f.intrinsics, f.lights, f.ambient, 0);
  const std::vector<TransparentFragment> frags =
      g.forward->captureTransparent(g.features, kCaptureBound);
  if (fragments) *fragments = frags.size();
  compositeTransparent(ref, frags, f.lights, f.ambient, 0, f.encoded);
  return ref;
}

TEST(Transparency, GlassVariantAddsBlendedMaterialsWithOpacityBelowOne) {
  for (const char* name : {"street", "atrium"}) {
    SCOPED_TRACE(name);
    const Scene plain = glassScene(name, "");
    const Scene glass = glassScene(name);
    EXPECT_FALSE(drawsBlendedMaterials(plain));
    EXPECT_TRUE(drawsBlendedMaterials(glass));
    EXPECT_GT(glass.triangleCount(), plain.triangleCount());
    for (size_t m = plain.materials.size(); m < glass.materials.size(); ++m) {
      EXPECT_EQ(glass.materials[m].alphaMode, AlphaMode::Blend);
      EXPECT_LT(glass.materials[m].opacity, 1.0f);
      EXPECT_GT(glass.materials[m].opacity, 0.0f);
    }
  }
}

// Every forward technique on the glass variants, frame 0 (whose camera looks at the glass):
// within the forward bound of the composited reference, no NaN, no missed contribution on the
// opaque surfaces; the glass changes the image well beyond that bound.
TEST(Transparency, ForwardTechniquesMatchTheCompositedReference) {
  REQUIRE_GL();
  for (const char* name : {"street", "atrium"}) {
    SCOPED_TRACE(name);
    const Scene scene = glassScene(name);
    GlFrame g(scene, 0, 96, 54);
    ASSERT_GT(g.forward->transparentDraws(), 0u);
    const PreparedFrame& f = g.prepared;
    const ReferenceImage opaque = shadeReference(f.encoded, f.intrinsics, f.lights, f.ambient, 0);
    size_t fragments = 0;
    const ReferenceImage ref = compositedReference(g, &fragments);
    EXPECT_GT(fragments, size_t(96 * 54 / 20)) << "frame 0 sees little glass";
    const ErrorStats glassEffect = compareReferences(opaque, ref, 1e-3 * ref.peak);
    EXPECT_GT(glassEffect.maxRelPeak, 1e-2);
    for (const char* technique : kForwardTechniques) {
      SCOPED_TRACE(technique);
      const FrameResult r = g.render(technique);
      const ErrorStats e = compareToReference(r.image, ref, kForwardBound * ref.peak);
      EXPECT_LE(e.maxRelPeak, kForwardBound);
      EXPECT_EQ(e.nonfinitePixels, 0u);
      ASSERT_TRUE(r.assignment.has_value());
      EXPECT_EQ(countMissedContributions(*r.assignment, f.encoded, f.intrinsics, f.lights, 0), 0u);
      bool transparentRow = false;
      for (const KernelTime& k : r.kernels)
        transparentRow = transparentRow || (k.name == "transparent" && k.launches > 0);
      EXPECT_TRUE(transparentRow);
      std::cout << "[ glass ] " << technique << " on " << name << ": " << fragments
                << " transparent fragments, max error " << e.maxRelPeak << " of the peak\n";
    }
  }
}

// The transparent fragments are shaded and counted: the same opaque scene without the glass
// gives the same opaque passes, so the difference is the transparent pass's work alone.
TEST(Transparency, LightingComputationsIncludeTransparentFragments) {
  REQUIRE_GL();
  const Scene glass = glassScene("street");
  const Scene plain = glassScene("street", "");
  GlFrame withGlass(glass, 0, 96, 54), without(plain, 0, 96, 54);
  for (const char* technique : kCompositing) {
    SCOPED_TRACE(technique);
    const uint64_t a = withGlass.render(technique).counters.lightingComputations;
    const uint64_t b = without.render(technique).counters.lightingComputations;
    EXPECT_GT(a, b);
  }
}

// `tiled`'s hybrid (Olsson & Assarsson Section 4): its deferred image of the opaque surfaces, then
// the glass in a tiled forward pass over its grid re-binned to [znear, the opaque far bound],
// within the forward bound of the composited reference, no NaN, no missed contribution on the
// opaque surfaces (its lists), the glass visible; the copy and the pass are rows of their own.
TEST(Transparency, TiledHybridMatchesTheCompositedReference) {
  REQUIRE_GL();
  for (const char* name : {"street", "atrium"}) {
    SCOPED_TRACE(name);
    const Scene scene = glassScene(name);
    GlFrame g(scene, 0, 96, 54);
    const PreparedFrame& f = g.prepared;
    const ReferenceImage opaque = shadeReference(f.encoded, f.intrinsics, f.lights, f.ambient, 0);
    const ReferenceImage ref = compositedReference(g);
    const FrameResult r = g.render("tiled");
    const ErrorStats e = compareToReference(r.image, ref, kForwardBound * ref.peak);
    EXPECT_LE(e.maxRelPeak, kForwardBound);
    EXPECT_EQ(e.nonfinitePixels, 0u);
    // Against the opaque reference it is far off: the glass is drawn, not left out.
    EXPECT_GT(compareToReference(r.image, opaque, 1e-3 * opaque.peak).maxRelPeak, 1e-2);
    ASSERT_TRUE(r.assignment.has_value());
    EXPECT_EQ(countMissedContributions(*r.assignment, f.encoded, f.intrinsics, f.lights, 0), 0u);
    for (const char* row : {"shade", "transparent_grid", "grid_copy", "image_copy", "transparent"})
      EXPECT_TRUE(hasRow(r, row)) << row;
    double sum = 0.0;
    for (const KernelTime& k : r.kernels) sum += k.ms;
    EXPECT_DOUBLE_EQ(r.totalMs, sum);
    std::cout << "[ glass ] tiled (hybrid) on " << name << ": max error " << e.maxRelPeak
              << " of the peak\n";
  }
}

// The hybrid and tiled-forward-prez draw the same glass fragments with the same shader over lists
// binned the same way (the same kernels on the same depth: the G-buffer's, the pre-pass's); the
// opaque surfaces differ as tiled and forward do (the position from depth against the
// interpolated one), within the forward bound: with the glass the two differ by what they differ
// without it, to fp32 rounding.
TEST(Transparency, TiledHybridAgreesWithTiledForwardPrez) {
  REQUIRE_GL();
  for (const char* name : {"street", "atrium"}) {
    SCOPED_TRACE(name);
    const Scene glass = glassScene(name);
    const Scene plain = glassScene(name, "");
    GlFrame g(glass, 0, 160, 90), p(plain, 0, 160, 90);
    const double hybrid =
        test::relativeDifference(g.render("tiled").image, g.render("tiled-forward-prez").image);
    const double opaque =
        test::relativeDifference(p.render("tiled").image, p.render("tiled-forward-prez").image);
    EXPECT_LE(hybrid, kForwardBound);
    // The glass adds no difference of its own beyond fp32 rounding.
    EXPECT_LE(hybrid, opaque + test::kFp32RelativeTolerance);
    std::cout << "[ glass ] " << name << " 160x90: tiled (hybrid) vs tiled-forward-prez " << hybrid
              << " of the peak; without the glass " << opaque << "\n";
  }
}

// The opaque depth under the glass is the G-buffer pass's, copied; where the rasterizer's last
// G-buffer pass was another frame's, the depth program draws it again: the same image, and a
// note says so.
TEST(Transparency, TiledHybridRedrawsTheDepthOfAnotherFrame) {
  REQUIRE_GL();
  const Scene scene = glassScene("atrium");
  GlFrame g(scene, 0, 96, 54);
  const FrameResult copied = g.render("tiled");
  g.rasterizer.rasterize(scene.camera(1), 64, 36, RasterOptions{});
  const FrameResult redrawn = g.render("tiled");
  EXPECT_LE(test::relativeDifference(copied.image, redrawn.image), test::kFp32RelativeTolerance);
  auto noted = [](const FrameResult& r) {
    for (const std::string& n : r.counters.notes)
      if (n.find("opaque depth drawn again") != std::string::npos) return true;
    return false;
  };
  EXPECT_FALSE(noted(copied));
  EXPECT_TRUE(noted(redrawn));
}

// The G-buffer holds the opaque surfaces only: a G-buffer technique without a tiled forward pass
// for them refuses the frame in one line rather than render it without its glass.
TEST(Transparency, OtherGBufferTechniquesRefuseInOneLine) {
  REQUIRE_GL();
  const Scene scene = glassScene("atrium");
  GlFrame g(scene, 0, 32, 18);
  for (const char* technique :
       {"deferred", "deferred-stencil", "clustered", "tiled-single", "brute"}) {
    SCOPED_TRACE(technique);
    try {
      g.render(technique);
      ADD_FAILURE() << "rendered a frame with transparent surfaces";
    } catch (const Error& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("alphaMode BLEND"), std::string::npos) << what;
      EXPECT_NE(what.find("technique '" + std::string(technique) + "'"), std::string::npos) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
  }
  // The software rasterizer draws no transparent surface: it refuses too.
  EXPECT_THROW(rasterize(scene, scene.camera(0), 32, 18, RasterOptions{}), Error);
}

// Known panes: emission only (no lights, no ambient), so each surface's colour is its emission
// and the image is the analytic premultiplied "over" of the panes' emissions, back to front.
const glm::vec3 kWall{0.2f, 0.4f, 0.6f};
const glm::vec3 kNear{1.0f, 0.5f, 0.25f};
const glm::vec3 kFar{0.1f, 0.9f, 0.3f};

uint32_t emitter(MeshBuilder& mb, glm::vec3 emission, float opacity) {
  Material m;
  m.diffuse = glm::vec3(0.0f);
  m.specular = glm::vec3(0.0f);
  m.emissive = emission;
  m.doubleSided = true;
  if (opacity < 1.0f) {
    m.alphaMode = AlphaMode::Blend;
    m.opacity = opacity;
  }
  return mb.addMaterial(m);
}

// A quad in the plane z, facing the camera at the origin (which looks down -Z), covering the
// frame where it is.
void facingQuad(MeshBuilder& mb, float z, float half, uint32_t material) {
  mb.quad({-half, -half, z}, {half, -half, z}, {half, half, z}, {-half, half, z}, material);
}

// panes: (depth, emission, opacity) in scene (draw) order.
struct Pane {
  float z;
  glm::vec3 emission;
  float opacity;
};
Scene paneScene(const std::vector<Pane>& panes) {
  Scene s;
  s.name = "panes";
  s.ambient = glm::vec3(0.0f);
  s.blendComposited = true;
  MeshBuilder mb(s);
  facingQuad(mb, -10.0f, 40.0f, emitter(mb, kWall, 1.0f));
  for (const Pane& p : panes) facingQuad(mb, p.z, 40.0f, emitter(mb, p.emission, p.opacity));
  s.cameraPath = {
      SceneCamera::lookAt({0.0, 0.0, 0.0}, {0.0, 0.0, -1.0}, {0.0, 1.0, 0.0}, 1.0f, 0.1f, 100.0f)};
  return s;
}

void expectEveryPixel(const FrameResult& r, glm::vec3 expected) {
  size_t wrong = 0;
  for (const glm::vec4& p : r.image)
    wrong += glm::length(glm::vec3(p) - expected) > 1e-6f * glm::length(expected) ? 1 : 0;
  EXPECT_EQ(wrong, 0u) << "first pixel " << r.image[0].x << " " << r.image[0].y << " "
                       << r.image[0].z << ", expected " << expected.x << " " << expected.y << " "
                       << expected.z;
}

TEST(Transparency, HalfTransparentPaneGivesTheAnalyticOver) {
  REQUIRE_GL();
  const Scene scene = paneScene({{-5.0f, kNear, 0.5f}});
  GlFrame g(scene, 0, 32, 18);
  const glm::vec3 expected = 0.5f * kNear + 0.5f * kWall;
  for (const char* technique : kCompositing) {
    SCOPED_TRACE(technique);
    expectEveryPixel(g.render(technique), expected);
  }
  const ReferenceImage ref = compositedReference(g);
  for (const glm::dvec3& c : ref.rgb)
    EXPECT_LE(glm::length(c - glm::dvec3(expected)), 1e-6 * glm::length(glm::dvec3(expected)));
}

// Two panes drawn in the scene's order near first: blended back to front, the far one first;
// the other order would give a visibly different colour.
TEST(Transparency, TwoPanesBlendInDepthOrderWhateverTheirDrawOrder) {
  REQUIRE_GL();
  const Scene scene = paneScene({{-4.0f, kNear, 0.5f}, {-7.0f, kFar, 0.25f}});
  GlFrame g(scene, 0, 32, 18);
  const glm::vec3 behind = 0.25f * kFar + 0.75f * kWall;
  const glm::vec3 expected = 0.5f * kNear + 0.5f * behind;
  const glm::vec3 drawOrder = 0.25f * kFar + 0.75f * (0.5f * kNear + 0.5f * kWall);
  ASSERT_GT(glm::length(expected - drawOrder), 0.05f);
  for (const char* technique : kCompositing) {
    SCOPED_TRACE(technique);
    expectEveryPixel(g.render(technique), expected);
  }
  const ReferenceImage ref = compositedReference(g);
  const ErrorStats e = compareToReference(g.render("forward-single").image, ref, 1e-6 * ref.peak);
  EXPECT_LE(e.maxRelPeak, 1e-6);
}

// Three full-frame panes are three fragments a pixel, more than the capture's first capacity
// (two a pixel): it grows and keeps all; below its bound it refuses in one line.
TEST(Transparency, CaptureGrowsAndReportsOverflow) {
  REQUIRE_GL();
  const Scene scene = paneScene({{-3.0f, kNear, 0.5f}, {-5.0f, kFar, 0.5f}, {-7.0f, kNear, 0.5f}});
  GlFrame g(scene, 0, 32, 18);
  const size_t all = 3 * 32 * 18;
  EXPECT_EQ(g.forward->captureTransparent(g.features, kCaptureBound).size(), all);
  EXPECT_EQ(g.forward->captureTransparent(g.features, all).size(), all);
  try {
    g.forward->captureTransparent(g.features, all - 1);
    ADD_FAILURE() << "an overflowing capture was not reported";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(std::to_string(all) + " fragments"), std::string::npos) << what;
    EXPECT_NE(what.find("bound of " + std::to_string(all - 1)), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace ts
