// The kernels' specular power (TS_POW in kernels/gbuffer.h: exp2 of s times an inline log2 under
// --math precise) against double-precision pow, run on the device through kernels/math_probe.cl in
// scalar code and in 16 lanes. docs/accuracy.md states the bound held here: relative error below
// 4e-6 wherever x^s >= 2^-24 (what can reach a pixel), and below that an absolute error under
// 2^-24; exact at x = 1 and 0.
#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "techniques/technique.h"
#include "test_support.h"

namespace ts {
namespace {

struct PowSample {
  std::vector<float> x, s;
};

PowSample samples() {
  PowSample p;
  const float exponents[] = {1.0f,  1.5f,   2.0f,   4.7f,   8.0f,    16.0f,  32.5f,
                             64.0f, 128.0f, 255.0f, 512.0f, 1000.0f, 2048.0f};
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f), log2x(-126.0f, 0.0f);
  for (float s : exponents) {
    auto add = [&](float x) {
      p.x.push_back(x);
      p.s.push_back(s);
    };
    for (float x : {0.0f, 1.0f, FLT_MIN, std::nextafter(1.0f, 0.0f), 0.5f, 0.70710677f, 0.999f,
                    1e-45f, 1e-40f})
      add(x);
    for (int i = 0; i < 4000; ++i) add(unit(rng));
    for (int i = 0; i < 2000; ++i) add(std::exp2(log2x(rng)));
    for (int i = 0; i < 2000; ++i) add(1.0f - std::ldexp(unit(rng), -8));  // near 1: highlights
  }
  while (p.x.size() % 16) {
    p.x.push_back(1.0f);
    p.s.push_back(1.0f);
  }
  return p;
}

std::vector<float> runProbe(const PowSample& p, int lanes) {
  TechniqueConfig config;
  config.lanes = lanes;
  cl::Program program =
      test::context().build("math_probe.cl", config.kernelOptions() + config.lanesOption());
  cl::Kernel kernel(program, "specular_power");
  cl::Context& ctx = test::context().context();
  const size_t bytes = p.x.size() * sizeof(float);
  cl::Buffer x(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, bytes, const_cast<float*>(p.x.data()));
  cl::Buffer s(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, bytes, const_cast<float*>(p.s.data()));
  cl::Buffer out(ctx, CL_MEM_WRITE_ONLY, bytes);
  kernel.setArg(0, x);
  kernel.setArg(1, s);
  kernel.setArg(2, out);
  test::context().queue().enqueueNDRangeKernel(kernel, cl::NullRange,
                                               cl::NDRange(p.x.size() / size_t(lanes)));
  std::vector<float> result(p.x.size());
  test::context().queue().enqueueReadBuffer(out, CL_TRUE, 0, bytes, result.data());
  return result;
}

TEST(MathProbe, SpecularPowerWithinItsBoundInScalarAndLanes) {
  const PowSample p = samples();
  for (int lanes : {1, 16}) {
    const std::vector<float> got = runProbe(p, lanes);
    double worstRelative = 0.0, worstAbsolute = 0.0;
    int failures = 0;
    for (size_t i = 0; i < got.size() && failures < 10; ++i) {
      const double want = std::pow(double(p.x[i]), double(p.s[i]));
      const double g = got[i];
      bool ok = std::isfinite(g) && g >= 0.0;
      if (p.x[i] == 1.0f || p.x[i] == 0.0f) {
        ok = ok && g == want;
      } else if (want >= std::ldexp(1.0, -24)) {
        const double rel = std::abs(g - want) / want;
        worstRelative = std::max(worstRelative, rel);
        ok = ok && rel < 4e-6;
      } else {
        worstAbsolute = std::max(worstAbsolute, std::abs(g - want));
        ok = ok && std::abs(g - want) < std::ldexp(1.0, -24);
      }
      if (!ok) {
        ++failures;
        ADD_FAILURE() << "lanes " << lanes << ": " << p.x[i] << "^" << p.s[i] << " = " << g
                      << ", double " << want;
      }
    }
    RecordProperty("lanes" + std::to_string(lanes) + "_max_relative_error",
                   std::to_string(worstRelative));
    std::printf("lanes %d: max relative error %.3g (x^s >= 2^-24), max absolute below %.3g\n",
                lanes, worstRelative, worstAbsolute);
  }
}

}  // namespace
}  // namespace ts
