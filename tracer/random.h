#pragma once
// Counter-based random numbers: every random number the renderer uses is a pure function of
// (frame, pixel, sample, dimension), so a pixel never depends on which thread rendered it, in
// which order tiles ran, or which process rendered the frame. No generator state is shared.
// Here: the key of a frame's block of pixels (64-bit, once per pixel); the sampler (sampler.h)
// seeds its scrambles with 32-bit hashes of it, 16 samples at a time.
#include <cstdint>

namespace meshtour::rng {

/// SplitMix64's output function (Steele, Lea, Flood 2014): a bijective 64-bit mixer whose
/// output bits each depend on every input bit.
constexpr std::uint64_t mix64(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

/// The part of a sample's key shared by all samples of one pixel (the sampler passes its block of
/// pixels: sampler::block_of): computed once per pixel rather than once per sample.
constexpr std::uint64_t pixel_key(std::uint64_t frame, std::uint64_t pixel) {
  return mix64(mix64(frame + 0x9e3779b97f4a7c15ULL) ^ pixel);
}

}  // namespace meshtour::rng
