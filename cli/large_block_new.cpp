// The program's global operator new: blocks of 4 MiB and more on transparent huge pages.
//
// A tour of a big scan first touches gigabytes of arrays (positions, triangles, the sort keys of
// the normals, the coverage model, the frame buffers). On the virtual machines of CI and render
// farms a page fault costs about 15 us, so a gigabyte in 4 KiB pages costs 4 s. Debian's kernels
// (and this machine's) give huge pages only to memory that asks for them with madvise, which glibc
// does not do by default, so big blocks are aligned to 2 MiB and ask: one fault per 2 MiB.
// Embree asks for its own BVH memory already. Where the kernel's huge pages are off, the advice is
// ignored and this is a plain aligned allocation. Every block is released by free(), as the
// library's operator delete does, so only operator new(size_t) is replaced (array and nothrow
// forms call it; the aligned forms use aligned_alloc already). Only in the executable: a library
// must not replace its host's allocator. Not under the sanitizers, which bring their own.
// (GCC says so with __SANITIZE_ADDRESS__, clang with __has_feature.)
#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define MESHTOUR_ADDRESS_SANITIZER 1
#endif
#endif
#if !defined(__SANITIZE_ADDRESS__) && !defined(MESHTOUR_ADDRESS_SANITIZER)
#include <sys/mman.h>

#include <cstdlib>
#include <new>

namespace {

constexpr std::size_t kHugePage = std::size_t{2} << 20;
// From 4 MiB, rounding up to whole huge pages wastes at most a third of a block.
constexpr std::size_t kLargeBlock = std::size_t{4} << 20;

void* allocate(std::size_t bytes) noexcept {
  if (bytes < kLargeBlock) return std::malloc(bytes ? bytes : 1);
  const std::size_t rounded = (bytes + kHugePage - 1) / kHugePage * kHugePage;
  void* p = std::aligned_alloc(kHugePage, rounded);
  if (p) madvise(p, rounded, MADV_HUGEPAGE);  // advice only
  return p;
}

}  // namespace

void* operator new(std::size_t bytes) {
  for (;;) {
    if (void* p = allocate(bytes)) return p;
    std::new_handler handler = std::get_new_handler();
    if (!handler) throw std::bad_alloc();
    handler();
  }
}
#endif
