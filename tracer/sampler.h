#pragma once
// Low-discrepancy sample numbers: Owen-scrambled Sobol points with hash-based scrambling (Burley
// 2020, "Practical Hash-based Owen Scrambling", JCGT 9(4)) in Z order (Ahmed and Wonka 2020,
// "Screen-space blue-noise diffusion of Monte Carlo sampling error via hierarchical ordering of
// pixels", as pbrt-v4's ZSobolSampler), 16 samples at a time.
//
// The pixels of a block of 256 x 256 share one sequence per pair of dimensions (pixel position,
// light choice and position, occlusion direction): pixel (x, y) takes the spp
// consecutive indices from its Morton code times spp (first_index). An aligned run of 2^k
// indices of a Sobol sequence is a (0, k, 2)-net, so a pixel's own samples are one (every
// 1/spp-area box of the unit square that a power of two allows holds one sample: the error of
// smooth integrands falls faster than 1/sqrt(spp)), and so are the samples of every aligned 2x2,
// 4x4, ... group of pixels: neighbouring pixels fill each other's gaps, their errors are
// negatively correlated (blue noise), and whatever averages neighbours (the reconstruction
// filter, the denoiser) cancels more of the error than it would of independent pixels'.
// Each pair shuffles the indices with its own nested (Owen) scramble, which maps aligned runs to
// aligned runs, so the pairs stay independent of one another; the values are Owen scrambled per
// block and pair.
//
// Integer operations only (shifts, masks, 32-bit multiplies), so every instruction set gives the
// same bits; the seeds are hashes of the block's key (random.h), so a sample depends only on
// (frame, pixel, sample index), never on threads, tile order or the farm split.
#include <cstdint>

#include "tracer/simd.h"

namespace meshtour::sampler {

using simd::F16;
using simd::U16;

MESHTOUR_SIMD_INLINE U16 reverse_bits(U16 x) {
#if defined(__AVX512BW__) || defined(__AVX2__)
  // Byte shuffles (vpshufb, within 128-bit lanes): each byte's two nibbles reversed by table
  // look-ups, then the four bytes of each word in reverse order. Integer operations: the same
  // bits as the shifts below (the baseline copy's), in a third of the instructions; the sampler
  // reverses ten words a packet. Tables list bytes from the highest, as _mm*_set_epi8 does.
#define MESHTOUR_NIBBLES_LOW 0xf0, 0x70, 0xb0, 0x30, 0xd0, 0x50, 0x90, 0x10, 0xe0, 0x60, 0xa0, 0x20, 0xc0, 0x40, 0x80, 0x00
#define MESHTOUR_NIBBLES_HIGH 0x0f, 0x07, 0x0b, 0x03, 0x0d, 0x05, 0x09, 0x01, 0x0e, 0x06, 0x0a, 0x02, 0x0c, 0x04, 0x08, 0x00
#define MESHTOUR_WORD_BYTES 12, 13, 14, 15, 8, 9, 10, 11, 4, 5, 6, 7, 0, 1, 2, 3
#if defined(__AVX512BW__)
  using Bytes = __m512i;
  const Bytes low = _mm512_set_epi8(MESHTOUR_NIBBLES_LOW, MESHTOUR_NIBBLES_LOW, MESHTOUR_NIBBLES_LOW, MESHTOUR_NIBBLES_LOW);
  const Bytes high = _mm512_set_epi8(MESHTOUR_NIBBLES_HIGH, MESHTOUR_NIBBLES_HIGH, MESHTOUR_NIBBLES_HIGH, MESHTOUR_NIBBLES_HIGH);
  const Bytes words = _mm512_set_epi8(MESHTOUR_WORD_BYTES, MESHTOUR_WORD_BYTES, MESHTOUR_WORD_BYTES, MESHTOUR_WORD_BYTES);
  const Bytes nibble = _mm512_set1_epi8(0x0f);
#else
  using Bytes = __m256i;
  const Bytes low = _mm256_set_epi8(MESHTOUR_NIBBLES_LOW, MESHTOUR_NIBBLES_LOW);
  const Bytes high = _mm256_set_epi8(MESHTOUR_NIBBLES_HIGH, MESHTOUR_NIBBLES_HIGH);
  const Bytes words = _mm256_set_epi8(MESHTOUR_WORD_BYTES, MESHTOUR_WORD_BYTES);
  const Bytes nibble = _mm256_set1_epi8(0x0f);
#endif
#undef MESHTOUR_NIBBLES_LOW
#undef MESHTOUR_NIBBLES_HIGH
#undef MESHTOUR_WORD_BYTES
  U16 r;
  for (int k = 0; k < U16::kPieces; ++k) {
    Bytes v;
    std::memcpy(&v, &x.p[k], sizeof v);
#if defined(__AVX512BW__)
    v = _mm512_or_si512(_mm512_shuffle_epi8(low, _mm512_and_si512(v, nibble)),
                        _mm512_shuffle_epi8(high, _mm512_and_si512(_mm512_srli_epi16(v, 4), nibble)));
    v = _mm512_shuffle_epi8(v, words);
#else
    v = _mm256_or_si256(_mm256_shuffle_epi8(low, _mm256_and_si256(v, nibble)),
                        _mm256_shuffle_epi8(high, _mm256_and_si256(_mm256_srli_epi16(v, 4), nibble)));
    v = _mm256_shuffle_epi8(v, words);
#endif
    std::memcpy(&r.p[k], &v, sizeof v);
  }
  return r;
#else
  x = ((x >> 1) & 0x55555555U) | ((x & 0x55555555U) << 1);
  x = ((x >> 2) & 0x33333333U) | ((x & 0x33333333U) << 2);
  x = ((x >> 4) & 0x0f0f0f0fU) | ((x & 0x0f0f0f0fU) << 4);
  x = ((x >> 8) & 0x00ff00ffU) | ((x & 0x00ff00ffU) << 8);
  return (x >> 16) | (x << 16);
#endif
}

/// A random permutation of 32-bit words in which bit k of the result depends only on bits 0..k
/// of `x` and the seed (N. Vegdahl's improvement of the Laine-Karras hash): on bit-reversed
/// numbers, that is an Owen scramble, a random nested permutation of the dyadic intervals.
MESHTOUR_SIMD_INLINE U16 laine_karras(U16 x, U16 seed) {
  x ^= x * 0x3d20adeaU;
  x += seed;
  x = x * ((seed >> 16) | 1U);
  x ^= x * 0x05526c56U;
  x ^= x * 0x53a22864U;
  return x;
}

/// Sobol's second dimension (primitive polynomial x + 1, whose generator matrix is Pascal's
/// triangle mod 2), bit-reversed: bit j of the result is the XOR of the bits b of `index` with
/// b & j == j (Lucas' theorem), a superset-sum transform in five shift-mask steps.
MESHTOUR_SIMD_INLINE U16 sobol1_reversed(U16 index) {
  index ^= (index >> 1) & 0x55555555U;
  index ^= (index >> 2) & 0x33333333U;
  index ^= (index >> 4) & 0x0f0f0f0fU;
  index ^= (index >> 8) & 0x00ff00ffU;
  index ^= (index >> 16) & 0x0000ffffU;
  return index;
}

/// The blocks of pixels that share a sequence: 2^kBlockBits square. 8 + 8 Morton bits and at
/// most 12 sample bits (--spp up to 4096) fit the 32-bit index.
constexpr int kBlockBits = 8;
/// The block's number (its key's pixel part: random.h).
constexpr std::uint64_t block_of(int x, int y) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(y) >> kBlockBits) << 32) | (static_cast<std::uint32_t>(x) >> kBlockBits);
}
constexpr std::uint32_t spread_bits(std::uint32_t v) {  // bit i of v to bit 2i (v < 256)
  v = (v | (v << 4)) & 0x0f0fU;
  v = (v | (v << 2)) & 0x3333U;
  v = (v | (v << 1)) & 0x5555U;
  return v;
}
/// Pixel (x, y)'s first index in its block's sequence: its Morton code within the block times
/// 2^log2_spp (2^log2_spp >= spp).
constexpr std::uint32_t first_index(int x, int y, int log2_spp) {
  const std::uint32_t mask = (1U << kBlockBits) - 1U;
  const std::uint32_t morton = spread_bits(static_cast<std::uint32_t>(x) & mask) | (spread_bits(static_cast<std::uint32_t>(y) & mask) << 1);
  return morton << log2_spp;
}

/// A 32-bit fixed-point fraction as a float in (0, 1): its top 24 bits, at the centre of the bin.
MESHTOUR_SIMD_INLINE F16 to_unit(U16 bits) { return (simd::to_float(simd::as_int(bits >> 8)) + 0.5f) * 0x1.0p-24f; }

/// The seeds of one pair of dimensions of one block: index shuffle, first and second value.
struct PairSeeds {
  U16 index, x, y;
};
MESHTOUR_SIMD_INLINE PairSeeds pair_seeds(U16 block_key, std::uint32_t pair) {
  const std::uint32_t salt = 0x632be5abU * (pair + 1);
  return {simd::hash(block_key ^ salt), simd::hash(block_key ^ (salt + 0x85ebca6bU)), simd::hash(block_key ^ (salt + 0xc2b2ae35U))};
}

/// Sample `sample_reversed` (the sample's index in its block's sequence, bit-reversed) of one pair of
/// dimensions: two numbers in (0, 1).
MESHTOUR_SIMD_INLINE void pair(U16 sample_reversed, const PairSeeds& seeds, F16& u, F16& v) {
  // The shuffled index, bit-reversed, is Sobol's first dimension at that index.
  const U16 sobol0 = laine_karras(sample_reversed, seeds.index);
  const U16 index = reverse_bits(sobol0);
  u = to_unit(reverse_bits(laine_karras(index, seeds.x)));
  v = to_unit(reverse_bits(laine_karras(sobol1_reversed(index), seeds.y)));
}

}  // namespace meshtour::sampler
