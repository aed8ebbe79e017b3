#include "techniques/multisampled_gbuffer.h"

#include <algorithm>

#include "cl/kernel_args.h"
#include "cl/work_group.h"
#include "raster/sample_gbuffers.h"
#include "techniques/transparent_hybrid.h"
#include "util/error.h"

namespace ts {
namespace {

// A plane's bytes per pixel (0: absent, an empty plane).
cl_int bytesPerPixel(size_t planeBytes, size_t pixels) { return cl_int(planeBytes / pixels); }

// The planes of every sample one after another, in a buffer of at least one byte (OpenCL refuses
// empty ones).
template <typename T>
cl::Buffer stackedPlane(ClContext& cl, const std::vector<EncodedGBuffer>& samples,
                        std::vector<T> EncodedGBuffer::*plane, uint64_t& bytes) {
  const size_t each = (samples[0].*plane).size() * sizeof(T);
  cl::Buffer buffer(cl.context(), CL_MEM_READ_ONLY, std::max<size_t>(each * samples.size(), 1));
  for (size_t k = 0; k < samples.size() && each > 0; ++k)
    cl.queue().enqueueWriteBuffer(buffer, CL_FALSE, k * each, each, (samples[k].*plane).data());
  bytes += each * samples.size();
  return buffer;
}

}  // namespace

MultisampledGBuffer::MultisampledGBuffer(ClContext& cl, const cl::Program& program)
    : cl_(cl), edgeMask_(program, "msaa_edge_mask") {}

void MultisampledGBuffer::upload(const std::vector<EncodedGBuffer>& samples,
                                 const EncodedGBuffer& frame) {
  if (samples.size() < 2) throw Error("a multisampled G-buffer needs at least 2 samples");
  for (const EncodedGBuffer& s : samples)
    if (s.width != frame.width || s.height != frame.height || s.format != frame.format ||
        s.model != frame.model || s.depth.size() != samples[0].depth.size() ||
        s.normal.size() != samples[0].normal.size() ||
        s.diffuse.size() != samples[0].diffuse.size() ||
        s.specular.size() != samples[0].specular.size() ||
        s.emissive.size() != samples[0].emissive.size())
      throw Error("the per-sample G-buffers do not have the frame's layout and size");
  samples_ = int(samples.size());
  width_ = frame.width;
  height_ = frame.height;
  bytes_ = 0;
  depth_ = stackedPlane(cl_, samples, &EncodedGBuffer::depth, bytes_);
  normal_ = stackedPlane(cl_, samples, &EncodedGBuffer::normal, bytes_);
  diffuse_ = stackedPlane(cl_, samples, &EncodedGBuffer::diffuse, bytes_);
  specular_ = stackedPlane(cl_, samples, &EncodedGBuffer::specular, bytes_);
  emissive_ = stackedPlane(cl_, samples, &EncodedGBuffer::emissive, bytes_);
  cl_.queue().finish();  // the host planes may go once this returns
  const size_t pixels = size_t(width_) * size_t(height_);
  const EncodedGBuffer& s = samples[0];
  planeBytes_ = {{bytesPerPixel(s.normal.size(), pixels), bytesPerPixel(s.diffuse.size(), pixels),
                  bytesPerPixel(s.specular.size(), pixels),
                  bytesPerPixel(s.emissive.size(), pixels)}};
  if (!edges_() || edges_.getInfo<CL_MEM_SIZE>() < pixels)
    edges_ = cl::Buffer(cl_.context(), CL_MEM_READ_WRITE, pixels);
}

void MultisampledGBuffer::enqueueEdgeMask(FrameTimer& timer) {
  KernelArgs(edgeMask_)
      .add(depth_)
      .add(normal_)
      .add(diffuse_)
      .add(specular_)
      .add(emissive_)
      .add(planeBytes_)
      .add(cl_int(width_))
      .add(cl_int(height_))
      .add(cl_int(samples_))
      .add(edges_)
      .done();
  const GroupShape g = fitGroup(16, 16, groupLimit(cl_, edgeMask_));
  cl_.queue().enqueueNDRangeKernel(edgeMask_, cl::NullRange, g.global(width_, height_), g.local(),
                                   nullptr, timer.next("msaa_edges"));
}

std::vector<uint8_t> MultisampledGBuffer::readEdges() const {
  std::vector<uint8_t> edges(size_t(width_) * size_t(height_));
  cl_.queue().enqueueReadBuffer(edges_, CL_TRUE, 0, edges.size(), edges.data());
  return edges;
}

const std::vector<EncodedGBuffer>& multisampledPlanes(const DeviceFrame& frame,
                                                      const std::string& technique) {
  if (!frame.samples)
    throw Error(technique + ": this " + std::to_string(frame.forward->samples()) +
                "-sample frame carries no per-sample G-buffer (DeviceFrame::samples)");
  if (hasTransparentDraws(frame))
    throw Error(technique + ": --msaa with transparent draws is not done");
  return frame.samples->like(*frame.gbuffer);
}

WorkCounters multisampledTileWorkCounters(const TileGrid& grid, const std::vector<uint32_t>& counts,
                                          const std::vector<EncodedGBuffer>& samples,
                                          const std::vector<uint8_t>& edges,
                                          const DeviceFrame& frame) {
  WorkCounters c;
  const size_t pixels = size_t(grid.width) * size_t(grid.height);
  const uint64_t perSample = samples[0].bytesPerPixel();
  const uint64_t directional = uint64_t(frame.directionalCount());
  SampleShading shading;
  shading.samples = int(samples.size());
  uint64_t shaded = 0;  // samples shaded (with geometry), the directional lights' work
  for (int y = 0; y < grid.height; ++y)
    for (int x = 0; x < grid.width; ++x) {
      const size_t i = size_t(y) * size_t(grid.width) + size_t(x);
      const uint32_t list = counts[size_t(grid.tileOf(x, y))];
      const size_t last = edges[i] ? samples.size() : 1;
      if (edges[i]) {
        ++shading.pixelsShadedPerSample;
        c.lightingComputations += uint64_t(samples.size() - 1) * list;
      }
      for (size_t k = 0; k < last; ++k)
        if (samples[k].depth[i] > 0.0f) {
          c.evaluations += list;
          ++shaded;
          c.gbufferBytesRead += perSample - 4;  // the planes after the depth
        }
      c.gbufferBytesRead += 4 * (last - 1);  // the edges' further depths
    }
  c.listMin = counts.empty() ? 0 : UINT32_MAX;
  double sum = 0.0;
  for (int t = 0; t < grid.count(); ++t) {
    c.lightingComputations += uint64_t(grid.pixelsIn(t)) * counts[size_t(t)];
    c.listMin = std::min(c.listMin, counts[size_t(t)]);
    c.listMax = std::max(c.listMax, counts[size_t(t)]);
    sum += counts[size_t(t)];
  }
  c.listMean = counts.empty() ? 0.0 : sum / double(counts.size());
  // Depth bounds read every sample's depth, the edge mask every sample's planes (at most: it
  // stops at a pixel's first difference), shading sample 0's depth and the rest counted above.
  c.gbufferBytesRead +=
      4 * pixels * samples.size() + perSample * pixels * samples.size() + 4 * pixels;
  c.lightingComputations += shaded * directional;
  c.evaluations += shaded * directional;
  shading.gbufferBytes = perSample * pixels * samples.size();
  c.sampleShading = shading;
  return c;
}

}  // namespace ts
