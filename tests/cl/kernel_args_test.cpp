// KernelArgs (src/cl/kernel_args.h): arguments are bound in order, and a launch whose arguments
// are not as many as the kernel declares is an error naming the kernel, not a failed enqueue.
#include <gtest/gtest.h>

#include <string>

#include "cl/kernel_args.h"
#include "test_support.h"
#include "util/error.h"

namespace ts {
namespace {

cl::Kernel threeArgs() {
  cl::Program program(test::context().context(),
                      "kernel void three_args(global float* out, float a, int b) {"
                      " out[0] = a + (float)b; }",
                      true);
  return cl::Kernel(program, "three_args");
}

std::string doneError(KernelArgs& args) {
  try {
    args.done();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(KernelArgs, BindsInOrderAndAcceptsTheDeclaredCount) {
  cl::Kernel kernel = threeArgs();
  cl::Buffer out(test::context().context(), CL_MEM_WRITE_ONLY, sizeof(float));
  cl_uint later = 0;
  KernelArgs args(kernel);
  args.add(out).later(later).add(cl_int(2));
  EXPECT_EQ(later, 1u);
  EXPECT_EQ(args.next(), 3u);
  EXPECT_NO_THROW(args.done());
  kernel.setArg(later, 0.5f);
  test::context().queue().enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(1));
  float result = 0.0f;
  test::context().queue().enqueueReadBuffer(out, CL_TRUE, 0, sizeof(float), &result);
  EXPECT_EQ(result, 2.5f);
}

TEST(KernelArgs, AWrongCountIsAnErrorNamingTheKernel) {
  cl::Kernel kernel = threeArgs();
  cl::Buffer out(test::context().context(), CL_MEM_WRITE_ONLY, sizeof(float));
  KernelArgs tooFew(kernel);
  tooFew.add(out).add(0.5f);
  EXPECT_EQ(doneError(tooFew), "kernel three_args declares 3 arguments but 2 were bound");
  cl_uint extra = 0;
  KernelArgs tooMany(kernel);
  tooMany.add(out).add(0.5f).add(cl_int(2)).later(extra);
  EXPECT_EQ(doneError(tooMany), "kernel three_args declares 3 arguments but 4 were bound");
}

}  // namespace
}  // namespace ts
