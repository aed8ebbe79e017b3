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
          {"copy_bandwidth_gbs_spread", spreadJson(bandwidth)},
          {"peak_gflops_spread", spreadJson(peak)},
          {"rounds", bandwidth.rounds.size()},
          {"settled", settled},
          {"agreement", agreement},
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
  cl::Buffer in(cl.context(), CL_MEM_READ_ONLY, bytes), out(cl.context(), CL_MEM_WRITE_ONLY, bytes);
  const float one = 1.0f;
  q.enqueueFillBuffer(in, one, 0, bytes);
  q.enqueueFillBuffer(out, one, 0, bytes);  // touch the pages before timing
  cl::Kernel copy(program, "copy_float4");
  KernelArgs(copy).add(in).add(out).done();
  auto launchCopy = [&] {
    cl::Event e;
    q.enqueueNDRangeKernel(copy, cl::NullRange, cl::NDRange(bytes / 16), cl::NullRange, nullptr,
                           &e);
    e.wait();
    return ClContext::eventMs(e);
  };

  // Peak arithmetic: enough work-items to fill the device, iterations doubled until a launch is
  // long enough to time reliably.
  c.fmaWorkItems = std::max<size_t>(size_t(cl.info().computeUnits) * 2048, 16384);
  cl::Buffer sink(cl.context(), CL_MEM_WRITE_ONLY, c.fmaWorkItems * sizeof(float));
  cl::Kernel fma(program, "fma_chain");
  cl_uint iterationsArg = 0;
  KernelArgs(fma).add(sink).later(iterationsArg).add(0.999f).add(0.001f).done();
  auto launchFma = [&](int iterations) {
    fma.setArg(iterationsArg, iterations);
    cl::Event e;
    q.enqueueNDRangeKernel(fma, cl::NullRange, cl::NDRange(c.fmaWorkItems), cl::NullRange, nullptr,
                           &e);
    e.wait();
    return ClContext::eventMs(e);
  };

  launchCopy();  // warm-up
  int iterations = 64;
  double ms = launchFma(iterations);  // also the warm-up
  while (ms < o.minFmaMs && iterations < (1 << 24)) {
    iterations *= ms > 0 ? std::clamp(int(o.minFmaMs / ms * 1.2) + 1, 2, 64) : 64;
    ms = launchFma(iterations);
  }
  c.fmaIterations = iterations;
  const double flops = 2.0 * double(c.fmaWorkItems) * iterations * c.chains * c.vectorWidth;

  // Whole rounds (both kernels in each, so a burst of load elsewhere hits one round, not one
  // rate) until the best two rounds of each rate agree.
  std::vector<std::vector<double>> rates(2);  // GB/s, GFLOP/s per round
  while (!roundsSettled(rates, o.rounds)) {
    std::vector<double> copyMs, fmaMs;
    for (int i = 0; i < o.repeats; ++i) copyMs.push_back(launchCopy());
    for (int i = 0; i < o.repeats; ++i) fmaMs.push_back(launchFma(iterations));
    c.copyMs.insert(c.copyMs.end(), copyMs.begin(), copyMs.end());
    c.fmaMs.insert(c.fmaMs.end(), fmaMs.begin(), fmaMs.end());
    double copyMedian = summarize(copyMs).median, fmaMedian = summarize(fmaMs).median;
    rates[0].push_back(copyMedian > 0 ? 2.0 * double(bytes) / (copyMedian * 1e-3) / 1e9 : 0.0);
    rates[1].push_back(fmaMedian > 0 ? flops / (fmaMedian * 1e-3) / 1e9 : 0.0);
  }
  c.bandwidth = spreadOf(rates[0]);
  c.peak = spreadOf(rates[1]);
  c.bandwidthGBs = c.bandwidth.best;
  c.peakGflops = c.peak.best;
  c.agreement = o.rounds.agreement;
  c.settled = bestTwoAgree(rates[0], c.agreement) && bestTwoAgree(rates[1], c.agreement);
  return c;
}

double limitMs(const Calibration& c, double bytes, double flops) {
  if (c.bandwidthGBs <= 0 || c.peakGflops <= 0) return 0.0;
  double memory = bytes / (c.bandwidthGBs * 1e9) * 1e3;
  double arithmetic = flops / (c.peakGflops * 1e9) * 1e3;
  return std::max(memory, arithmetic);
}

}  // namespace ts
