#include "techniques/tile_grid.h"

#include <algorithm>

#include "cl/kernel_args.h"
#include "cl/work_group.h"
#include "shading/shading_cpu.h"

namespace ts {

TileGrid::TileGrid(int w, int h, int tw, int th)
    : tileW(tw),
      tileH(th),
      tilesX((w + tw - 1) / tw),
      tilesY((h + th - 1) / th),
      width(w),
      height(h) {}

int TileGrid::pixelsIn(int t) const {
  int tx = t % tilesX, ty = t / tilesX;
  int w = std::min(tileW, width - tx * tileW), h = std::min(tileH, height - ty * tileH);
  return w * h;
}

cl::Event* FrameTimer::next(const std::string& name) {
  events_.emplace_back(name, cl::Event());
  return &events_.back().second;
}

std::vector<KernelTime> FrameTimer::kernels() const {
  std::vector<KernelTime> out;
  for (const auto& [name, event] : events_) {
    // By value: clang before 16 cannot capture a structured binding.
    auto it = std::find_if(out.begin(), out.end(),
                           [&, n = name](const KernelTime& k) { return k.name == n; });
    if (it == out.end()) {
      out.push_back({name, 0.0, 0});
      it = out.end() - 1;
    }
    it->ms += ClContext::eventMs(event);
    it->launches += 1;
  }
  return out;
}

double FrameTimer::totalMs() const {
  double sum = 0.0;
  for (const auto& [name, event] : events_) sum += ClContext::eventMs(event);
  return sum;
}

WorkCounters tileWorkCounters(const TileGrid& grid, const std::vector<uint32_t>& counts,
                              const DeviceFrame& frame) {
  WorkCounters c;
  const auto& depth = frame.gbuffer->depth;
  size_t geometry = 0;
  for (int y = 0; y < grid.height; ++y)
    for (int x = 0; x < grid.width; ++x)
      if (depth[size_t(y) * grid.width + x] > 0.0f) {
        c.evaluations += counts[grid.tileOf(x, y)];
        ++geometry;
      }
  c.listMin = counts.empty() ? 0 : UINT32_MAX;
  double sum = 0.0;
  for (int t = 0; t < grid.count(); ++t) {
    c.lightingComputations += uint64_t(grid.pixelsIn(t)) * counts[t];
    c.listMin = std::min(c.listMin, counts[t]);
    c.listMax = std::max(c.listMax, counts[t]);
    sum += counts[t];
  }
  c.listMean = counts.empty() ? 0.0 : sum / double(counts.size());
  // Depth is read by the depth-bounds pass and again by shading; the other planes once per
  // geometry pixel (background pixels stop after the depth read).
  size_t pixels = size_t(grid.width) * grid.height;
  c.gbufferBytesRead = 2 * 4 * pixels + geometry * (frame.gbuffer->bytesPerPixel() - 4);
  addDirectionalWork(c, geometry, frame);
  return c;
}

void addDirectionalWork(WorkCounters& c, uint64_t geometryPixels, const DeviceFrame& frame) {
  uint64_t work = geometryPixels * uint64_t(frame.directionalCount());
  c.lightingComputations += work;
  c.evaluations += work;
}

void enqueueBinning(ClContext& cl, const BinningKernels& kernels, int lightCount,
                    const cl::Buffer& counts, int bins, const cl::Buffer& offsets,
                    const cl::Buffer& total, const cl::Buffer& list, size_t capacity,
                    FrameTimer& timer) {
  cl::Kernel& bin = kernels.bin;
  const size_t group = fitGroup(64, 1, groupLimit(cl, bin)).x;  // work-items sharing a light's bins
  auto binPass = [&](int fill, const char* name) {
    bin.setArg(kernels.fillArg, fill);
    cl.queue().enqueueNDRangeKernel(bin, cl::NullRange, cl::NDRange(size_t(lightCount) * group),
                                    cl::NDRange(group), nullptr, timer.next(name));
  };
  enqueueBinningPasses(cl, binPass, kernels.scan, kernels.sort, lightCount, counts, bins, offsets,
                       total, list, capacity, timer);
}

void enqueueBinningPasses(ClContext& cl, const BinPass& binPass, cl::Kernel& scan, cl::Kernel& sort,
                          int lightCount, const cl::Buffer& counts, int bins,
                          const cl::Buffer& offsets, const cl::Buffer& total,
                          const cl::Buffer& list, size_t capacity, FrameTimer& timer) {
  cl::CommandQueue& queue = cl.queue();
  const size_t scanGroup = powerOfTwoGroup(256, groupLimit(cl, scan));
  if (lightCount > 0) binPass(0, "bin_count");  // OpenCL refuses an empty NDRange
  KernelArgs(scan).add(counts).add(bins).add(offsets).add(total).done();
  queue.enqueueNDRangeKernel(scan, cl::NullRange, cl::NDRange(scanGroup), cl::NDRange(scanGroup),
                             nullptr, timer.next("scan"));
  if (lightCount > 0) binPass(1, "bin_fill");
  if (lightCount == 0 || bins == 0) return;  // every list is empty
  KernelArgs(sort).add(counts).add(offsets).add(bins).add(list).add(cl_uint(capacity)).done();
  const size_t sortGroup = fitGroup(64, 1, groupLimit(cl, sort)).x;
  queue.enqueueNDRangeKernel(sort, cl::NullRange, cl::NDRange(roundUp(size_t(bins), sortGroup)),
                             cl::NDRange(sortGroup), nullptr, timer.next("bin_sort"));
}

void reserveList(ClContext& cl, cl::Buffer& list, size_t& capacity, size_t entries) {
  if (entries <= capacity && list()) return;
  capacity = std::max(entries, capacity);
  list =
      cl::Buffer(cl.context(), CL_MEM_READ_WRITE, std::max<size_t>(capacity, 1) * sizeof(uint32_t));
}

uint32_t runUntilListFits(ClContext& cl, cl::Buffer& list, size_t& capacity,
                          const cl::Buffer& total, const std::function<void()>& enqueueFrame,
                          const std::string& listName, std::vector<std::string>& notes) {
  for (;;) {
    enqueueFrame();
    uint32_t entries = 0;
    cl.queue().enqueueReadBuffer(total, CL_TRUE, 0, sizeof(uint32_t), &entries);
    if (entries <= capacity) return entries;
    // The count pass knew the exact total, so one re-run suffices; a quarter extra spares the
    // next frames another.
    reserveList(cl, list, capacity, size_t(entries) + entries / 4);
    notes.push_back(listName + " light list grown to " + std::to_string(capacity) +
                    " entries; frame re-run");
  }
}

glm::vec4 lightNdcBounds(const ViewLights& lights, size_t i, const CameraIntrinsics& camera,
                         int spotCulling) {
  shading_f::ts_light_volume v =
      shading_f::ts_make_light_volume(lights.positionRange[i], lights.spot[i], spotCulling);
  return shading_f::ts_light_ndc_bounds(&v, camera.znear, camera.tanHalfFovX, camera.tanHalfFovY);
}

size_t tileListBound(const TileGrid& grid, const DeviceFrame& frame, int spotCulling) {
  const CameraIntrinsics& cam = frame.camera;
  size_t bound = 0;
  for (size_t i = 0; i < frame.lights->size(); ++i) {
    glm::vec4 b = lightNdcBounds(*frame.lights, i, cam, spotCulling);
    int x0, y0, x1, y1;
    if (shading_f::ts_ndc_bounds_to_tiles(b, grid.width, grid.height, grid.tileW, grid.tileH, &x0,
                                          &y0, &x1, &y1))
      bound += size_t(x1 - x0 + 1) * size_t(y1 - y0 + 1);
  }
  return bound;
}

LightAssignment tileAssignment(const TileGrid& grid, std::vector<uint32_t> offsets,
                               std::vector<uint32_t> counts, std::vector<uint32_t> lights) {
  LightAssignment a;
  a.binOffset = std::move(offsets);
  a.binCount = std::move(counts);
  a.binLights = std::move(lights);
  a.pixelBin.resize(size_t(grid.width) * grid.height);
  for (int y = 0; y < grid.height; ++y)
    for (int x = 0; x < grid.width; ++x) a.pixelBin[size_t(y) * grid.width + x] = grid.tileOf(x, y);
  return a;
}

std::vector<glm::vec4> readImage(ClContext& cl, const cl::Buffer& image, const DeviceFrame& frame) {
  std::vector<glm::vec4> out(size_t(frame.width()) * frame.height());
  cl.queue().enqueueReadBuffer(image, CL_TRUE, 0, out.size() * sizeof(glm::vec4), out.data());
  return out;
}

cl::LocalSpaceArg laneLocalMemory(const TechniqueConfig& config, size_t groupSize) {
  size_t slots = roundUp(groupSize, size_t(std::max(config.lanes, 1)));
  return cl::Local(size_t(config.lanePlanes()) * slots * sizeof(float));
}

size_t pow2AtLeast(size_t n, size_t cap) {
  size_t p = 1;
  while (p < n && p < cap) p <<= 1;
  return std::min(p, cap);
}

}  // namespace ts
