// The denoiser's a-trous pass (denoiser_impl.h), compiled once per instruction set (see
// tracer/CMakeLists.txt: MESHTOUR_DENOISE_PASS names the copy); all copies give the same bits,
// because every pixel goes through the same IEEE operations (add, multiply, divide, square root,
// compare, select; no FMA contraction: -ffp-contract=off) whatever the vector width.
#include <tbb/parallel_for.h>

#include <cstring>

#include "tracer/denoiser_impl.h"
#include "tracer/simd.h"

#ifndef MESHTOUR_DENOISE_PASS
#define MESHTOUR_DENOISE_PASS atrous_pass_baseline
#endif

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
constexpr float kLumaSigma = 2.0f;    // luminance difference in standard deviations
constexpr float kAlbedoSigma = 0.1f;  // summed absolute albedo difference
constexpr int kNormalPowerLog2 = 6;   // weight max(0, n.n')^64

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
Lanes luminance(Lanes r, Lanes g, Lanes b) { return 0.2126f * r + 0.7152f * g + 0.0722f * b; }

}  // namespace

// One a-trous pass with step `step` from `in` to `out` (both kPlanesPerImage planes). The
// planes' addresses are taken once per row (restrict: the stores cannot change them), and groups
// of four pixels with nothing to filter are copied.
void MESHTOUR_DENOISE_PASS(Planes& in, Planes& out, Planes& guides, int step, bool transparent) {
  const int width = in.width, height = in.height;
  const std::ptrdiff_t stride = in.stride;
  constexpr float h[3] = {0.25f, 0.5f, 0.25f};
  tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& range) {
    for (int y = range.begin(); y != range.end(); ++y) {
      const float* __restrict src[kPlanesPerImage];
      float* __restrict dst[kPlanesPerImage];
      const float* __restrict gd[kGuides];
      for (int k = 0; k < kPlanesPerImage; ++k) src[k] = in.at(k, 0, y), dst[k] = out.at(k, 0, y);
      for (int k = 0; k < kGuides; ++k) gd[k] = guides.at(k, 0, y);
      for (int x = 0; x < width; x += kWidth) {
        const Lanes nx = load(gd[kNx] + x), ny = load(gd[kNy] + x), nz = load(gd[kNz] + x);
        Lanes c[kPlanesPerImage];
        for (int k = 0; k < kPlanesPerImage; ++k) c[k] = load(src[k] + x);
        // Nothing to filter: no surface (sky, padding), or no noise (the lit ground far from the
        // model, whose rays are known unblocked and not traced; the variance is prefiltered, so
        // this is no pixel next to a noisy one).
        const Mask busy = ((nx != 0.0f) | (ny != 0.0f) | (nz != 0.0f)) & (c[kVar] > 1e-12f);
        int any_busy = 0;
        for (int i = 0; i < kWidth; ++i) any_busy |= busy[i];
        if (!any_busy) {
          for (int k = 0; k < kPlanesPerImage; ++k) store(dst[k] + x, c[k]);
          continue;
        }
        const Lanes z = load(gd[kDepth] + x), z_grad = load(gd[kDepthGradient] + x);
        const Lanes ar = load(gd[kAlbedoR] + x), ag = load(gd[kAlbedoG] + x), ab = load(gd[kAlbedoB] + x);
        const Lanes luma = luminance(c[kR], c[kG], c[kB]) + (transparent ? c[kA] : Lanes{});
        const Lanes inv_z = 1.0f / (kDepthSigma * z_grad * static_cast<float>(step) + 1e-3f * z + 1e-30f);
        const Lanes inv_l = 1.0f / (kLumaSigma * sqrt_lanes(c[kVar]) + 1e-4f);
        Lanes sum[kPlanesPerImage] = {}, sum_w{};
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const std::ptrdiff_t o = x + (dy * stride + dx) * step;
            Lanes q[kPlanesPerImage];
            for (int k = 0; k < kPlanesPerImage; ++k) q[k] = load(src[k] + o);
            const Lanes q_luma = luminance(q[kR], q[kG], q[kB]) + (transparent ? q[kA] : Lanes{});
            Lanes cos_n = max_lanes(nx * load(gd[kNx] + o) + ny * load(gd[kNy] + o) + nz * load(gd[kNz] + o), Lanes{});
            for (int i = 0; i < kNormalPowerLog2; ++i) cos_n = cos_n * cos_n;
            const float inv_distance = dx != 0 && dy != 0 ? 0.5f : 1.0f;
            const Lanes albedo_diff = abs_lanes(ar - load(gd[kAlbedoR] + o)) + abs_lanes(ag - load(gd[kAlbedoG] + o)) + abs_lanes(ab - load(gd[kAlbedoB] + o));
            const Lanes exponent = abs_lanes(z - load(gd[kDepth] + o)) * inv_z * inv_distance + abs_lanes(luma - q_luma) * inv_l +
                                albedo_diff * (1.0f / kAlbedoSigma);
            const Lanes w = (h[dx + 1] * h[dy + 1]) * cos_n * falloff(exponent);
            for (int k = 0; k < kVar; ++k) sum[k] += w * q[k];
            sum[kVar] += (w * w) * q[kVar];
            sum_w += w;
          }
        // Pixels with nothing to filter stay as they are, whichever group of pixels they share a
        // vector with (so every vector width gives the same bits).
        const Mask filtered = busy & (sum_w > 0.0f);
        const Lanes safe_w = filtered ? sum_w : splat(1.0f);
        for (int k = 0; k < kVar; ++k) store(dst[k] + x, filtered ? sum[k] / safe_w : c[k]);
        store(dst[kVar] + x, filtered ? sum[kVar] / (safe_w * safe_w) : c[kVar]);
      }
    }
  });
}

}  // namespace meshtour::denoise_detail
