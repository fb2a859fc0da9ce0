// The denoiser's a-trous pass and fit (denoiser_impl.h), compiled once per instruction set
// (instruction_set.h: each copy specialises the two templates for its set); all copies give the same bits,
// because every pixel goes through the same IEEE operations (add, multiply, divide, square root,
// compare, select; no FMA contraction: -ffp-contract=off) whatever the vector width.
#include <tbb/parallel_for.h>

#include <cstring>
#include <type_traits>
#include <vector>

#include "tracer/denoiser_impl.h"
#include "tracer/simd.h"


namespace meshtour::denoise_detail {
namespace {

// kWidth pixels at once, the target's native vector (GCC vector extension).
constexpr int kWidth = simd::kNativeLanes;
using Lanes = float __attribute__((vector_size(4 * kWidth)));
using Mask = int __attribute__((vector_size(4 * kWidth)));

// Edge-stopping settings (SVGF's, tuned on the benchmark frames, bench/denoise_quality.cpp).
// (SVGF's luminance sigma is 4; 2 measured better here, because the variance estimate is of a
// pixel's own box mean of independent samples, while the beauty is a wider filter's mean of
// stratified ones, whose error is smaller.)
constexpr float kDepthSigma = 1.0f;   // depth difference in units of the local depth gradient
constexpr float kLumaSigma = 4.0f;    // luminance difference in standard deviations
constexpr int kNormalPowerLog2 = 6;   // weight max(0, n.n')^64
// The fit's luminance weight: a Gaussian of the guide's luminance difference in units of
// kFitLumaSigma standard deviations of the guide plus kFitLumaFloor of its luminance (the guide,
// the a-trous passes' output, is nearly noise-free, so its own deviation alone would stop at
// every leftover ripple). Measured on the benchmark frames (bench/denoise_quality.cpp).
constexpr float kFitLumaSigma = 2.0f;
constexpr float kFitLumaFloor = 0.015f;
constexpr float kFitRidge = 1e-3f;         // slope damping, relative to the sum of weights
constexpr float kFitNormalRidge = 1e-3f;   // damping of the normal-tilt coefficients, likewise
// The fit's normal weight, exp(-32 (1 - n.n')): looser than the a-trous pass's (n.n')^64, because
// the fit models the visibility's change with the normal (a feature) instead of only stopping at it.
constexpr float kFitNormalScale = 32.0f;

Lanes load(const float* p) {
  Lanes v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
void store(float* p, Lanes v) { std::memcpy(p, &v, sizeof v); }
Lanes splat(float v) { return Lanes{} + v; }
Lanes abs_lanes(Lanes v) { return v < 0.0f ? -v : v; }  // lane-wise select
Lanes max_lanes(Lanes a, Lanes b) { return a > b ? a : b; }
Lanes sqrt_lanes(Lanes v) {  // IEEE square roots (sqrtps / vsqrtps with -fno-math-errno)
  Lanes r;
  for (int i = 0; i < kWidth; ++i) r[i] = __builtin_sqrtf(v[i]);
  return r;
}
// exp(-x) for x >= 0 by (1 + x/8)^-8: smooth, 1 at 0, falling like exp(-x) near 0 with a
// slightly longer tail; plain arithmetic, so every CPU gives the same bits.
Lanes falloff(Lanes x) {
  Lanes t = 1.0f + x * 0.125f;
  t = t * t;
  t = t * t;
  t = t * t;
  return 1.0f / t;
}
// The fit's falloff: (1 - x/8)^8 for x < 8, else 0: 1 at 0 and close to exp(-x) near 0, with a
// shorter tail than falloff (the fit's wide window must not let far, different pixels in) and
// no division, which would dominate the fit's cost at 81 taps a pixel.
Lanes falloff_compact(Lanes x) {
  Lanes t = max_lanes(1.0f - x * 0.125f, Lanes{});
  t = t * t;
  t = t * t;
  return t * t;
}

}  // namespace

// One a-trous pass with step `step` from `in` to `out` (both kLumaPlanes planes: the visibility's
// luminance and its variance). The planes' addresses are taken once per row (restrict: the
// stores cannot change them), and groups of pixels with nothing to filter are copied.
template <InstructionSet Set>
void atrous_pass(Planes& in, Planes& out, Planes& guides, int step) {
  static_assert(Set == kCompiledFor, "atrous_pass instantiated outside its instruction set's copy of denoiser_pass.cpp");
  const int width = in.width, height = in.height;
  const std::ptrdiff_t stride = in.stride;
  constexpr float h[3] = {0.25f, 0.5f, 0.25f};
  tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& range) {
    for (int y = range.begin(); y != range.end(); ++y) {
      const float* __restrict src_luma = in.at(kLuma, 0, y);
      const float* __restrict src_var = in.at(kLumaVar, 0, y);
      float* __restrict dst_luma = out.at(kLuma, 0, y);
      float* __restrict dst_var = out.at(kLumaVar, 0, y);
      const float* __restrict gd[kGuides];
      for (int k = 0; k < kGuides; ++k) gd[k] = guides.at(k, 0, y);
      for (int x = 0; x < width; x += kWidth) {
        const Lanes nx = load(gd[kNx] + x), ny = load(gd[kNy] + x), nz = load(gd[kNz] + x);
        const Lanes luma = load(src_luma + x), var = load(src_var + x);
        // Nothing to filter: no surface (sky, padding), or no noise (the lit ground far from the
        // model, whose rays are known unblocked and not traced; the variance is prefiltered, so
        // this is no pixel next to a noisy one).
        const Mask busy = ((nx != 0.0f) | (ny != 0.0f) | (nz != 0.0f)) & (var > 1e-12f);
        int any_busy = 0;
        for (int i = 0; i < kWidth; ++i) any_busy |= busy[i];
        if (!any_busy) {
          store(dst_luma + x, luma);
          store(dst_var + x, var);
          continue;
        }
        const Lanes z = load(gd[kDepth] + x), z_grad = load(gd[kDepthGradient] + x);
        const Lanes inv_z = 1.0f / (kDepthSigma * z_grad * static_cast<float>(step) + 1e-3f * z + 1e-30f);
        const Lanes inv_l = 1.0f / (kLumaSigma * sqrt_lanes(var) + 1e-4f);
        Lanes sum_luma{}, sum_var{}, sum_w{};
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const std::ptrdiff_t o = x + (dy * stride + dx) * step;
            const Lanes q_luma = load(src_luma + o);
            Lanes cos_n = max_lanes(nx * load(gd[kNx] + o) + ny * load(gd[kNy] + o) + nz * load(gd[kNz] + o), Lanes{});
            for (int i = 0; i < kNormalPowerLog2; ++i) cos_n = cos_n * cos_n;
            const float inv_distance = dx != 0 && dy != 0 ? 0.5f : 1.0f;
            const Lanes exponent = abs_lanes(z - load(gd[kDepth] + o)) * inv_z * inv_distance + abs_lanes(luma - q_luma) * inv_l;
            const Lanes w = (h[dx + 1] * h[dy + 1]) * cos_n * falloff(exponent);
            sum_luma += w * q_luma;
            sum_var += (w * w) * load(src_var + o);
            sum_w += w;
          }
        // Pixels with nothing to filter stay as they are, whichever group of pixels they share a
        // vector with (so every vector width gives the same bits).
        const Mask filtered = busy & (sum_w > 0.0f);
        const Lanes safe_w = filtered ? sum_w : splat(1.0f);
        store(dst_luma + x, filtered ? sum_luma / safe_w : luma);
        store(dst_var + x, filtered ? sum_var / (safe_w * safe_w) : var);
      }
    }
  });
}

// The fit (denoiser_impl.h): per pixel, a weighted least-squares fit of the raw visibility of the
// pixels in a disc of `radius` by five features: 1, the offset along x and y (a plane) and the
// tilt of the neighbour's normal against the pixel's own, in two directions of its tangent plane;
// its value at the pixel (offset 0, tilt 0) is the result. A weighted mean (zero order) of a
// sloped signal is pulled towards the side with more weight, which blurs every gradient of a
// soft shadow or of occlusion; the plane has no such bias. The normal's tilt carries the
// occlusion of small bumps (fur, carving, cloth), which changes with the normal faster than with
// the position: as a feature rather than only a weight it lets neighbours on the other flank of a
// bump count without flattening the bump (after NFOR, Bitterli et al. 2016, which regresses on
// the renderer's features). Sums in a fixed order for every lane.
template <InstructionSet Set>
void fit_pass(Planes& raw, Planes& guide, Planes& out, Planes& guides, int radius, bool transparent) {
  static_assert(Set == kCompiledFor, "fit_pass instantiated outside its instruction set's copy of denoiser_pass.cpp");
  const int width = raw.width, height = raw.height;
  const std::ptrdiff_t stride = raw.stride;
  const float inv_radius = 1.0f / static_cast<float>(radius);
  // The window's taps, once: a disc rather than a square (the corners add little), each with its
  // offset in the planes, its position in units of the radius, and 1 / its distance.
  struct Tap {
    std::ptrdiff_t offset;
    float fx, fy, inv_distance;
  };
  std::vector<Tap> taps;
  for (int dy = -radius; dy <= radius; ++dy)
    for (int dx = -radius; dx <= radius; ++dx)
      if (dx * dx + dy * dy <= radius * radius + radius)
        taps.push_back({dy * stride + dx, static_cast<float>(dx) * inv_radius, static_cast<float>(dy) * inv_radius,
                        dx == 0 && dy == 0 ? 1.0f : 1.0f / __builtin_sqrtf(static_cast<float>(dx * dx + dy * dy))});
  constexpr int kFeatures = 5, kPlaneFeatures = 3;
  // The rows, with the number of channels known to the compiler (the sums stay in registers).
  const auto fit_rows = [&](auto channel_count) {
  constexpr int channels = decltype(channel_count)::value;
  tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& range) {
    std::vector<Lanes> weighted(taps.size() * 3);  // per tap: weight and weighted tilts
    for (int y = range.begin(); y != range.end(); ++y) {
      const float* __restrict src[kPlanesPerImage];
      float* __restrict dst[kPlanesPerImage];
      const float* __restrict gd[kGuides];
      for (int k = 0; k < kPlanesPerImage; ++k) src[k] = raw.at(k, 0, y), dst[k] = out.at(k, 0, y);
      for (int k = 0; k < kGuides; ++k) gd[k] = guides.at(k, 0, y);
      const float* __restrict guide_luma = guide.at(kLuma, 0, y);
      const float* __restrict guide_var = guide.at(kLumaVar, 0, y);
      for (int x = 0; x < width; x += kWidth) {
        const Lanes nx = load(gd[kNx] + x), ny = load(gd[kNy] + x), nz = load(gd[kNz] + x);
        Lanes c[kPlanesPerImage];  // the pixels' own, unfiltered values
        for (int k = 0; k < kPlanesPerImage; ++k) c[k] = load(src[k] + x);
        const Lanes var = load(guide_var + x);
        const Mask busy = ((nx != 0.0f) | (ny != 0.0f) | (nz != 0.0f)) & (var > 1e-12f);
        int any_busy = 0;
        for (int i = 0; i < kWidth; ++i) any_busy |= busy[i];
        if (!any_busy) {
          for (int k = 0; k < kVar; ++k) store(dst[k] + x, c[k]);  // the variance plane of the result is not read
          continue;
        }
        const Lanes z = load(gd[kDepth] + x), z_grad = load(gd[kDepthGradient] + x);
        const Lanes luma = load(guide_luma + x);
        // Depth differences in units of the local depth gradient times the distance (a plane's
        // rise), and a relative tolerance for flat-on views.
        const Lanes inv_z = 1.0f / (kDepthSigma * z_grad + 1e-3f * z + 1e-30f);
        const Lanes inv_l = 1.0f / (kFitLumaSigma * sqrt_lanes(var) + kFitLumaFloor * max_lanes(luma, splat(0.05f)));
        // Two directions of the pixel's tangent plane (Duff et al. 2017, "Building an orthonormal
        // basis, revisited": no branch, one division), along which a neighbour's normal tilts.
        const Lanes sign = nz >= 0.0f ? splat(1.0f) : splat(-1.0f);
        const Lanes inv = -1.0f / (sign + nz), cross = nx * ny * inv;
        const Lanes t1x = 1.0f + sign * nx * nx * inv, t1y = sign * cross, t1z = -sign * nx;
        const Lanes t2x = cross, t2y = sign + ny * ny * inv, t2z = -ny;
        // Pixels whose window is one normal (the ground, a flat face; kFlatWindow) fit the plane
        // alone: the tilts are no feature there. The plane's normal equations are the first
        // three rows of the full ones, summed in the same order, and its weights are the same
        // (the same normal term), so such a pixel gets the same bits whether or not its
        // neighbours in the vector are flat too: a group of only flat pixels skips the normals.
        const Mask flat = busy & (load(gd[kFlatWindow] + x) != 0.0f);
        int all_flat = 1, any_flat = 0;
        for (int i = 0; i < kWidth; ++i) all_flat &= (busy[i] == 0) | (flat[i] != 0), any_flat |= flat[i] != 0;
        Lanes m[kFeatures][kFeatures] = {};  // the normal equations' lower triangle (m[i][j], j <= i)
        // A tap's weight, given its normal term: one expression for both sweeps below, so that a
        // flat pixel's weights are the same bits in either.
        const auto tap_weight = [&](const Tap& tap, std::ptrdiff_t o, Lanes normal_term) __attribute__((always_inline)) {
          const Lanes l = (load(guide_luma + o) - luma) * inv_l;
          return falloff_compact(abs_lanes(z - load(gd[kDepth] + o)) * (inv_z * tap.inv_distance) + 0.5f * (l * l) + normal_term);
        };
        // First the weights and the normal equations, keeping each tap's weight and weighted
        // tilts; then the solution's weight for every tap (below), so that the values are read
        // and summed once per channel instead of once per feature and channel.
        if (all_flat) {
          const Lanes normal_term = kFitNormalScale * (1.0f - (nx * nx + ny * ny + nz * nz));
          for (std::size_t t = 0; t < taps.size(); ++t) {
            const Tap& tap = taps[t];
            const std::ptrdiff_t o = x + tap.offset;
            const Lanes w = tap_weight(tap, o, normal_term);
            const Lanes wx = w * tap.fx, wy = w * tap.fy;
            m[0][0] += w;
            m[1][0] += wx;
            m[1][1] += wx * tap.fx;
            m[2][0] += wy;
            m[2][1] += wy * tap.fx;
            m[2][2] += wy * tap.fy;
            weighted[t * 3] = w;
          }
        } else {
          for (std::size_t t = 0; t < taps.size(); ++t) {
            const Tap& tap = taps[t];
            const std::ptrdiff_t o = x + tap.offset;
            // (n.n')^s ~ exp(-s (1 - n.n')) near 1: one exponent, one falloff. A neighbour
            // without a surface (n' = 0) gets exponent s, beyond the falloff's reach.
            const Lanes qx = load(gd[kNx] + o), qy = load(gd[kNy] + o), qz = load(gd[kNz] + o);
            const Lanes cos_n = nx * qx + ny * qy + nz * qz;
            const Lanes w = tap_weight(tap, o, kFitNormalScale * (1.0f - cos_n));
            // The tilt: (n' - n) . t = n' . t, since n . t = 0.
            const Lanes f[kFeatures] = {splat(1.0f), splat(tap.fx), splat(tap.fy), qx * t1x + qy * t1y + qz * t1z, qx * t2x + qy * t2y + qz * t2z};
            Lanes wf[kFeatures];
            wf[0] = w;
            for (int i = 1; i < kFeatures; ++i) wf[i] = w * f[i];
            for (int i = 0; i < kFeatures; ++i)
              for (int j = 0; j <= i; ++j) m[i][j] += j == 0 ? wf[i] : wf[i] * f[j];
            Lanes* kept = &weighted[t * 3];
            kept[0] = w, kept[1] = wf[3], kept[2] = wf[4];
          }
        }
        // Damped slopes (relative to the sum of weights), then s = M^-1 e0 by an LDL^T
        // factorisation: the fit's value at the pixel is s . (sum of w f v) = sum of (s . w f) v.
        // The plane's system is the leading 3x3 block, whose factors are the first three columns.
        const int features = all_flat ? kPlaneFeatures : kFeatures;
        const Lanes m00 = m[0][0];
        m[1][1] += kFitRidge * m00;
        m[2][2] += kFitRidge * m00;
        m[3][3] += kFitNormalRidge * m00;
        m[4][4] += kFitNormalRidge * m00;
        Lanes d[kFeatures], inv_d[kFeatures], lower[kFeatures][kFeatures] = {};
        Mask solvable = busy & (m00 > 0.0f), plane_solvable = solvable;
        for (int j = 0; j < features; ++j) {
          Lanes dj = m[j][j];
          for (int k = 0; k < j; ++k) dj -= lower[j][k] * lower[j][k] * d[k];
          solvable &= dj > 1e-6f * m00;
          if (j == kPlaneFeatures - 1) plane_solvable = solvable;
          d[j] = dj;
          inv_d[j] = 1.0f / (solvable ? dj : splat(1.0f));
          for (int i = j + 1; i < features; ++i) {
            Lanes v = m[i][j];
            for (int k = 0; k < j; ++k) v -= lower[i][k] * lower[j][k] * d[k];
            lower[i][j] = v * inv_d[j];
          }
        }
        const auto solve = [&](int n, Lanes* s) {
          for (int i = 0; i < n; ++i) {  // L y = e0, then y / d
            Lanes v = i == 0 ? splat(1.0f) : Lanes{};
            for (int k = 0; k < i; ++k) v -= lower[i][k] * s[k];
            s[i] = v;
          }
          for (int i = 0; i < n; ++i) s[i] = s[i] * inv_d[i];
          for (int i = n - 1; i >= 0; --i)  // L^T s = y / d
            for (int k = i + 1; k < n; ++k) s[i] -= lower[k][i] * s[k];
        };
        Lanes s[kFeatures] = {};
        solve(features, s);
        Mask fitted_ok = all_flat ? plane_solvable : solvable;
        if (!all_flat && any_flat) {
          Lanes plane[kPlaneFeatures];
          solve(kPlaneFeatures, plane);
          for (int i = 0; i < kPlaneFeatures; ++i) s[i] = flat ? plane[i] : s[i];
          for (int i = kPlaneFeatures; i < kFeatures; ++i) s[i] = flat ? Lanes{} : s[i];
          fitted_ok = flat ? plane_solvable : solvable;
        }
        // Where the fit is not determined, the weighted mean (s = e0 / sum of weights); with no
        // weight at all, the pixel itself.
        const Mask averaged = busy & (m00 > 0.0f);
        const Lanes safe_m00 = averaged ? m00 : splat(1.0f);
        s[0] = fitted_ok ? s[0] : 1.0f / safe_m00;
        for (int i = 1; i < kFeatures; ++i) s[i] = fitted_ok ? s[i] : Lanes{};
        Lanes fitted[4] = {};
        for (std::size_t t = 0; t < taps.size(); ++t) {
          const std::ptrdiff_t o = x + taps[t].offset;
          const Lanes* kept = &weighted[t * 3];
          const Lanes plane_weight = kept[0] * (s[0] + s[1] * taps[t].fx + s[2] * taps[t].fy);
          Lanes k = plane_weight;
          if (!all_flat) {
            k = plane_weight + s[3] * kept[1] + s[4] * kept[2];
            if (any_flat) k = flat ? plane_weight : k;
          }
          for (int ch = 0; ch < channels; ++ch) fitted[ch] += k * load(src[ch] + o);
        }
        // RGB, and alpha where it carries the ground's shadow; in opaque frames alpha is coverage, not noise.
        if (channels == 3) store(dst[kA] + x, c[kA]);
        for (int ch = 0; ch < channels; ++ch) {
          Lanes v = max_lanes(fitted[ch], Lanes{});  // visibility and alpha are never negative
          if (ch == kA) v = v > 1.0f ? splat(1.0f) : v;
          store(dst[ch] + x, averaged ? v : c[ch]);
        }
      }
    }
  });
  };
  if (transparent)
    fit_rows(std::integral_constant<int, 4>{});
  else
    fit_rows(std::integral_constant<int, 3>{});
}

// This file's copies of the two passes.
template void atrous_pass<kCompiledFor>(Planes& in, Planes& out, Planes& guides, int step);
template void fit_pass<kCompiledFor>(Planes& raw, Planes& guide, Planes& out, Planes& guides, int radius, bool transparent);

}  // namespace meshtour::denoise_detail
