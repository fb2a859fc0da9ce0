#pragma once
// Counter-based random numbers: every random number the renderer uses is a pure function of
// (frame, pixel, sample, dimension), so a pixel never depends on which thread rendered it, in
// which order tiles ran, or which process rendered the frame. No generator state is shared.
#include <cstdint>

namespace meshtour::rng {

/// SplitMix64's output function (Steele, Lea, Flood 2014): a bijective 64-bit mixer whose
/// output bits each depend on every input bit.
constexpr std::uint64_t mix64(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

/// The part of a sample's key shared by all samples of one pixel: computed once per pixel
/// rather than once per sample.
constexpr std::uint64_t pixel_key(std::uint64_t frame, std::uint64_t pixel) {
  return mix64(mix64(frame + 0x9e3779b97f4a7c15ULL) ^ pixel);
}

/// Two uniform numbers in [0, 1), 24 bits each (every float of [0, 1) with 24 bits is exactly
/// reachable): one mix per pair, half the cost of two separate numbers.
struct Uniform2 {
  float u, v;
};

/// The random stream of one camera sample: numbered pairs of uniform numbers.
class SampleStream {
public:
  constexpr SampleStream(std::uint64_t frame, std::uint64_t pixel, std::uint64_t sample)
      : SampleStream(pixel_key(frame, pixel), sample) {}
  /// From the pixel's key (see pixel_key): the same stream, without re-deriving the pixel part.
  constexpr SampleStream(std::uint64_t pixel_key_value, std::uint64_t sample) : key_(mix64(pixel_key_value ^ sample)) {}

  constexpr Uniform2 pair(std::uint32_t index) const {
    const std::uint64_t z = mix64(key_ + 0x9e3779b97f4a7c15ULL * (index + 1));
    // Through int32: a signed conversion is one instruction, an unsigned 64-bit one is several.
    return {static_cast<float>(static_cast<std::int32_t>(z >> 40)) * 0x1.0p-24f,
            static_cast<float>(static_cast<std::int32_t>((z >> 16) & 0xffffffULL)) * 0x1.0p-24f};
  }
  constexpr std::uint32_t bits(std::uint32_t index) const {
    return static_cast<std::uint32_t>(mix64(key_ ^ (0xd1b54a32d192ed03ULL * (index + 1))) >> 32);
  }

private:
  std::uint64_t key_;
};

/// Random numbers shared by all samples of one pixel (e.g. the shift decorrelating strata).
inline SampleStream pixel_stream(std::uint64_t frame, std::uint64_t pixel) { return {pixel_key(frame, pixel), ~0ULL}; }

}  // namespace meshtour::rng
