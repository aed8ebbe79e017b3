#include "cl/kernel_args.h"

#include "util/error.h"

namespace ts {

void KernelArgs::done() const {
  const cl_uint declared = kernel_.getInfo<CL_KERNEL_NUM_ARGS>();
  if (next_ == declared) return;
  throw Error("kernel " + kernel_.getInfo<CL_KERNEL_FUNCTION_NAME>() + " declares " +
              std::to_string(declared) + " arguments but " + std::to_string(next_) + " were bound");
}

}  // namespace ts
