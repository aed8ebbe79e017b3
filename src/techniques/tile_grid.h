#pragma once
// Host-side helpers shared by the tile-based techniques: the screen grid, the per-frame timing of
// profiled commands, and the work counters / light assignment derived from per-tile lists.
#include <functional>
#include <string>
#include <vector>

#include "techniques/technique.h"

namespace ts {

struct TileGrid {
  int tileW = 16, tileH = 16;
  int tilesX = 0, tilesY = 0;
  int width = 0, height = 0;

  TileGrid() = default;
  TileGrid(int width, int height, int tileW, int tileH);
  int count() const { return tilesX * tilesY; }
  int tileOf(int x, int y) const { return (y / tileH) * tilesX + x / tileW; }
  // Pixels of tile t that lie on the screen (edge tiles are partial).
  int pixelsIn(int t) const;
};

// Collects profiled events of one frame and turns them into per-kernel times after the queue has
// finished (times of launches with the same name add up).
class FrameTimer {
 public:
  cl::Event* next(const std::string& name);  // pass to enqueue*, then wait
  std::vector<KernelTime> kernels() const;
  double totalMs() const;
  void clear() { events_.clear(); }

 private:
  std::vector<std::pair<std::string, cl::Event>> events_;
};

// Counters of a frame shaded from per-tile lists (tiled techniques). Lighting computations are
// the paper's: on-screen tile pixels x list length; evaluations: geometry pixels x list length;
// both plus the directional lights' work (addDirectionalWork).
WorkCounters tileWorkCounters(const TileGrid& grid, const std::vector<uint32_t>& counts,
                              const DeviceFrame& frame);

// Directional lights are evaluated at every geometry pixel by every technique: adds geometry
// pixels x directional lights to the lighting computations and the evaluations.
void addDirectionalWork(WorkCounters& c, uint64_t geometryPixels, const DeviceFrame& frame);

// Conservative NDC bounds of point or spot light i's volume (kernels/culling.h in float, as the
// kernels compute them; spotCulling: TechniqueConfig::spotCulling).
glm::vec4 lightNdcBounds(const ViewLights& lights, size_t i, const CameraIntrinsics& camera,
                         int spotCulling);

// The passes that build a binned light list (tiled, clustered), the paper's grid: count each
// light into its bins, exclusive scan of the counts into offsets (and the total), fill the list,
// sort each bin's list into light index order (the fill's order changes from run to run).
// `bin` is launched with one work-group of (up to) 64 per light; its argument `fillArg` selects
// count (0) or fill (1), its other arguments are set by the caller. `scan` gets (counts, bins,
// offsets, total) and one work-group of up to 256; `sort` (kernels/sort_bins.h) gets (counts,
// offsets, bins, list, capacity), one work-item per bin. Profiled as bin_count, scan, bin_fill,
// bin_sort.
struct BinningKernels {
  cl::Kernel& bin;
  cl_uint fillArg;
  cl::Kernel& scan;
  cl::Kernel& sort;
};
void enqueueBinning(ClContext& cl, const BinningKernels& kernels, int lightCount,
                    const cl::Buffer& counts, int bins, const cl::Buffer& offsets,
                    const cl::Buffer& total, const cl::Buffer& list, size_t capacity,
                    FrameTimer& timer);
// The same passes with the caller's own count and fill launches: `binPass(fill, name)` enqueues
// one pass (fill 0: count, 1: fill), its launches profiled under `name`; called only when there
// are lights.
using BinPass = std::function<void(int fill, const char* name)>;
void enqueueBinningPasses(ClContext& cl, const BinPass& binPass, cl::Kernel& scan, cl::Kernel& sort,
                          int lightCount, const cl::Buffer& counts, int bins,
                          const cl::Buffer& offsets, const cl::Buffer& total,
                          const cl::Buffer& list, size_t capacity, FrameTimer& timer);

// The light index list buffer of a binned technique, `capacity` entries: grows `list` to at least
// `entries` (contents are not kept: the list is rebuilt every frame).
void reserveList(ClContext& cl, cl::Buffer& list, size_t& capacity, size_t entries);

// Runs `enqueueFrame` (which clears the timer and enqueues the whole frame, its scan writing the
// list's total entries to `total`) until the list fits its buffer: a list is never truncated; when
// the frame needed more entries, the list grows and the frame runs again, and `notes` says so.
// Returns the total.
uint32_t runUntilListFits(ClContext& cl, cl::Buffer& list, size_t& capacity,
                          const cl::Buffer& total, const std::function<void()>& enqueueFrame,
                          const std::string& listName, std::vector<std::string>& notes);

// Upper bound of a frame's tile light list entries: the tiles of every light's screen rectangle
// (culling.h in float on the host), before any depth-range test. Sizing the list buffer with it
// saves the grow-and-rerun of a first frame.
size_t tileListBound(const TileGrid& grid, const DeviceFrame& frame, int spotCulling);

// Per-tile lists as a LightAssignment (pixelBin = the pixel's tile).
LightAssignment tileAssignment(const TileGrid& grid, std::vector<uint32_t> offsets,
                               std::vector<uint32_t> counts, std::vector<uint32_t> lights);

// Reads back an RGBA float image of the frame's size.
std::vector<glm::vec4> readImage(ClContext& cl, const cl::Buffer& image, const DeviceFrame& frame);

// The local buffer of a kernel shading in lanes (kernels/lanes.h): config.lanePlanes() floats per
// pixel slot, the work-group's items rounded up to whole vectors of config.lanes.
cl::LocalSpaceArg laneLocalMemory(const TechniqueConfig& config, size_t groupSize);

// Smallest power of two >= n, capped at `cap`.
size_t pow2AtLeast(size_t n, size_t cap);

}  // namespace ts
