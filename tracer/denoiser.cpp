// The denoiser (denoiser.h): demodulate by the albedo, a-trous passes guided by normal, depth,
// albedo and the lighting's variance, remodulate. Four pixels at a time (GCC vector extension;
// SSE2 at the baseline every x86-64 CPU runs), rows in parallel.
#include "tracer/denoiser.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <limits>
#if defined(__SSE2__)
#include <immintrin.h>
#endif

namespace meshtour {

void DenoiseGuides::reset(int w, int h, int spp) {
  width = w;
  height = h;
  samples_per_pixel = spp;
  const std::size_t n = static_cast<std::size_t>(w) * h;
  albedo.assign(n * 3, 0.0f);
  unshadowed.assign(n * 3, 0.0f);
  normal.assign(n * 3, 0.0f);
  depth.assign(n, std::numeric_limits<float>::infinity());
  moments.assign(n * 2, 0.0f);
}

namespace {

using F4 = float __attribute__((vector_size(16)));
using I4 = int __attribute__((vector_size(16)));

// Edge-stopping settings (SVGF's, tuned on the benchmark frames, bench/denoise_quality.cpp).
// (SVGF's luminance sigma is 4; 2 measured better here, because the variance estimate is of a
// pixel's own box mean of independent samples, while the beauty is a wider filter's mean of
// stratified ones, whose error is smaller.)
constexpr float kDepthSigma = 1.0f;   // depth difference in units of the local depth gradient
constexpr float kLumaSigma = 2.0f;    // luminance difference in standard deviations
constexpr float kAlbedoSigma = 0.1f;  // summed absolute albedo difference
constexpr int kNormalPowerLog2 = 6;   // weight max(0, n.n')^64
constexpr int kPad = 16;                // the widest pass's step: neighbours never leave the planes

F4 load4(const float* p) {
  F4 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
void store4(float* p, F4 v) { std::memcpy(p, &v, sizeof v); }
F4 splat(float v) { return F4{} + v; }
F4 abs4(F4 v) { return v < 0.0f ? -v : v; }  // lane-wise select
F4 max4(F4 a, F4 b) { return a > b ? a : b; }
F4 sqrt4(F4 v) {
#if defined(__SSE2__)
  return F4(_mm_sqrt_ps(v));
#else
  F4 r;
  for (int i = 0; i < 4; ++i) r[i] = __builtin_sqrtf(v[i]);
  return r;
#endif
}
// exp(-x) for x >= 0 by (1 + x/8)^-8: smooth, 1 at 0, falling like exp(-x) near 0 with a
// slightly longer tail; plain arithmetic, so every CPU gives the same bits.
F4 falloff(F4 x) {
  F4 t = 1.0f + x * 0.125f;
  t = t * t;
  t = t * t;
  t = t * t;
  return 1.0f / t;
}
F4 luminance(F4 r, F4 g, F4 b) { return 0.2126f * r + 0.7152f * g + 0.0722f * b; }

// Planes of width + padding, rows of `stride` floats, kPad pixels of margin on every side.
struct Planes {
  int width, height, stride, rows;
  std::vector<float> data;
  int count;
  Planes(int w, int h, int n) : width(w), height(h), stride(((w + 3) / 4) * 4 + 2 * kPad), rows(h + 2 * kPad), count(n) {
    data.assign(static_cast<std::size_t>(stride) * rows * n, 0.0f);
  }
  float* plane(int k) { return data.data() + static_cast<std::size_t>(stride) * rows * k; }
  // The address of pixel (x, y) (image coordinates) of plane k.
  float* at(int k, int x, int y) { return plane(k) + static_cast<std::size_t>(y + kPad) * stride + (x + kPad); }
};

enum Plane { kR, kG, kB, kA, kVar, kPlanesPerImage };
enum Guide { kNx, kNy, kNz, kDepth, kDepthGradient, kAlbedoR, kAlbedoG, kAlbedoB, kGuides };

// One a-trous pass with step `step` from `in` to `out` (both kPlanesPerImage planes).
void atrous_pass(Planes& in, Planes& out, Planes& guides, int step, bool transparent) {
  const int width = in.width, height = in.height;
  constexpr float h[3] = {0.25f, 0.5f, 0.25f};
  tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& range) {
    for (int y = range.begin(); y != range.end(); ++y)
      for (int x = 0; x < width; x += 4) {
        const F4 nx = load4(guides.at(kNx, x, y)), ny = load4(guides.at(kNy, x, y)), nz = load4(guides.at(kNz, x, y));
        const F4 z = load4(guides.at(kDepth, x, y)), z_grad = load4(guides.at(kDepthGradient, x, y));
        const F4 ar = load4(guides.at(kAlbedoR, x, y)), ag = load4(guides.at(kAlbedoG, x, y)), ab = load4(guides.at(kAlbedoB, x, y));
        F4 c[4];
        for (int k = 0; k < 4; ++k) c[k] = load4(in.at(k, x, y));
        const F4 var = load4(in.at(kVar, x, y));
        const F4 luma = luminance(c[0], c[1], c[2]) + (transparent ? c[3] : F4{});
        const F4 inv_z = 1.0f / (kDepthSigma * z_grad * static_cast<float>(step) + 1e-3f * z + 1e-30f);
        const F4 inv_l = 1.0f / (kLumaSigma * sqrt4(var) + 1e-4f);
        F4 sum[4] = {}, sum_var{}, sum_w{};
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int qx = x + dx * step, qy = y + dy * step;
            F4 q[4];
            for (int k = 0; k < 4; ++k) q[k] = load4(in.at(k, qx, qy));
            const F4 q_var = load4(in.at(kVar, qx, qy));
            const F4 q_luma = luminance(q[0], q[1], q[2]) + (transparent ? q[3] : F4{});
            F4 cos_n = nx * load4(guides.at(kNx, qx, qy)) + ny * load4(guides.at(kNy, qx, qy)) + nz * load4(guides.at(kNz, qx, qy));
            cos_n = max4(cos_n, F4{});
            for (int i = 0; i < kNormalPowerLog2; ++i) cos_n = cos_n * cos_n;
            const float distance = dx != 0 && dy != 0 ? 2.0f : 1.0f;
            const F4 albedo_diff = abs4(ar - load4(guides.at(kAlbedoR, qx, qy))) + abs4(ag - load4(guides.at(kAlbedoG, qx, qy))) +
                                   abs4(ab - load4(guides.at(kAlbedoB, qx, qy)));
            const F4 exponent = abs4(z - load4(guides.at(kDepth, qx, qy))) * inv_z * (1.0f / distance) +
                                abs4(luma - q_luma) * inv_l + albedo_diff * (1.0f / kAlbedoSigma);
            const F4 w = (h[dx + 1] * h[dy + 1]) * cos_n * falloff(exponent);
            for (int k = 0; k < 4; ++k) sum[k] += w * q[k];
            sum_var += (w * w) * q_var;
            sum_w += w;
          }
        // Pixels without a surface (background, padding) have no normal: no weight, unchanged.
        const I4 filtered = sum_w > 0.0f;
        const F4 safe_w = filtered ? sum_w : splat(1.0f);
        for (int k = 0; k < 4; ++k) store4(out.at(k, x, y), filtered ? sum[k] / safe_w : c[k]);
        store4(out.at(kVar, x, y), filtered ? sum_var / (safe_w * safe_w) : var);
      }
  });
}

}  // namespace

std::vector<float> denoise(const std::vector<float>& rgba, const DenoiseGuides& g, const DenoiseSettings& settings) {
  const int width = g.width, height = g.height;
  const std::size_t npix = static_cast<std::size_t>(width) * height;
  const bool transparent = settings.transparent;
  Planes guides(width, height, kGuides), a(width, height, kPlanesPerImage), b(width, height, kPlanesPerImage);
  // The unshadowed light the beauty is divided by: the box means through the reconstruction
  // filter's pixel weights (separable, renormalised at the frame's edges like the beauty).
  std::vector<float> unshadowed_h(npix * 3), unshadowed_f(npix * 3);
  const int reach = settings.reach;
  tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& range) {
    for (int y = range.begin(); y != range.end(); ++y)
      for (int x = 0; x < width; ++x) {
        float acc[3] = {0, 0, 0}, w = 0;
        for (int i = -reach; i <= reach; ++i) {
          if (x + i < 0 || x + i >= width) continue;
          const float t = settings.taps[static_cast<std::size_t>(i + reach)];
          for (int c = 0; c < 3; ++c) acc[c] += t * g.unshadowed[(static_cast<std::size_t>(y) * width + x + i) * 3 + c];
          w += t;
        }
        for (int c = 0; c < 3; ++c) unshadowed_h[(static_cast<std::size_t>(y) * width + x) * 3 + c] = acc[c] / w;
      }
  });
  tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& range) {
    for (int y = range.begin(); y != range.end(); ++y)
      for (int x = 0; x < width; ++x) {
        float acc[3] = {0, 0, 0}, w = 0;
        for (int i = -reach; i <= reach; ++i) {
          if (y + i < 0 || y + i >= height) continue;
          const float t = settings.taps[static_cast<std::size_t>(i + reach)];
          for (int c = 0; c < 3; ++c) acc[c] += t * unshadowed_h[(static_cast<std::size_t>(y + i) * width + x) * 3 + c];
          w += t;
        }
        for (int c = 0; c < 3; ++c) unshadowed_f[(static_cast<std::size_t>(y) * width + x) * 3 + c] = acc[c] / w;
      }
  });
  const auto divisor = [&](std::size_t p, int c) {
    const float v = unshadowed_f[p * 3 + static_cast<std::size_t>(c)];
    return v > 1e-3f ? v : 1.0f;
  };

  // Planes: the visibility (beauty / unshadowed light) and alpha, the variance of the pixel's mean, the guides.
  const float n = static_cast<float>(std::max(1, g.samples_per_pixel));
  tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& range) {
    for (int y = range.begin(); y != range.end(); ++y)
      for (int x = 0; x < width; ++x) {
        const std::size_t p = static_cast<std::size_t>(y) * width + x;
        for (int c = 0; c < 3; ++c) *a.at(c, x, y) = rgba[p * 4 + static_cast<std::size_t>(c)] / divisor(p, c);
        *a.at(kA, x, y) = rgba[p * 4 + 3];
        const float mean = g.moments[p * 2] / n, second = g.moments[p * 2 + 1] / n;
        *a.at(kVar, x, y) = std::max(0.0f, second - mean * mean) / n;
        const float* nrm = &g.normal[p * 3];
        const float len2 = nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2];
        const float inv = len2 > 0.0f ? 1.0f / std::sqrt(len2) : 0.0f;
        for (int c = 0; c < 3; ++c) *guides.at(kNx + c, x, y) = nrm[c] * inv;
        *guides.at(kDepth, x, y) = std::isfinite(g.depth[p]) ? g.depth[p] : 0.0f;
        for (int c = 0; c < 3; ++c) *guides.at(kAlbedoR + c, x, y) = g.albedo[p * 3 + static_cast<std::size_t>(c)];
      }
  });
  // The depth's gradient: the smaller one-sided difference along each axis, so that a
  // silhouette (a jump on one side only) does not count as a steep surface.
  tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& range) {
    for (int y = range.begin(); y != range.end(); ++y)
      for (int x = 0; x < width; ++x) {
        const float z = *guides.at(kDepth, x, y);
        const auto one_sided = [&](int dx, int dy) {
          const int qx = x + dx, qy = y + dy;
          if (qx < 0 || qy < 0 || qx >= width || qy >= height) return std::numeric_limits<float>::infinity();
          return std::abs(*guides.at(kDepth, qx, qy) - z);
        };
        const float gx = std::min(one_sided(-1, 0), one_sided(1, 0)), gy = std::min(one_sided(0, -1), one_sided(0, 1));
        *guides.at(kDepthGradient, x, y) = (std::isfinite(gx) ? gx : 0.0f) + (std::isfinite(gy) ? gy : 0.0f);
      }
  });
  // SVGF's variance prefilter: a 3x3 blur, so that the luminance weights of the first pass do
  // not follow the variance estimate's own noise.
  tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& range) {
    constexpr float k[3] = {0.25f, 0.5f, 0.25f};
    for (int y = range.begin(); y != range.end(); ++y)
      for (int x = 0; x < width; ++x) {
        float acc = 0, w = 0;
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            if (x + dx < 0 || y + dy < 0 || x + dx >= width || y + dy >= height) continue;
            acc += k[dx + 1] * k[dy + 1] * *a.at(kVar, x + dx, y + dy);
            w += k[dx + 1] * k[dy + 1];
          }
        *b.at(kVar, x, y) = acc / w;
      }
  });
  std::memcpy(a.plane(kVar), b.plane(kVar), sizeof(float) * static_cast<std::size_t>(a.stride) * a.rows);

  Planes* in = &a;
  Planes* out = &b;
  const int passes = std::clamp(settings.passes, 1, 5);
  for (int pass = 0; pass < passes; ++pass) {
    atrous_pass(*in, *out, guides, 1 << pass, transparent);
    std::swap(in, out);
  }

  std::vector<float> result(npix * 4);
  tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& range) {
    for (int y = range.begin(); y != range.end(); ++y)
      for (int x = 0; x < width; ++x) {
        const std::size_t p = static_cast<std::size_t>(y) * width + x;
        for (int c = 0; c < 3; ++c) result[p * 4 + static_cast<std::size_t>(c)] = *in->at(c, x, y) * divisor(p, c);
        result[p * 4 + 3] = *in->at(kA, x, y);
      }
  });
  return result;
}

}  // namespace meshtour
