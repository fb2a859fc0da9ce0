#pragma once
// How the process keeps the memory it frees. A tour allocates and frees the same large buffers
// every frame (the Film's layers, the denoised frame, the 8-bit copy, the encoder's planes). glibc
// hands blocks above its mmap threshold back to the kernel on free, and the next frame then pays a
// page fault for every 4 KiB it touches: on the virtual machines of CI and render farms about
// 15 us each (80 MB first touched in 270-320 ms, rewritten in 5 ms), 55 ms for one 1280x720 RGBA
// float layer, a tenth of a frame. Kept in the heap, the next frame reuses them.
#include <malloc.h>

namespace meshtour {

/// Keeps freed blocks of up to 32 MiB (glibc's largest mmap threshold: a 1920x1080 float RGBA
/// layer) in the heap, and lets the heap keep up to 256 MiB free before trimming it. Called once
/// at start-up by the program and the benchmarks (a library must not change its host's allocator).
inline void keep_freed_frame_buffers() {
  mallopt(M_MMAP_THRESHOLD, 32 * 1024 * 1024);
  mallopt(M_TRIM_THRESHOLD, 256 * 1024 * 1024);
}

}  // namespace meshtour
