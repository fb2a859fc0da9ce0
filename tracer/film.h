#pragma once
// The reconstruction filter: a separable Blackman-Harris window, tabulated once so that splatting
// a sample costs a few table reads instead of cosines.
#include <Eigen/Core>
#include <array>
#include <cmath>
#include <numbers>
#include <vector>

namespace meshtour {

class FilterTable {
public:
  FilterTable() = default;
  /// `radius` in pixels: samples further than that from a pixel's centre (along x or y) do not
  /// reach it.
  explicit FilterTable(float radius) : radius_(radius) {
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
    const float f = std::abs(distance) / radius_ * kEntries;
    if (!(f < kEntries)) return 0.0f;
    const int i = static_cast<int>(f);
    const float t = f - static_cast<float>(i);
    return table_[i] + t * (table_[i + 1] - table_[i]);
  }

  /// Adds `value` (RGBA) weighted by the filter, and the weight itself, to every pixel of
  /// `sums` (rows of `stride` pixels, 5 floats each) that the sample at (x, y) reaches; (x, y)
  /// are continuous coordinates in that buffer, pixel centres at +0.5.
  void splat(float x, float y, const Eigen::Vector4f& value, float* sums, int stride) const {
    const int ix0 = static_cast<int>(std::ceil(x - 0.5f - radius_)), ix1 = static_cast<int>(std::floor(x - 0.5f + radius_));
    const int iy0 = static_cast<int>(std::ceil(y - 0.5f - radius_)), iy1 = static_cast<int>(std::floor(y - 0.5f + radius_));
    float wx[8];
    for (int ix = ix0; ix <= ix1 && ix - ix0 < 8; ++ix) wx[ix - ix0] = weight(static_cast<float>(ix) + 0.5f - x);
    for (int iy = iy0; iy <= iy1; ++iy) {
      const float wy = weight(static_cast<float>(iy) + 0.5f - y);
      if (wy <= 0.0f || iy < 0 || iy >= stride) continue;
      for (int ix = ix0; ix <= ix1 && ix - ix0 < 8; ++ix) {
        if (ix < 0 || ix >= stride) continue;
        const float w = wx[ix - ix0] * wy;
        if (w <= 0.0f) continue;
        float* dst = sums + (static_cast<std::size_t>(iy) * stride + ix) * 5;
        dst[0] += w * value[0];
        dst[1] += w * value[1];
        dst[2] += w * value[2];
        dst[3] += w * value[3];
        dst[4] += w;
      }
    }
  }

private:
  static constexpr int kEntries = 256;
  float radius_ = 1.5f;
  std::array<float, kEntries + 1> table_{};
};

}  // namespace meshtour
