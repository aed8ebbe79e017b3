#pragma once
// Binds a kernel's arguments in order, so that no call site counts indices by hand, and checks at
// the end that every argument the kernel declares was bound.
#include <string>
#include <tuple>

#include <CL/opencl.hpp>

namespace ts {

class KernelArgs {
 public:
  explicit KernelArgs(cl::Kernel& kernel) : kernel_(kernel) {}

  template <typename T>
  KernelArgs& add(const T& value) {
    kernel_.setArg(next_++, value);
    return *this;
  }
  // A group of arguments in order (DeviceFrame's planes and lights).
  template <typename... Ts>
  KernelArgs& add(const std::tuple<Ts...>& group) {
    // this-> spelled out: clang's -Wunused-lambda-capture misses the implicit one in a generic
    // lambda (and g++ needs the capture).
    std::apply([this](const auto&... value) { (this->add(value), ...); }, group);
    return *this;
  }
  // The group only when `bound` (arguments that a kernel has in some builds only).
  template <typename... Ts>
  KernelArgs& addIf(bool bound, const std::tuple<Ts...>& group) {
    if (bound) add(group);
    return *this;
  }
  // Leaves the next argument to be set before each launch: `index` receives its index.
  KernelArgs& later(cl_uint& index) {
    index = next_++;
    return *this;
  }
  cl_uint next() const { return next_; }

  // Throws ts::Error naming the kernel when the arguments bound (later ones included) are not
  // as many as it declares (CL_KERNEL_NUM_ARGS).
  void done() const;

 private:
  cl::Kernel& kernel_;
  cl_uint next_ = 0;
};

}  // namespace ts
