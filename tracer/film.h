#pragma once
// The Film: what a frame's samples become (after pbrt-v4's Film, which the sampler and the
// integrator feed and which knows nothing of rays). It owns
//  - the reconstruction filter: a separable Blackman-Harris window, evaluated for 16 samples at
//    once with polynomials;
//  - the accumulation: each tile's filtered sums, with an apron for the filter's reach, summed
//    into the frame afterwards in a fixed order, so that no pixel depends on thread timing;
//  - the layers: the beauty (premultiplied RGBA: RGB, alpha), the extra layers (albedo, normal,
//    depth; ExtraLayers) and the denoiser's guides (DenoiseGuides), their allocation, memory kept
//    between frames, and their write-out into the frame's Image.
// The integrator (tile_kernel.cpp) splats its samples onto a FilmTile; the renderer gathers the
// tiles into the frame (Film::gather) and hands the layers to the denoiser and to the Image.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <mutex>
#include <numbers>
#include <optional>
#include <type_traits>
#include <vector>

#include "tracer/denoiser.h"
#include "tracer/simd.h"
#include "tracer/tracer.h"

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
  MESHTOUR_SIMD_INLINE void add(const simd::F16* wx_lanes, const simd::F16* wy_lanes, int lane, Vector value) {
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
  MESHTOUR_SIMD_INLINE void flush(float* buffer, int stride, int x, int y) const {
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

// 16 x 16 pixels: at 16 spp a tile's rays (4096 camera rays, up to 8192 secondary) stay in the
// L2 cache, and a 1280x720 frame has 3600 tiles, plenty to balance two or more threads.
constexpr int kTileSize = 16;

/// Memory that outlives a frame, one entry per frame rendered at the same time: mapping and
/// page-faulting a 1280x720 frame's tile sums (29 MB) or the denoiser's memory (about 110 MB)
/// afresh for every frame cost more than using them.
template <typename T>
class SparePool {
public:
  /// A spare entry, or an empty one.
  T take() {
    std::lock_guard lock(mutex_);
    if (spares_.empty()) return T{};
    T spare = std::move(spares_.back());
    spares_.pop_back();
    return spare;
  }
  void give_back(T&& spare) {
    std::lock_guard lock(mutex_);
    spares_.push_back(std::move(spare));
  }

private:
  std::mutex mutex_;
  std::vector<T> spares_;
};

/// The Film's memory kept between frames (the renderer holds it).
struct FilmMemory {
  SparePool<std::vector<float>> tile_sums;
  SparePool<DenoiseGuides> guides;
};

/// One tile of the Film, as the integrator feeds it: its pixels, its filtered sums and the
/// layers' pixels (the tile's own; no other tile writes them). A view: the Film owns the memory.
struct FilmTile {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  ///< the tile's pixels: [x0, x1) x [y0, y1)
  int frame_width = 0;                 ///< the layers' rows, in pixels
  /// The filtered sums: stride x stride pixels, the tile's pixel (x0, y0) at (apron, apron), each
  /// pixel RGBA (premultiplied), then, with the denoiser's guides, the unshadowed light's RGB,
  /// then the filter's weight.
  int apron = 0, stride = 0;
  float* sums = nullptr;
  DenoiseGuides* guides = nullptr;  ///< the denoiser's guides, or null (no denoising)
  // The extra layers, or null: per pixel, the sums over its own samples (box, not the filter).
  float* albedo = nullptr;  ///< 3 per pixel, each sample's albedo / spp
  float* normal = nullptr;  ///< 3 per pixel, the samples' normals, normalised by Film::finish_tile
  float* depth = nullptr;   ///< 1 per pixel, the nearest sample's depth

  /// Pixel (x, y) of the frame in the tile's sums.
  MESHTOUR_SIMD_INLINE int sums_pixel(int x, int y) const { return (y - y0 + apron) * stride + (x - x0 + apron); }
  /// Pixel (x, y) of the frame in the layers.
  MESHTOUR_SIMD_INLINE int layer_pixel(int x, int y) const { return y * frame_width + x; }
};

/// A frame's Film: its tiles' sums and its layers, from allocation to write-out.
class Film {
public:
  /// A width x height film whose samples go through `filter`, with the `layers` asked for and
  /// the denoiser's guides when `denoiser_guides`. Memory comes from and goes back to `memory`.
  Film(int width, int height, int samples_per_pixel, const ReconstructionFilter& filter, const ExtraLayers& layers,
       bool denoiser_guides, FilmMemory& memory);
  ~Film();
  Film(const Film&) = delete;
  Film& operator=(const Film&) = delete;

  int tile_count() const { return tiles_x_ * tiles_y_; }
  /// Tile `index` (row by row), its sums and its pixels of the guides cleared while they are
  /// brought into this thread's cache. Safe to call for different tiles at once.
  FilmTile tile(int index);
  /// Once all of a tile's samples are in: its pixels of the normal layer become unit normals.
  void finish_tile(const FilmTile& tile);
  /// Each pixel gathers the tile sums that reach it, always in the same order, into the beauty and
  /// the guides' unshadowed light; the tile sums then go back to the memory.
  void gather();

  /// The beauty: premultiplied RGBA, width * height * 4 (after gather()).
  const std::vector<float>& beauty() const { return rgba_; }
  /// The denoiser's guides (after gather()), or null when they were not asked for.
  const DenoiseGuides* denoiser_guides() const { return guides_ ? &*guides_ : nullptr; }
  /// Moves the layers into `image` (size, rgba, albedo, normal, depth): the Film's last use.
  void write_to(Image& image);

private:
  int width_, height_;
  int tiles_x_, tiles_y_, apron_, stride_;
  int sum_floats_;             // floats per pixel of a tile's sums
  std::size_t tile_floats_;    // floats of one tile's sums
  FilmMemory& memory_;
  std::vector<float> tile_sums_;  // every tile's sums, tile after tile
  std::vector<float> rgba_, albedo_, normal_, depth_;
  std::optional<DenoiseGuides> guides_;
};

}  // namespace meshtour
