#pragma once
// The reconstruction filter: a separable Blackman-Harris window, evaluated for 16 samples at once
// with polynomials, and the per-pixel sums that splat samples onto their neighbours.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <numbers>
#include <type_traits>

#include "tracer/simd.h"

namespace meshtour {

class ReconstructionFilter {
public:
  ReconstructionFilter() = default;
  /// `radius` in pixels: samples further than that from a pixel's centre (along x or y) do not
  /// reach it.
  explicit ReconstructionFilter(float radius) : radius_(radius) {}
  /// Pixels beyond a tile's edge that its samples can reach.
  int apron() const { return static_cast<int>(std::ceil(radius_)); }

  /// Pixels on either side of a sample's own pixel that it can reach: a sample at offset o in
  /// [0, 1) from its pixel's corner is |k + 0.5 - o| from the centre of the pixel k columns away.
  int reach() const { return static_cast<int>(std::ceil(radius_ - 0.5f)); }

  /// The weights along one axis of 16 samples at offsets `o` in [0, 1) inside their pixels:
  /// w[i] for the pixel i - reach() away (2 reach() + 1 of them).
  ///
  /// The 4-term Blackman-Harris window over [-radius, radius] (smooth, nearly Gaussian, ~0 at the
  /// radius, so truncating it leaves no visible ringing), evaluated directly: with
  /// z = 1/2 + d/(2 radius), cos(2 pi z) = sin(pi (d/radius - 1/2)), an odd polynomial on
  /// [-pi/2, pi/2], and the window's cos(4 pi z), cos(6 pi z) are Chebyshev polynomials of it.
  MESHTOUR_SIMD_INLINE void weights(simd::F16 o, simd::F16* w) const {
    constexpr float a0 = 0.35875f, a1 = 0.48829f, a2 = 0.14128f, a3 = 0.01168f;
    const int r = reach();
    for (int i = 0; i <= 2 * r; ++i) {
      const simd::F16 d = static_cast<float>(i - r) + 0.5f - o;
      const simd::F16 dist = simd::select(simd::lt(d, 0.0f), -d, d);
      const simd::F16 x = (dist * (1.0f / radius_) - 0.5f) * std::numbers::pi_v<float>;
      const simd::F16 x2 = x * x;
      const simd::F16 c = x * (1.0f + x2 * (-1.0f / 6 + x2 * (1.0f / 120 + x2 * (-1.0f / 5040 + x2 * (1.0f / 362880)))));
      const simd::F16 window = (a0 - a2) + c * ((3.0f * a3 - a1) + c * (2.0f * a2 + c * (-4.0f * a3)));
      w[i] = simd::select(simd::lt(dist, radius_), window, simd::broadcast(0.0f));
    }
  }

private:
  float radius_ = 1.5f;
};

/// Four floats in one SIMD register (GCC and Clang vector extension; plain SSE on x86-64).
using Float4 = float __attribute__((vector_size(16)));

/// Up to eight floats in one or two SIMD registers (GCC and Clang vector extension).
using Float8 = float __attribute__((vector_size(32)));

/// The filtered sums of the samples of one pixel over the (2 Reach + 1)^2 pixels around it. All
/// samples of a pixel reach the same pixels, so they are summed here and added to the tile's
/// buffer once per pixel instead of once per sample. Each sample carries `Values` floats (4:
/// premultiplied RGBA; 7: RGBA and, for the denoiser, the unshadowed light's RGB), summed as one
/// vector; the buffer holds Values + 1 floats per pixel (the values, then the weight).
template <int Reach, int Values>
class PixelSplat {
public:
  static constexpr int kTaps = 2 * Reach + 1;
  static constexpr int kWeightVectors = (kTaps + 3) / 4;
  static_assert(Values == 4 || Values == 7);
  using Vector = std::conditional_t<Values == 4, Float4, Float8>;

  /// A sample with values `value` (lanes past Values are ignored) and tap weights `wx`, `wy`
  /// (ReconstructionFilter::weights: wx[i] of lane `lane` is the weight of the pixel i - Reach
  /// columns away).
  void add(const simd::F16* wx_lanes, const simd::F16* wy_lanes, int lane, Vector value) {
    Vector weighted[kTaps];
    float weights[kWeightVectors * 4] = {};
    for (int i = 0; i < kTaps; ++i) {
      weights[i] = wx_lanes[i][lane];
      weighted[i] = weights[i] * value;
    }
    Float4 wx[kWeightVectors];  // the horizontal weights, four taps per register
    std::memcpy(wx, weights, sizeof wx);
    for (int j = 0; j < kTaps; ++j) {
      const float wy = wy_lanes[j][lane];
      for (int i = 0; i < kTaps; ++i) values_[j][i] += wy * weighted[i];
      for (int v = 0; v < kWeightVectors; ++v) weight_[j][v] += wy * wx[v];
    }
  }

  /// Adds the sums to `buffer` (rows of `stride` pixels, Values + 1 floats each), around the
  /// pixel at (x, y), which must be at least Reach pixels inside the buffer.
  void flush(float* buffer, int stride, int x, int y) const {
    for (int j = 0; j < kTaps; ++j) {
      float* dst = buffer + (static_cast<std::size_t>(y + j - Reach) * stride + (x - Reach)) * (Values + 1);
      for (int i = 0; i < kTaps; ++i, dst += Values + 1) {
        for (int c = 0; c < Values; ++c) dst[c] += values_[j][i][c];
        dst[Values] += weight_[j][i / 4][i % 4];
      }
    }
  }

private:
  Vector values_[kTaps][kTaps] = {};
  Float4 weight_[kTaps][kWeightVectors] = {};
};

}  // namespace meshtour
