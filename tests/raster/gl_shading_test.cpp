// kernels/shading.h compiled as GLSL (shaders/opencl_as_glsl.h, src/raster/gl_gbuffer_shading.h):
// the fragment shader's source is the kernels' file itself, and a G-buffer shaded in a fragment
// shader agrees with the OpenCL `brute` technique and with the double reference to fp32 rounding.
// The GL tests skip, saying why, where no OpenGL context can be made.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "cl/cl_context.h"
#include "raster/egl_context.h"
#include "raster/gl_gbuffer_shading.h"
#include "reference_check.h"
#include "require_gl.h"
#include "util/error.h"
#include "util/file_read.h"

namespace ts {
namespace {

// Sets an environment variable for one scope.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const std::string& value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old, had_ = true;
    ::setenv(name, value.c_str(), 1);
  }
  ~ScopedEnv() {
    if (had_) ::setenv(name_, old_.c_str(), 1);
    else ::unsetenv(name_);
  }

 private:
  const char* name_;
  std::string old_;
  bool had_ = false;
};

// The GLSL build's source holds the OpenCL build's kernels/shading.h byte for byte, and it is
// the file of the kernel folder (TILESHADE_KERNEL_DIR) that is read: a marked copy there shows up.
TEST(GlShading, FragmentSourceIsTheKernelsShadingHeader) {
  const std::string header = readTextFile(kernelDir() + "/shading.h", "shading header");
  const std::string source = GlGBufferShading::fragmentSource();
  EXPECT_NE(source.find(header), std::string::npos)
      << "the fragment shader does not contain " << kernelDir() << "/shading.h verbatim";
  EXPECT_NE(source.find("opencl_as_glsl"), std::string::npos);

  const std::filesystem::path dir = test::freshDir("gl_shading", "kernel_dir");
  const std::string marker = "/* a marked copy of shading.h */\n";
  std::ofstream(dir / "shading.h") << marker << header;
  ScopedEnv env("TILESHADE_KERNEL_DIR", dir.string());
  const std::string marked = GlGBufferShading::fragmentSource();
  EXPECT_NE(marked.find(marker + header), std::string::npos)
      << "the fragment shader does not read shading.h from $TILESHADE_KERNEL_DIR";
  std::filesystem::remove_all(dir);
}

struct ShadedFrame {
  std::string name;
  PreparedFrame frame;
  TechniqueConfig config;
};

// Extra light types on a built-in frame (view space): a spot light at the camera looking ahead
// and a directional light, so the spot and directional terms run too.
void addSpotAndDirectional(PreparedFrame& f) {
  f.lights.addSpot(glm::vec3(0.5f, 0.5f, -1.0f), 40.0f, glm::vec3(3.0f, 2.5f, 2.0f),
                   glm::normalize(glm::vec3(0.1f, -0.2f, -1.0f)), 0.2f, 0.5f);
  f.lights.addDirectional(glm::normalize(glm::vec3(0.3f, 1.0f, 0.4f)),
                          glm::vec3(0.2f, 0.2f, 0.25f));
}

// The bound: both sides are fp32 sums of the same terms in the same order; the fragment shader's
// compiler may contract or reorder differently and GLSL's pow/inversesqrt are not OpenCL's, a few
// ulps per term. kFp32RelativeTolerance (2e-5 of the peak, reference_check.h) is the bound every
// fp32 kernel meets against the double reference; it holds here for both comparisons.
TEST(GlShading, FragmentShaderMatchesBruteAndTheReference) {
  REQUIRE_GL();
  std::vector<ShadedFrame> frames;
  for (const auto& [scene, lights] : {std::pair{"atrium", "small"}, std::pair{"street", "many"}}) {
    const Scene& s = test::builtinScene(scene, lights);
    ShadedFrame f{std::string(scene) + "/" + lights + " blinn-phong general", {}, {}};
    f.frame = prepareFrame(s, 0, 96, 54, GBufferFormat::FP32);
    addSpotAndDirectional(f.frame);
    frames.push_back(std::move(f));
  }
  {
    const Scene& s = test::builtinScene("atrium", "small");
    ShadedFrame f{"atrium/small metallic-roughness general", {}, {}};
    f.config.features = SceneFeatures::general(ShadingModel::MetallicRoughness);
    f.frame = prepareFrame(s, 1, 96, 54, GBufferFormat::FP32, f.config.features);
    addSpotAndDirectional(f.frame);
    frames.push_back(std::move(f));
  }
  {
    const Scene& s = test::builtinScene("street", "few");
    ShadedFrame f{"street/few as analysed", {}, {}};
    f.config.features = analyzeScene(s, nativeShadingModel(s));
    f.frame = prepareFrame(s, 2, 96, 54, GBufferFormat::FP32, f.config.features);
    frames.push_back(std::move(f));
  }
  GlGBufferShading shading;
  for (const ShadedFrame& sf : frames) {
    SCOPED_TRACE(sf.name);
    const PreparedFrame& f = sf.frame;
    const std::vector<glm::vec4> gl =
        shading.shade(f.encoded, f.intrinsics, f.lights, f.ambient, f.features, 0);
    const ReferenceImage ref = shadeReference(f.encoded, f.intrinsics, f.lights, f.ambient, 0);
    ASSERT_GT(ref.peak, 0.0);
    const ErrorStats e = compareToReference(gl, ref, test::kFp32RelativeTolerance * ref.peak);
    EXPECT_LE(e.maxRelPeak, test::kFp32RelativeTolerance);
    EXPECT_EQ(e.nonfinitePixels, 0u);
    const FrameResult brute = test::renderOnly(f, test::cachedTechnique("brute", sf.config), false);
    const double vsBrute = test::relativeDifference(brute.image, gl);
    EXPECT_LE(vsBrute, test::kFp32RelativeTolerance);
    std::cout << "[ GL shade ] " << sf.name << ": " << f.lights.size() << " lights, vs reference "
              << e.maxRelPeak << " of the peak, vs brute " << vsBrute << "\n";
    RecordProperty(sf.name + " vs reference", std::to_string(e.maxRelPeak));
  }
}

// A G-buffer the fragment shader cannot read is refused in one line, not shaded wrong.
TEST(GlShading, RefusesAnEncodingOtherThanFp32) {
  REQUIRE_GL();
  const PreparedFrame f =
      prepareFrame(test::builtinScene("atrium", "small"), 0, 32, 18, GBufferFormat::FP16);
  GlGBufferShading shading;
  try {
    shading.shade(f.encoded, f.intrinsics, f.lights, f.ambient, f.features, 0);
    FAIL() << "an fp16 G-buffer was shaded";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("fp32"), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
  }
}

}  // namespace
}  // namespace ts
