#pragma once
// Internal to the G-buffer planes (src/gbuffer/) and the rasterizer that fills them: allocation of
// the large per-pixel planes (a 1080p G-buffer is ~140 MB).
// Fresh allocations of that size come straight from mmap, and first-touch page faults (4 KiB each)
// can cost more than rasterizing the frame; asking for transparent huge pages before the first
// touch cuts them ~500x. Advisory only (Linux madvise); elsewhere, or when refused, nothing
// changes.
#include <cstddef>
#include <cstdint>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace ts::plane_alloc {

inline void adviseHugePages(const void* data, size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  constexpr size_t kMin = size_t(4) << 20;  // only for buffers worth it
  constexpr uintptr_t kPage = 4096;
  if (bytes < kMin) return;
  uintptr_t begin = (reinterpret_cast<uintptr_t>(data) + kPage - 1) & ~(kPage - 1);
  uintptr_t end = (reinterpret_cast<uintptr_t>(data) + bytes) & ~(kPage - 1);
  if (end > begin) madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
#else
  (void)data;
  (void)bytes;
#endif
}

// v = n value-initialized (zero) elements; new storage is advised before it is touched.
template <typename T>
void assignZeroed(std::vector<T>& v, size_t n) {
  if (v.capacity() < n) {
    std::vector<T>().swap(v);
    v.reserve(n);
    adviseHugePages(v.data(), n * sizeof(T));
  }
  v.assign(n, T{});
}

// v = [first, last); new storage is advised before it is touched.
template <typename T, typename It>
void assignRange(std::vector<T>& v, It first, It last) {
  size_t n = size_t(last - first);
  if (v.capacity() < n) {
    std::vector<T>().swap(v);
    v.reserve(n);
    adviseHugePages(v.data(), n * sizeof(T));
  }
  v.assign(first, last);
}

}  // namespace ts::plane_alloc
