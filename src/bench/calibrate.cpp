#include "bench/calibrate.h"

#include <algorithm>

#include "bench/bench_stats.h"
#include "cl/kernel_args.h"
#include "util/error.h"

namespace ts {
namespace {

int nativeFloatWidth(const cl::Device& device) {
  cl_uint w = device.getInfo<CL_DEVICE_NATIVE_VECTOR_WIDTH_FLOAT>();
  if (w >= 16) return 16;
  if (w >= 8) return 8;
  if (w >= 4) return 4;
  if (w >= 2) return 2;
  return 1;
}

}  // namespace

nlohmann::json Calibration::toJson() const {
  return {{"copy_bandwidth_gbs", bandwidthGBs},
          {"peak_gflops", peakGflops},
          {"copy_bytes_per_buffer", copyBytes},
          {"copy_ms", copyMs},
          {"fma_vector_width", vectorWidth},
          {"fma_chains", chains},
          {"fma_work_items", fmaWorkItems},
          {"fma_iterations", fmaIterations},
          {"fma_ms", fmaMs},
          {"kernel_source", "kernels/calibrate.cl"}};
}

Calibration calibrate(ClContext& cl, const CalibrationOptions& o) {
  if (o.repeats < 1) throw Error("calibration needs at least one timed launch");
  Calibration c;
  c.vectorWidth = nativeFloatWidth(cl.device());
  c.chains = 8;
  cl::Program program = cl.build("calibrate.cl", "-DCAL_WIDTH=" + std::to_string(c.vectorWidth) +
                                                     " -DCAL_CHAINS=" + std::to_string(c.chains));
  auto& q = cl.queue();

  // Copy bandwidth. The buffer is capped by what the device allows per allocation.
  size_t maxAlloc = size_t(cl.device().getInfo<CL_DEVICE_MAX_MEM_ALLOC_SIZE>());
  size_t bytes = std::min(o.copyBytes, maxAlloc) / 16 * 16;
  bytes = std::max<size_t>(bytes, 16 * 1024);
  c.copyBytes = bytes;
  {
    cl::Buffer in(cl.context(), CL_MEM_READ_ONLY, bytes),
        out(cl.context(), CL_MEM_WRITE_ONLY, bytes);
    const float one = 1.0f;
    q.enqueueFillBuffer(in, one, 0, bytes);
    q.enqueueFillBuffer(out, one, 0, bytes);  // touch the pages before timing
    cl::Kernel copy(program, "copy_float4");
    KernelArgs(copy).add(in).add(out).done();
    for (int i = 0; i <= o.repeats; ++i) {
      cl::Event e;
      q.enqueueNDRangeKernel(copy, cl::NullRange, cl::NDRange(bytes / 16), cl::NullRange, nullptr,
                             &e);
      e.wait();
      if (i > 0) c.copyMs.push_back(ClContext::eventMs(e));  // launch 0 is the warm-up
    }
  }
  double copyMs = summarize(c.copyMs).median;
  c.bandwidthGBs = copyMs > 0 ? 2.0 * double(bytes) / (copyMs * 1e-3) / 1e9 : 0.0;

  // Peak arithmetic: enough work-items to fill the device, iterations doubled until a launch is
  // long enough to time reliably.
  c.fmaWorkItems = std::max<size_t>(size_t(cl.info().computeUnits) * 2048, 16384);
  cl::Buffer sink(cl.context(), CL_MEM_WRITE_ONLY, c.fmaWorkItems * sizeof(float));
  cl::Kernel fma(program, "fma_chain");
  cl_uint iterationsArg = 0;
  KernelArgs(fma).add(sink).later(iterationsArg).add(0.999f).add(0.001f).done();
  auto launch = [&](int iterations) {
    fma.setArg(iterationsArg, iterations);
    cl::Event e;
    q.enqueueNDRangeKernel(fma, cl::NullRange, cl::NDRange(c.fmaWorkItems), cl::NullRange, nullptr,
                           &e);
    e.wait();
    return ClContext::eventMs(e);
  };
  int iterations = 64;
  double ms = launch(iterations);  // also the warm-up
  while (ms < o.minFmaMs && iterations < (1 << 24)) {
    iterations *= ms > 0 ? std::clamp(int(o.minFmaMs / ms * 1.2) + 1, 2, 64) : 64;
    ms = launch(iterations);
  }
  c.fmaIterations = iterations;
  for (int i = 0; i < o.repeats; ++i) c.fmaMs.push_back(launch(iterations));
  double fmaMs = summarize(c.fmaMs).median;
  double flops = 2.0 * double(c.fmaWorkItems) * iterations * c.chains * c.vectorWidth;
  c.peakGflops = fmaMs > 0 ? flops / (fmaMs * 1e-3) / 1e9 : 0.0;
  return c;
}

double limitMs(const Calibration& c, double bytes, double flops) {
  if (c.bandwidthGBs <= 0 || c.peakGflops <= 0) return 0.0;
  double memory = bytes / (c.bandwidthGBs * 1e9) * 1e3;
  double arithmetic = flops / (c.peakGflops * 1e9) * 1e3;
  return std::max(memory, arithmetic);
}

}  // namespace ts
