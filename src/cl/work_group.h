#pragma once
// Work-group shapes within what the device and the kernel allow. Every launch asks for its shape
// here instead of fixing it: a device may allow fewer work-items per group than the 256 the
// kernels were tuned for (CL_DEVICE_MAX_WORK_GROUP_SIZE; Oclgrind's --max-wgsize 128, embedded
// and some mobile GPUs), and a kernel may allow fewer than its device (CL_KERNEL_WORK_GROUP_SIZE:
// registers, local memory). A launch over the limit fails with CL_INVALID_WORK_GROUP_SIZE (issue
// #12). The shapes only shrink: on a device that allows the preferred shape nothing changes.
#include <array>
#include <cstddef>

#include <CL/opencl.hpp>

namespace ts {

class ClContext;

// What a work-group may be: at most `size` work-items in all, at most items[d] along dimension d.
struct GroupLimit {
  size_t size = 1;
  std::array<size_t, 2> items{{1, 1}};
};

// The limit for launching `kernel` on cl's device: the device's (ClContext::maxWorkGroupSize, which
// a test may cap), and the kernel's own CL_KERNEL_WORK_GROUP_SIZE.
GroupLimit groupLimit(const ClContext& cl, const cl::Kernel& kernel);
// The device's alone, for a kernel whose shape is fixed when it is built (before the kernel
// exists).
GroupLimit deviceGroupLimit(const ClContext& cl);

// A 2-D work-group shape.
struct GroupShape {
  size_t x = 1, y = 1;
  size_t size() const { return x * y; }
  cl::NDRange local() const { return cl::NDRange(x, y); }
  // The global range covering width x height work-items in whole groups.
  cl::NDRange global(size_t width, size_t height) const;
};

// One dimension: the largest power of two <= both `preferred` and the limit (tree reductions need
// a power of two). `preferred` >= 1.
size_t powerOfTwoGroup(size_t preferred, const GroupLimit& limit);
// The preferred shape, its larger side halved (rounding up) until it fits the limit.
GroupShape fitGroup(size_t preferredX, size_t preferredY, const GroupLimit& limit);
// The largest shape whose sides divide the tile's and are at most 16, that fits the limit: a
// work-group never straddles two tiles (kernels that take the tile from the group id).
GroupShape tileDividingGroup(int tileW, int tileH, const GroupLimit& limit);

}  // namespace ts
