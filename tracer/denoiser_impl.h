#pragma once
// The denoiser's private parts, shared by denoiser.cpp and denoiser_pass.cpp (the a-trous pass,
// compiled once per instruction set like the tile kernel). Not public API.
#include <algorithm>
#include <cstddef>
#include <vector>

#include "core/huge_page_allocator.h"
#include "tracer/instruction_set.h"

namespace meshtour::denoise_detail {

constexpr int kPad = 16;  // the widest pass's step: neighbours never leave the planes
constexpr int kRowAlign = 16;  // rows are padded to the widest vector, so every copy sees one layout

// Planes of width + padding, rows of `stride` floats, kPad pixels of margin on every side, in
// memory the caller keeps between frames. The margins are zeroed (no normal: no weight); every
// pixel inside is written before it is read.
struct Planes {
  int width, height, stride, rows, count;
  float* data;
  Planes(int w, int h, int n, std::vector<float, HugePageAllocator<float>>& memory)
      : width(w), height(h), stride(((w + kRowAlign - 1) / kRowAlign) * kRowAlign + 2 * kPad), rows(h + 2 * kPad), count(n) {
    const std::size_t size = static_cast<std::size_t>(stride) * rows * n;
    if (memory.size() < size) memory.resize(size);
    data = memory.data();
    for (int k = 0; k < n; ++k) {
      float* p = plane(k);
      std::fill(p, p + static_cast<std::size_t>(stride) * kPad, 0.0f);
      std::fill(p + static_cast<std::size_t>(stride) * (kPad + h), p + static_cast<std::size_t>(stride) * rows, 0.0f);
      for (int y = 0; y < h; ++y) {
        float* row = p + static_cast<std::size_t>(stride) * (kPad + y);
        std::fill(row, row + kPad, 0.0f);
        std::fill(row + kPad + w, row + stride, 0.0f);
      }
    }
  }
  // Forced inline: the a-trous pass is compiled once per instruction set, and an out-of-line
  // copy compiled for AVX-512 could be the one the linker keeps for every caller.
  [[gnu::always_inline]] float* plane(int k) { return data + static_cast<std::size_t>(stride) * rows * k; }
  // The address of pixel (x, y) (image coordinates) of plane k.
  [[gnu::always_inline]] float* at(int k, int x, int y) { return plane(k) + static_cast<std::size_t>(y + kPad) * stride + (x + kPad); }
};


// The frame's planes: the visibility (RGB), alpha, and the variance of the pixel's mean.
enum Plane { kR, kG, kB, kA, kVar, kPlanesPerImage };
// The guide's planes: the visibility's luminance (plus alpha in transparent frames) and its variance.
enum LumaPlane { kLuma, kLumaVar, kLumaPlanes };
// kFlatWindow: 1 where every pixel of the fit's window (the square around it, inside the frame)
// has the pixel's own normal (the ground, a flat face): the normal's tilt is no feature there.
enum Guide { kNx, kNy, kNz, kDepth, kDepthGradient, kFlatWindow, kGuides };

// One a-trous pass with step `step` from `in` to `out` (both kLumaPlanes planes), one copy per
// instruction set (the same bits: per-pixel IEEE operations only, no FMA contraction).
using AtrousPass = void (*)(Planes& in, Planes& out, Planes& guides, int step);
template <InstructionSet>
void atrous_pass(Planes& in, Planes& out, Planes& guides, int step);

// The fit: per pixel, a weighted least-squares plane (value and slopes along x and y) through the
// unfiltered visibility `raw` (kPlanesPerImage planes) of the pixels within `radius`, weighted by
// normal, depth and the guide's luminance (`guide`, kLumaPlanes planes: the a-trous passes'
// output), written to `out`; one copy per instruction set.
using FitPass = void (*)(Planes& raw, Planes& guide, Planes& out, Planes& guides, int radius, bool transparent);
template <InstructionSet>
void fit_pass(Planes& raw, Planes& guide, Planes& out, Planes& guides, int radius, bool transparent);

// Each set's copy of the two passes is compiled in that set's copy of denoiser_pass.cpp only, as
// the tile kernel's (renderer_impl.h says why).
extern template void atrous_pass<InstructionSet::baseline>(Planes&, Planes&, Planes&, int);
extern template void atrous_pass<InstructionSet::x86_64_v3>(Planes&, Planes&, Planes&, int);
extern template void atrous_pass<InstructionSet::x86_64_v4>(Planes&, Planes&, Planes&, int);
extern template void fit_pass<InstructionSet::baseline>(Planes&, Planes&, Planes&, Planes&, int, bool);
extern template void fit_pass<InstructionSet::x86_64_v3>(Planes&, Planes&, Planes&, Planes&, int, bool);
extern template void fit_pass<InstructionSet::x86_64_v4>(Planes&, Planes&, Planes&, Planes&, int, bool);

}  // namespace meshtour::denoise_detail
