#pragma once
// OpenCL set-up: device choice, a profiling command queue, program builds from kernels/.
#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include <CL/opencl.hpp>

namespace ts {

struct DeviceInfo {
  int index = 0;  // position in listDevices(), usable as --device <index>
  std::string platform;
  std::string name;
  std::string type;  // "gpu", "cpu", "accelerator", "other"
  int computeUnits = 0;
  size_t globalMemBytes = 0;
  size_t localMemBytes = 0;
  size_t maxWorkGroupSize = 0;
  std::vector<size_t> maxWorkItemSizes;  // per dimension
  cl::Device device;
};

std::vector<DeviceInfo> listDevices();

// Where kernels/ lives: $TILESHADE_KERNEL_DIR, else <exe>/../share/tileshade/kernels, else (run
// from a build folder) the source tree this binary was built from (util/data_dir.h).
std::string kernelDir();

class ClContext {
 public:
  // spec: "" or "default" (first GPU, else first CPU), "cpu", "gpu", an index from listDevices(),
  // or a case-insensitive substring of "platform device". Throws ts::Error when nothing matches.
  // $TILESHADE_DEVICE is used when spec is empty.
  explicit ClContext(const std::string& spec = "");
  // The caller's own objects (an engine's context, device and queue; each retained). The queue
  // must profile (CL_QUEUE_PROFILING_ENABLE): frame times come from its events. Throws ts::Error
  // otherwise, or when the device is not the queue's.
  ClContext(cl_context context, cl_device_id device, cl_command_queue queue);

  const DeviceInfo& info() const { return info_; }
  std::string deviceName() const { return info_.platform + " / " + info_.name; }
  bool isGpu() const { return info_.type == "gpu"; }

  // Builds kernels/<file> (its #include "…" lines inlined from kernels/) with `options`.
  // Throws ts::Error with the build log.
  // The build's wall time is added to compileMs().
  cl::Program build(const std::string& file, const std::string& options = "");
  double compileMs() const { return compileMs_; }

  cl::Context& context() { return context_; }
  cl::CommandQueue& queue() { return queue_; }
  const cl::Device& device() const { return info_.device; }

  // The most work-items a work-group may have: the device's CL_DEVICE_MAX_WORK_GROUP_SIZE, or
  // less after capWorkGroupSize, which tests use to stand in for a stricter device. Launches take
  // their shapes from it through src/cl/work_group.h.
  size_t maxWorkGroupSize() const { return std::min(info_.maxWorkGroupSize, groupCap_); }
  void capWorkGroupSize(size_t items) { groupCap_ = items; }

  // Start-to-end time of a finished, profiled command.
  static double eventMs(const cl::Event& event);

 private:
  DeviceInfo info_;
  cl::Context context_;
  cl::CommandQueue queue_;
  double compileMs_ = 0.0;
  size_t groupCap_ = SIZE_MAX;
};

// Rounds n up to a multiple of m (global sizes for NDRanges).
inline size_t roundUp(size_t n, size_t m) { return (n + m - 1) / m * m; }

}  // namespace ts
