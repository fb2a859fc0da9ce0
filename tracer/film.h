#pragma once
// The reconstruction filter: a separable Blackman-Harris window, tabulated once so that splatting
// a sample costs a few table reads instead of cosines.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
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

  float weight(float distance) const {
    const float f = std::abs(distance) * to_index_;
    if (!(f < kEntries)) return 0.0f;
    const int i = static_cast<int>(f);
    const float t = f - static_cast<float>(i);
    return table_[i] + t * (table_[i + 1] - table_[i]);
  }

  /// Pixels on either side of a sample's own pixel that it can reach: a sample at offset o in
  /// [0, 1) from its pixel's corner is |k + 0.5 - o| from the centre of the pixel k columns away.
  int reach() const { return static_cast<int>(std::ceil(radius_ - 0.5f)); }

private:
  static constexpr int kEntries = 256;
  float radius_ = 1.5f;
  float to_index_ = kEntries / 1.5f;  // table entries per pixel of distance
  std::array<float, kEntries + 1> table_{};
};

/// The filtered sums of the samples of one pixel over the (2 Reach + 1)^2 pixels around it. All
/// samples of a pixel reach the same pixels, so they are summed here (in registers, the loops
/// having fixed bounds) and added to the tile's buffer once per pixel instead of once per sample.
template <int Reach>
class PixelSplat {
public:
  static constexpr int kTaps = 2 * Reach + 1;

  /// A sample at offset (ox, oy) in [0, 1)^2 inside the pixel, with premultiplied RGBA `value`.
  void add(const FilterTable& filter, float ox, float oy, const float value[4]) {
    float wx[kTaps], wy[kTaps];
    for (int i = 0; i < kTaps; ++i) wx[i] = filter.weight(static_cast<float>(i - Reach) + 0.5f - ox);
    for (int j = 0; j < kTaps; ++j) wy[j] = filter.weight(static_cast<float>(j - Reach) + 0.5f - oy);
    for (int j = 0; j < kTaps; ++j)
      for (int i = 0; i < kTaps; ++i) {
        const float w = wx[i] * wy[j];
        float* dst = sums_[j][i];
        dst[0] += w * value[0];
        dst[1] += w * value[1];
        dst[2] += w * value[2];
        dst[3] += w * value[3];
        dst[4] += w;
      }
  }

  /// Adds the sums to `buffer` (rows of `stride` pixels, RGBA and weight each), around the pixel
  /// at (x, y), which must be at least Reach pixels inside the buffer.
  void flush(float* buffer, int stride, int x, int y) const {
    for (int j = 0; j < kTaps; ++j) {
      float* row = buffer + (static_cast<std::size_t>(y + j - Reach) * stride + (x - Reach)) * 5;
      for (int i = 0; i < kTaps; ++i)
        for (int c = 0; c < 5; ++c) row[i * 5 + c] += sums_[j][i][c];
    }
  }

private:
  float sums_[kTaps][kTaps][5] = {};
};

}  // namespace meshtour
