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

/// The random stream of one camera sample.
class SampleStream {
public:
  constexpr SampleStream(std::uint64_t frame, std::uint64_t pixel, std::uint64_t sample)
      : key_(mix64(mix64(mix64(frame + 0x9e3779b97f4a7c15ULL) ^ pixel) ^ sample)) {}
  /// Uniform in [0, 1), from the top 24 bits (every float in the range is exactly reachable).
  constexpr float uniform(std::uint32_t dimension) const {
    return static_cast<float>(mix64(key_ + 0x9e3779b97f4a7c15ULL * (dimension + 1)) >> 40) * 0x1.0p-24f;
  }
  constexpr std::uint32_t bits(std::uint32_t dimension) const {
    return static_cast<std::uint32_t>(mix64(key_ ^ (0xd1b54a32d192ed03ULL * (dimension + 1))) >> 32);
  }

private:
  std::uint64_t key_;
};

/// Random numbers shared by all samples of one pixel (e.g. the shift decorrelating strata).
inline SampleStream pixel_stream(std::uint64_t frame, std::uint64_t pixel) { return {frame, pixel, ~0ULL}; }

}  // namespace meshtour::rng
