#pragma once
// The reconstruction filter: a separable Blackman-Harris window, tabulated once so that splatting
// a sample costs a few table reads instead of cosines.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <numbers>

namespace meshtour {

class FilterTable {
public:
  FilterTable() = default;
  /// `radius` in pixels: samples further than that from a pixel's centre (along x or y) do not
  /// reach it.
  explicit FilterTable(float radius) : radius_(radius), to_index_(kEntries / radius) {
    // Blackman-Harris (4-term) window over [-radius, radius]: smooth, nearly Gaussian, and it
    // falls to ~0 at the radius, so truncating it leaves no visible ringing.
    constexpr double a0 = 0.35875, a1 = 0.48829, a2 = 0.14128, a3 = 0.01168;
    for (int i = 0; i <= kEntries; ++i) {
      const double x = 0.5 + 0.5 * static_cast<double>(i) / kEntries;  // distance 0 -> centre of the window
      const double w = 2.0 * std::numbers::pi * x;
      table_[i] = static_cast<float>(a0 - a1 * std::cos(w) + a2 * std::cos(2 * w) - a3 * std::cos(3 * w));
    }
  }
  /// Pixels beyond a tile's edge that its samples can reach.
  int apron() const { return static_cast<int>(std::ceil(radius_)); }

  /// |distance| must stay below radius + 1 (a sample's farthest tap is reach() + 0.5 away): the
  /// table is padded with zeros that far, so the lookup needs no range test.
  float weight(float distance) const {
    const float f = std::abs(distance) * to_index_;
    const int i = static_cast<int>(f);
    const float t = f - static_cast<float>(i);
    return table_[i] + t * (table_[i + 1] - table_[i]);
  }

  /// Pixels on either side of a sample's own pixel that it can reach: a sample at offset o in
  /// [0, 1) from its pixel's corner is |k + 0.5 - o| from the centre of the pixel k columns away.
  int reach() const { return static_cast<int>(std::ceil(radius_ - 0.5f)); }

private:
  static constexpr int kEntries = 256;  // per radius
  // radius + 1 <= 3 radii for every radius >= 0.5; one radius more to spare.
  static constexpr int kPadded = 4 * kEntries + 2;
  float radius_ = 1.5f;
  float to_index_ = kEntries / 1.5f;  // table entries per pixel of distance
  std::array<float, kPadded> table_{};  // zero beyond kEntries
};

/// Four floats in one SIMD register (GCC and Clang vector extension; plain SSE on x86-64).
using Float4 = float __attribute__((vector_size(16)));

/// The filtered sums of the samples of one pixel over the (2 Reach + 1)^2 pixels around it. All
/// samples of a pixel reach the same pixels, so they are summed here and added to the tile's
/// buffer once per pixel instead of once per sample; RGBA is summed four channels at a time.
template <int Reach>
class PixelSplat {
public:
  static constexpr int kTaps = 2 * Reach + 1;
  static constexpr int kWeightVectors = (kTaps + 3) / 4;

  /// A sample at offset (ox, oy) in [0, 1)^2 inside the pixel, with premultiplied RGBA `value`.
  void add(const FilterTable& filter, float ox, float oy, Float4 value) {
    Float4 weighted[kTaps];
    float weights[kWeightVectors * 4] = {};
    for (int i = 0; i < kTaps; ++i) {
      weights[i] = filter.weight(static_cast<float>(i - Reach) + 0.5f - ox);
      weighted[i] = weights[i] * value;
    }
    Float4 wx[kWeightVectors];  // the horizontal weights, four taps per register
    std::memcpy(wx, weights, sizeof wx);
    for (int j = 0; j < kTaps; ++j) {
      const float wy = filter.weight(static_cast<float>(j - Reach) + 0.5f - oy);
      for (int i = 0; i < kTaps; ++i) rgba_[j][i] += wy * weighted[i];
      for (int v = 0; v < kWeightVectors; ++v) weight_[j][v] += wy * wx[v];
    }
  }

  /// Adds the sums to `buffer` (rows of `stride` pixels, RGBA and weight each), around the pixel
  /// at (x, y), which must be at least Reach pixels inside the buffer.
  void flush(float* buffer, int stride, int x, int y) const {
    for (int j = 0; j < kTaps; ++j) {
      float* dst = buffer + (static_cast<std::size_t>(y + j - Reach) * stride + (x - Reach)) * 5;
      for (int i = 0; i < kTaps; ++i, dst += 5) {
        for (int c = 0; c < 4; ++c) dst[c] += rgba_[j][i][c];
        dst[4] += weight_[j][i / 4][i % 4];
      }
    }
  }

private:
  Float4 rgba_[kTaps][kTaps] = {};
  Float4 weight_[kTaps][kWeightVectors] = {};
};

}  // namespace meshtour
