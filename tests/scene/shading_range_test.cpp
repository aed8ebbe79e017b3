// Scenes whose finite light colours and materials multiply past fp32's range are refused with one
// error instead of rendering inf/NaN (src/scene/shading_range.h, issue #12), and the bound the
// check uses is an upper bound of what the reference shades.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "reference/reference.h"
#include "render/frame_setup.h"
#include "scene/scene_loader.h"
#include "scene/shading_range.h"
#include "util/error.h"

namespace ts {
namespace {

Scene litQuad(glm::vec3 color, glm::vec3 diffuse) {
  Scene s = makeBuiltinScene("atrium", "small", 1);
  for (auto& m : s.materials) m.diffuse = diffuse;
  s.lights = {SceneLight::point({0, 1, 0}, color, 5.0f)};
  return s;
}

TEST(ShadingRange, ProductsBeyondFloatAreRefusedWithOneLine) {
  // Each value is a finite float; C * falloff(100) * kd is 1e40.
  Scene s = litQuad(glm::vec3(1e37f), glm::vec3(10.0f));
  try {
    prepareFrame(s, 0, 16, 16, GBufferFormat::FP32);
    FAIL() << "a scene shading to 1e40 was accepted";
  } catch (const Error& e) {
    std::string what = e.what();
    EXPECT_NE(what.find("beyond what fp32 shading holds"), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << "one line";
  }
  Scene nan = litQuad(glm::vec3(std::numeric_limits<float>::quiet_NaN()), glm::vec3(0.5f));
  EXPECT_THROW(prepareFrame(nan, 0, 16, 16, GBufferFormat::FP32), Error);
  Scene inf = litQuad(glm::vec3(1.0f), glm::vec3(std::numeric_limits<float>::infinity()));
  EXPECT_THROW(prepareFrame(inf, 0, 16, 16, GBufferFormat::FP32), Error);
}

TEST(ShadingRange, BoundHoldsTheReferenceAndAcceptsTheBuiltins) {
  for (const auto& [name, lights] : {std::pair{"street", "many"}, std::pair{"atrium", "mixed"}}) {
    Scene s = makeBuiltinScene(name, lights, 1);
    double bound = shadingRangeBound(s);
    EXPECT_LE(bound, kShadingRangeLimit) << name;
    PreparedFrame f = prepareFrame(s, 0, 64, 48, GBufferFormat::FP32);
    ReferenceImage ref = shadeReference(f.encoded, f.intrinsics, f.lights, f.ambient, 0);
    EXPECT_LE(ref.peak, bound) << name;
  }
  // Near the limit, still accepted.
  Scene big = litQuad(glm::vec3(1e31f), glm::vec3(1e3f));  // bound 1e36
  EXPECT_NO_THROW(prepareFrame(big, 0, 16, 16, GBufferFormat::FP32));
}

}  // namespace
}  // namespace ts
