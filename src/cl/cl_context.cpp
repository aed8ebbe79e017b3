#include "cl/cl_context.h"

#include <algorithm>
#include <limits>
#include <cctype>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include "util/data_dir.h"
#include "util/error.h"
#include "util/file_read.h"
#include "util/short_text.h"

namespace ts {
namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

std::string typeName(cl_device_type type) {
  if (type & CL_DEVICE_TYPE_GPU) return "gpu";
  if (type & CL_DEVICE_TYPE_CPU) return "cpu";
  if (type & CL_DEVICE_TYPE_ACCELERATOR) return "accelerator";
  return "other";
}

std::string trim(std::string s) {
  while (!s.empty() && (s.back() == '\0' || std::isspace((unsigned char)s.back()))) s.pop_back();
  size_t b = 0;
  while (b < s.size() && std::isspace((unsigned char)s[b])) ++b;
  return s.substr(b);
}

const DeviceInfo& choose(const std::vector<DeviceInfo>& devices, const std::string& spec) {
  if (devices.empty()) {
    throw Error("no OpenCL device found (install pocl-opencl-icd, or a GPU driver's ICD)");
  }
  auto firstOfType = [&](const std::string& type) -> const DeviceInfo* {
    for (const auto& d : devices)
      if (d.type == type) return &d;
    return nullptr;
  };
  std::string s = lower(trim(spec));
  if (s.empty() || s == "default") {
    if (auto d = firstOfType("gpu")) return *d;
    if (auto d = firstOfType("cpu")) return *d;
    return devices.front();
  }
  if (s == "cpu" || s == "gpu") {
    if (auto d = firstOfType(s)) return *d;
    throw Error("no OpenCL " + s + " device (see `tileshade devices`)");
  }
  if (std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isdigit(c); })) {
    // At most 9 digits, so that the number fits (a longer one is out of range anyway).
    size_t i = s.size() <= 9 ? std::stoul(s) : std::numeric_limits<size_t>::max();
    if (i < devices.size()) return devices[i];
    throw Error("device index " + s + " out of range: " + std::to_string(devices.size()) +
                " device(s) (see `tileshade devices`)");
  }
  for (const auto& d : devices)
    if (lower(d.platform + " " + d.name).find(s) != std::string::npos) return d;
  throw Error("no OpenCL device matches '" + shortText(spec) + "' (see `tileshade devices`)");
}

std::string readFile(const std::string& path) {
  if (!std::filesystem::exists(path))
    throw Error("cannot read kernel source " + path + " (set TILESHADE_KERNEL_DIR?)");
  return readTextFile(path, "kernel source");
}

// Replaces each `#include "file"` line with that file from kernels/ (each file once), so a
// program's source is self-contained: no -I path for the OpenCL compiler to mis-split, and
// compiler caches key on the real text.
std::string inlineIncludes(const std::string& dir, const std::string& source,
                           std::vector<std::string>& seen) {
  std::istringstream in(source);
  std::ostringstream out;
  std::string line;
  while (std::getline(in, line)) {
    size_t q0, q1;
    if (line.rfind("#include \"", 0) == 0 && (q0 = line.find('"')) != std::string::npos &&
        (q1 = line.find('"', q0 + 1)) != std::string::npos) {
      std::string name = line.substr(q0 + 1, q1 - q0 - 1);
      if (std::find(seen.begin(), seen.end(), name) == seen.end()) {
        seen.push_back(name);
        out << inlineIncludes(dir, readFile(dir + "/" + name), seen) << "\n";
      }
      continue;
    }
    out << line << "\n";
  }
  return out.str();
}

DeviceInfo describe(const cl::Platform& p, const cl::Device& d, int index) {
  DeviceInfo info;
  info.index = index;
  info.platform = trim(p.getInfo<CL_PLATFORM_NAME>());
  info.name = trim(d.getInfo<CL_DEVICE_NAME>());
  info.type = typeName(d.getInfo<CL_DEVICE_TYPE>());
  info.computeUnits = int(d.getInfo<CL_DEVICE_MAX_COMPUTE_UNITS>());
  info.globalMemBytes = size_t(d.getInfo<CL_DEVICE_GLOBAL_MEM_SIZE>());
  info.localMemBytes = size_t(d.getInfo<CL_DEVICE_LOCAL_MEM_SIZE>());
  info.maxWorkGroupSize = d.getInfo<CL_DEVICE_MAX_WORK_GROUP_SIZE>();
  info.maxWorkItemSizes = d.getInfo<CL_DEVICE_MAX_WORK_ITEM_SIZES>();
  info.device = d;
  return info;
}

}  // namespace

std::vector<DeviceInfo> listDevices() {
  std::vector<DeviceInfo> out;
  std::vector<cl::Platform> platforms;
  try {
    cl::Platform::get(&platforms);
  } catch (const cl::Error&) {
    return out;  // CL_PLATFORM_NOT_FOUND_KHR: no ICD installed
  }
  for (auto& p : platforms) {
    std::vector<cl::Device> devices;
    try {
      p.getDevices(CL_DEVICE_TYPE_ALL, &devices);
    } catch (const cl::Error&) {
      continue;
    }
    for (auto& d : devices) out.push_back(describe(p, d, int(out.size())));
  }
  return out;
}

std::string kernelDir() { return dataDir("TILESHADE_KERNEL_DIR", "kernels", TILESHADE_KERNEL_DIR); }

ClContext::ClContext(const std::string& spec) {
  std::string s = spec;
  if (s.empty())
    if (const char* env = std::getenv("TILESHADE_DEVICE"); env) s = env;
  info_ = choose(listDevices(), s);
  context_ = cl::Context(info_.device);
  queue_ = cl::CommandQueue(context_, info_.device, CL_QUEUE_PROFILING_ENABLE);
}

ClContext::ClContext(cl_context context, cl_device_id device, cl_command_queue queue) {
  if (!context || !device || !queue)
    throw Error("Device::fromOpenCL needs a context, a device and a command queue (one is null)");
  cl_command_queue_properties properties = 0;
  cl_device_id queueDevice = nullptr;
  cl_context queueContext = nullptr;
  if (clGetCommandQueueInfo(queue, CL_QUEUE_PROPERTIES, sizeof properties, &properties, nullptr) !=
          CL_SUCCESS ||
      clGetCommandQueueInfo(queue, CL_QUEUE_DEVICE, sizeof queueDevice, &queueDevice, nullptr) !=
          CL_SUCCESS ||
      clGetCommandQueueInfo(queue, CL_QUEUE_CONTEXT, sizeof queueContext, &queueContext, nullptr) !=
          CL_SUCCESS)
    throw Error("Device::fromOpenCL: the command queue is not a valid OpenCL queue");
  if (!(properties & CL_QUEUE_PROFILING_ENABLE))
    throw Error(
        "Device::fromOpenCL: the command queue was created without "
        "CL_QUEUE_PROFILING_ENABLE; tileshade times kernels from its events");
  if (queueDevice != device || queueContext != context)
    throw Error("Device::fromOpenCL: the command queue belongs to another device or context");
  // retainObject = true: the caller keeps its own references.
  context_ = cl::Context(context, true);
  queue_ = cl::CommandQueue(queue, true);
  const cl::Device d(device, true);
  info_ = describe(cl::Platform(d.getInfo<CL_DEVICE_PLATFORM>(), true), d, -1);
}

cl::Program ClContext::build(const std::string& file, const std::string& options) {
  std::string dir = kernelDir();
  std::vector<std::string> seen;
  std::string source = inlineIncludes(dir, readFile(dir + "/" + file), seen);
  cl::Program program(context_, source);
  // Kernels may use what only PoCL's compiler and runtime handle (kernels/gbuffer.h, TS_POCL).
  std::string opts = "-cl-std=CL1.2 " + options;
  if (info_.platform.find("Portable Computing Language") != std::string::npos) opts += " -DTS_POCL";
  auto t0 = std::chrono::steady_clock::now();
  try {
    program.build({info_.device}, opts.c_str());
  } catch (const cl::Error&) {
    std::string log = program.getBuildInfo<CL_PROGRAM_BUILD_LOG>(info_.device);
    throw Error("OpenCL build of kernels/" + file + " failed (options: " + options + "):\n" + log);
  }
  compileMs_ +=
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return program;
}

double ClContext::eventMs(const cl::Event& event) {
  cl_ulong start = event.getProfilingInfo<CL_PROFILING_COMMAND_START>();
  cl_ulong end = event.getProfilingInfo<CL_PROFILING_COMMAND_END>();
  return double(end - start) * 1e-6;
}

}  // namespace ts
