#pragma once
// An allocator for big, long-lived scratch buffers (the denoiser's planes, tens of MB): blocks of
// 2 MiB and more are aligned to 2 MiB and offered to the kernel's transparent huge pages
// (madvise), so that their first touch costs one page fault per 2 MiB instead of one per 4 KiB.
// On the virtual machines of CI and render farms a fault costs about 15 us: the denoiser's 80 MB
// of planes took 0.4-0.5 s to first touch, with huge pages a few tens of ms. Where the kernel's
// huge pages are off, this is a plain aligned allocation.
#include <sys/mman.h>

#include <cstddef>
#include <cstdlib>
#include <new>

namespace meshtour {

template <typename T>
struct HugePageAllocator {
  using value_type = T;
  static constexpr std::size_t kHugePage = std::size_t{2} << 20;

  HugePageAllocator() = default;
  template <typename U>
  HugePageAllocator(const HugePageAllocator<U>&) noexcept {}

  T* allocate(std::size_t n) {
    const std::size_t bytes = n * sizeof(T);
    if (bytes < kHugePage) {
      if (void* p = std::malloc(bytes ? bytes : 1)) return static_cast<T*>(p);
      throw std::bad_alloc();
    }
    const std::size_t rounded = (bytes + kHugePage - 1) / kHugePage * kHugePage;
    void* p = std::aligned_alloc(kHugePage, rounded);
    if (!p) throw std::bad_alloc();
    madvise(p, rounded, MADV_HUGEPAGE);  // advice only: ignored where huge pages are off
    return static_cast<T*>(p);
  }
  void deallocate(T* p, std::size_t) noexcept { std::free(p); }

  template <typename U>
  bool operator==(const HugePageAllocator<U>&) const noexcept { return true; }
};

}  // namespace meshtour
