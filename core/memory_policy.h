#pragma once
// How the process keeps the memory it frees. A tour allocates and frees the same large buffers
// every frame (the Film's layers, the denoised frame, the 8-bit copy, the encoder's planes). glibc
// hands blocks above its mmap threshold back to the kernel on free, and the next frame then pays a
// page fault for every 4 KiB it touches: on the virtual machines of CI and render farms about
// 15 us each (80 MB first touched in 270-320 ms, rewritten in 5 ms), 55 ms for one 1280x720 RGBA
// float layer, a tenth of a frame. Kept in the heap, the next frame reuses them.
#include <malloc.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>

namespace meshtour {

/// Keeps freed blocks of up to 32 MiB (glibc's largest mmap threshold: a 1920x1080 float RGBA
/// layer) in the heap, and lets the heap keep up to 256 MiB free before trimming it. Called once
/// at start-up by the program and the benchmarks (a library must not change its host's allocator).
inline void keep_freed_frame_buffers() {
  mallopt(M_MMAP_THRESHOLD, 32 * 1024 * 1024);
  mallopt(M_TRIM_THRESHOLD, 256 * 1024 * 1024);
}

/// Re-executes the program once, first thing in main(), with glibc's tunable
/// `glibc.malloc.hugetlb=1` when the kernel gives transparent huge pages only to memory that asks
/// for them (`madvise`, Debian's default and this machine's): malloc then asks for every block it
/// maps or grows the heap by, and a big model's arrays (positions, the BVH, the sort keys of the
/// normals, the coverage model; gigabytes at 17.8M faces) are first touched one fault per 2 MiB
/// instead of one per 4 KiB. A fault costs about 15 us on the virtual machines this runs on:
/// one gigabyte of 4 KiB faults is 4 s. glibc reads its tunables only when a process starts, hence
/// the exec. Returns without doing anything when huge pages are `always` or `never`, when
/// GLIBC_TUNABLES already sets the tunable (either way: `glibc.malloc.hugetlb=0` turns this off),
/// or when the exec fails; the same process id runs on.
inline void reexec_with_transparent_huge_pages(char** argv) {
  std::ifstream mode_file("/sys/kernel/mm/transparent_hugepage/enabled");
  const std::string mode{std::istreambuf_iterator<char>(mode_file), std::istreambuf_iterator<char>()};
  if (mode.find("[madvise]") == std::string::npos) return;
  const char* current = std::getenv("GLIBC_TUNABLES");
  std::string tunables = current ? current : "";
  if (tunables.find("glibc.malloc.hugetlb") != std::string::npos) return;
  tunables += tunables.empty() ? "glibc.malloc.hugetlb=1" : ":glibc.malloc.hugetlb=1";
  if (setenv("GLIBC_TUNABLES", tunables.c_str(), 1) != 0) return;
  execv("/proc/self/exe", argv);
  // Still here: the exec failed (no /proc). Run on with 4 KiB pages, the tunable unset again so
  // that child processes do not believe it applies.
  if (current) setenv("GLIBC_TUNABLES", current, 1);
  else unsetenv("GLIBC_TUNABLES");
}

}  // namespace meshtour
