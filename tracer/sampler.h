#pragma once
// Low-discrepancy sample numbers: Owen-scrambled Sobol points with hash-based scrambling (Burley
// 2020, "Practical Hash-based Owen Scrambling", JCGT 9(4)), 16 samples at a time.
//
// Every pair of dimensions of a camera sample (pixel position, light position, occlusion
// direction; the light choice uses one) takes the first two Sobol dimensions at a shuffled index:
// within a pixel the samples of one pair form a (0, m, 2)-net (every 1/spp-area box of the unit
// square that a power of two allows holds one sample), so the error of smooth integrands falls
// faster than 1/sqrt(spp), and the shuffle (an Owen scramble of the sample index, seeded per
// pixel and per pair) keeps the pairs independent of one another. The values are Owen scrambled
// too (seeded per pixel), so neighbouring pixels do not share a pattern.
//
// Integer operations only (shifts, masks, 32-bit multiplies), so every instruction set gives the
// same bits; the seeds are hashes of the pixel's key (random.h), so a sample depends only on
// (frame, pixel, sample index), never on threads or tile order.
#include <cstdint>

#include "tracer/simd.h"

namespace meshtour::sampler {

using simd::F16;
using simd::U16;

MESHTOUR_SIMD_INLINE U16 reverse_bits(U16 x) {
  x = ((x >> 1) & 0x55555555U) | ((x & 0x55555555U) << 1);
  x = ((x >> 2) & 0x33333333U) | ((x & 0x33333333U) << 2);
  x = ((x >> 4) & 0x0f0f0f0fU) | ((x & 0x0f0f0f0fU) << 4);
  x = ((x >> 8) & 0x00ff00ffU) | ((x & 0x00ff00ffU) << 8);
  return (x >> 16) | (x << 16);
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

/// A 32-bit fixed-point fraction as a float in (0, 1): its top 24 bits, at the centre of the bin.
MESHTOUR_SIMD_INLINE F16 to_unit(U16 bits) { return (simd::to_float(simd::as_int(bits >> 8)) + 0.5f) * 0x1.0p-24f; }

/// The seeds of one pair of dimensions of one pixel: index shuffle, first and second value.
struct PairSeeds {
  U16 index, x, y;
};
MESHTOUR_SIMD_INLINE PairSeeds pair_seeds(U16 pixel_key, std::uint32_t pair) {
  const std::uint32_t salt = 0x632be5abU * (pair + 1);
  return {simd::hash(pixel_key ^ salt), simd::hash(pixel_key ^ (salt + 0x85ebca6bU)), simd::hash(pixel_key ^ (salt + 0xc2b2ae35U))};
}

/// Sample `sample_reversed` (the sample's index within its pixel, bit-reversed) of one pair of
/// dimensions: two numbers in (0, 1).
MESHTOUR_SIMD_INLINE void pair(U16 sample_reversed, const PairSeeds& seeds, F16& u, F16& v) {
  // The shuffled index, bit-reversed, is Sobol's first dimension at that index.
  const U16 sobol0 = laine_karras(sample_reversed, seeds.index);
  const U16 index = reverse_bits(sobol0);
  u = to_unit(reverse_bits(laine_karras(index, seeds.x)));
  v = to_unit(reverse_bits(laine_karras(sobol1_reversed(index), seeds.y)));
}

/// One number in (0, 1): the first dimension of a pair.
MESHTOUR_SIMD_INLINE F16 single(U16 sample_reversed, const PairSeeds& seeds) {
  const U16 index = reverse_bits(laine_karras(sample_reversed, seeds.index));
  return to_unit(reverse_bits(laine_karras(index, seeds.x)));
}

}  // namespace meshtour::sampler
