// The denoiser (denoiser.h): divide by the unshadowed light, two a-trous passes guided by normal,
// depth and the visibility's variance, the fit, multiply back. The stages' hot loops are in
// denoiser_pass.cpp (one copy per instruction set); the set-up and the result here, rows in parallel.
#include "tracer/denoiser.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <limits>

#include "tracer/denoiser_impl.h"

namespace meshtour {

void DenoiseGuides::reset(int w, int h, int spp) {
  width = w;
  height = h;
  samples_per_pixel = spp;
  const std::size_t n = static_cast<std::size_t>(w) * h;
  unshadowed.assign(n * 3, 0.0f);
  normal.assign(n * 3, 0.0f);
  depth.assign(n, std::numeric_limits<float>::infinity());
  moments.assign(n * 2, 0.0f);
}

void DenoiseGuides::resize(int w, int h, int spp) {
  width = w;
  height = h;
  samples_per_pixel = spp;
  const std::size_t n = static_cast<std::size_t>(w) * h;
  unshadowed.resize(n * 3);
  normal.resize(n * 3);
  depth.resize(n);
  moments.resize(n * 2);
}

using namespace denoise_detail;

namespace {
// The copies of the two stages compiled for one instruction set.
struct Stages {
  AtrousPass atrous;
  FitPass fit;
};
Stages stages_for(InstructionSet set) {
  switch (set) {
#if defined(MESHTOUR_TILE_KERNELS_X86_64)
    case InstructionSet::x86_64_v3: return {&atrous_pass<InstructionSet::x86_64_v3>, &fit_pass<InstructionSet::x86_64_v3>};
    case InstructionSet::x86_64_v4: return {&atrous_pass<InstructionSet::x86_64_v4>, &fit_pass<InstructionSet::x86_64_v4>};
#endif
    default: return {&atrous_pass<InstructionSet::baseline>, &fit_pass<InstructionSet::baseline>};
  }
}
}  // namespace

std::vector<float> denoise(const std::vector<float>& rgba, const DenoiseGuides& g, const DenoiseSettings& settings,
                           DenoiseWorkspace* workspace) {
  DenoiseWorkspace local;
  DenoiseWorkspace& scratch = workspace ? *workspace : local;
  const int width = g.width, height = g.height;
  const std::size_t npix = static_cast<std::size_t>(width) * height;
  const bool transparent = settings.transparent;
  Planes guides(width, height, kGuides, scratch.guides), a(width, height, kPlanesPerImage, scratch.ping),
      b(width, height, kPlanesPerImage, scratch.pong), luma_a(width, height, kLumaPlanes, scratch.luma_ping),
      luma_b(width, height, kLumaPlanes, scratch.luma_pong);
  // A channel whose unshadowed light is (nearly) nothing, such as the blue of an orange surface
  // outside its highlight, has no visibility of its own: it takes the pixel's luminance
  // visibility for the filter's neighbours and keeps its raw value. (Dividing by 1 there instead
  // put the neighbours' visibility, about 1, straight into the frame: a blue fleck wherever a
  // highlight's edge crossed such a surface.)
  constexpr float kNoLight = 1e-3f;
  const auto luminance = [](float r, float g, float b) { return 0.2126f * r + 0.7152f * g + 0.0722f * b; };
  const auto unshadowed = [&](std::size_t p, int c) { return g.unshadowed[p * 3 + static_cast<std::size_t>(c)]; };
  // Whether any of the pixel's samples hit a surface (their normals' sum is not nothing): the
  // criterion of the set-up below, also asked of neighbours before their planes are written.
  const auto normal_length2 = [&](std::size_t p) {
    const float* n = &g.normal[p * 3];
    return n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
  };
  const auto no_surface = [&](std::size_t p) { return !(normal_length2(p) > 0.0f); };
  // A silhouette pixel mixes the model with what is behind it. Where that is the backdrop, whose
  // share of the pixel's light is never shadowed, that share is taken out before the fit and
  // added back after it: otherwise the fit, which takes the model's visibility from the pixel's
  // neighbours on the model, darkens the backdrop's part by it (a dark fringe around a lit model).
  // In opaque frames alpha is the model's share (filter-weighted, like the light); of the rest,
  // the backdrop's is the share of the neighbours behind the model that have no surface (the
  // ground, also behind the model, is shadowed and stays in the fit); its colour is that of the
  // nearest pixel of the row that sees only the backdrop (a vertical gradient). Measured on the
  // bunny's frame (bench/denoise_quality.cpp): relative RMSE 0.700 -> 0.694 %, the silhouettes'
  // bias energy a fifth lower; frames without a backdrop behind the model are unchanged.
  constexpr float kModelShareMin = 0.02f;  // below it the pixel is backdrop with a speck of model: left as it is
  constexpr int kBackdropSearch = 8;       // how far along the row the backdrop's colour is looked for
  struct BackdropShare {
    float beauty[3] = {0, 0, 0}, light[3] = {0, 0, 0};  // the backdrop's part of the pixel's beauty and unshadowed light
  };
  const auto backdrop_share = [&](int x, int y) {
    BackdropShare share;
    const std::size_t p = static_cast<std::size_t>(y) * width + x;
    const float model = rgba[p * 4 + 3];
    if (transparent || !(model < 1.0f - 1e-3f) || !(model >= kModelShareMin)) return share;
    float behind = 0.0f, backdrop = 0.0f;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int qx = x + dx, qy = y + dy;
        if ((dx == 0 && dy == 0) || qx < 0 || qy < 0 || qx >= width || qy >= height) continue;
        const std::size_t q = static_cast<std::size_t>(qy) * width + qx;
        // What is behind: neighbours without a surface (the backdrop, whatever the model's
        // filter spills onto them) and neighbours with a surface that are mostly not the model
        // (the ground); other silhouette pixels do not tell.
        const bool none = no_surface(q);
        behind += none || rgba[q * 4 + 3] < 0.5f ? 1.0f : 0.0f;
        backdrop += none ? 1.0f : 0.0f;
      }
    if (!(backdrop > 0.0f)) return share;
    const float weight = backdrop / behind * (1.0f - model);  // the backdrop's share of the pixel
    // The backdrop's colour: the nearest pixel of the row that sees nothing else.
    for (int d = 1; d <= kBackdropSearch; ++d)
      for (const int qx : {x - d, x + d}) {
        if (qx < 0 || qx >= width) continue;
        const std::size_t q = static_cast<std::size_t>(y) * width + qx;
        if (!no_surface(q) || rgba[q * 4 + 3] != 0.0f) continue;
        for (int c = 0; c < 3; ++c) share.beauty[c] = weight * rgba[q * 4 + static_cast<std::size_t>(c)], share.light[c] = weight * unshadowed(q, c);
        return share;
      }
    return share;
  };
  // The visibility (beauty / unshadowed light, less the backdrop's share) and alpha of pixel p,
  // and their luminance, into the planes' rows at x.
  const auto visibility = [&](std::size_t p, const BackdropShare& share, auto& planes, float* luma, int x) {
    float light[3], beauty[3];
    for (int c = 0; c < 3; ++c) light[c] = unshadowed(p, c) - share.light[c], beauty[c] = rgba[p * 4 + static_cast<std::size_t>(c)] - share.beauty[c];
    const float light_luma = luminance(light[0], light[1], light[2]);
    const float luma_visibility = light_luma > kNoLight ? luminance(beauty[0], beauty[1], beauty[2]) / light_luma : 1.0f;
    for (int c = 0; c < 3; ++c) planes[c][x] = light[c] > kNoLight ? beauty[c] / light[c] : luma_visibility;
    planes[kA][x] = rgba[p * 4 + 3];
    luma[x] = luminance(planes[kR][x], planes[kG][x], planes[kB][x]) + (transparent ? planes[kA][x] : 0.0f);
  };
  const float inv_n = 1.0f / static_cast<float>(std::max(1, g.samples_per_pixel));
  tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& range) {
    for (int y = range.begin(); y != range.end(); ++y) {
      float* __restrict planes[kPlanesPerImage];
      float* __restrict guide[kGuides];
      for (int k = 0; k < kPlanesPerImage; ++k) planes[k] = a.at(k, 0, y);
      for (int k = 0; k < kGuides; ++k) guide[k] = guides.at(k, 0, y);
      float* __restrict luma = luma_a.at(kLuma, 0, y);
      for (int x = 0; x < width; ++x) {
        const std::size_t p = static_cast<std::size_t>(y) * width + x;
        const float* nrm = &g.normal[p * 3];
        const float len2 = normal_length2(p);
        if (!(len2 > 0.0f)) {
          // Nothing hit (the sky, the background: most of a frame): no neighbour gives the pixel
          // any weight (it has no normal) and it is never filtered, so the result takes its raw
          // value (below) and its planes need only be finite and the same every time.
          for (int k = 0; k < kPlanesPerImage; ++k) planes[k][x] = 0.0f;
          luma[x] = 0.0f;
          for (int k = 0; k < kGuides; ++k) guide[k][x] = 0.0f;
          continue;
        }
        visibility(p, backdrop_share(x, y), planes, luma, x);
        const float mean = g.moments[p * 2] * inv_n, second = g.moments[p * 2 + 1] * inv_n;
        planes[kVar][x] = std::max(0.0f, second - mean * mean) * inv_n;
        const float inv = 1.0f / std::sqrt(len2);
        for (int c = 0; c < 3; ++c) guide[kNx + c][x] = nrm[c] * inv;
        guide[kDepth][x] = std::isfinite(g.depth[p]) ? g.depth[p] : 0.0f;
      }
    }
  });
  const auto hit = [&](int x, int y) {
    return *guides.at(kNx, x, y) != 0.0f || *guides.at(kNy, x, y) != 0.0f || *guides.at(kNz, x, y) != 0.0f;
  };
  // The depth's gradient: the smaller one-sided difference along each axis, so that a
  // silhouette (a jump on one side only) does not count as a steep surface.
  tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& range) {
    for (int y = range.begin(); y != range.end(); ++y)
      for (int x = 0; x < width; ++x) {
        if (!hit(x, y)) continue;  // read only where a pixel is filtered; zeroed above
        const float z = *guides.at(kDepth, x, y);
        if (x > 0 && y > 0 && x + 1 < width && y + 1 < height) {  // inside: no bounds checks
          const float* d = guides.at(kDepth, x, y);
          const float gx = std::min(std::abs(d[-1] - z), std::abs(d[1] - z)), gy = std::min(std::abs(d[-guides.stride] - z), std::abs(d[guides.stride] - z));
          *guides.at(kDepthGradient, x, y) = gx + gy;
          continue;
        }
        const auto one_sided = [&](int dx, int dy) {
          const int qx = x + dx, qy = y + dy;
          if (qx < 0 || qy < 0 || qx >= width || qy >= height) return std::numeric_limits<float>::infinity();
          return std::abs(*guides.at(kDepth, qx, qy) - z);
        };
        const float gx = std::min(one_sided(-1, 0), one_sided(1, 0)), gy = std::min(one_sided(0, -1), one_sided(0, 1));
        *guides.at(kDepthGradient, x, y) = (std::isfinite(gx) ? gx : 0.0f) + (std::isfinite(gy) ? gy : 0.0f);
      }
  });
  // Windows of one normal (denoiser_impl.h): the fit solves for the plane alone there. A pixel
  // whose normal equals its right and lower neighbours' is "joined"; a window whose pixels are all
  // joined is one normal (a connected square, one pixel wider at its right and bottom edges: a
  // few windows are missed, none is wrongly taken). Counted by box sums: along the row, then over
  // the window's rows. Exact comparisons and small integer counts: the same flags on every CPU.
  const int radius = std::clamp(settings.fit_radius, 1, 8);
  const float window_pixels = static_cast<float>((2 * radius + 1) * (2 * radius + 1));
  Planes& counts = b;  // the fit's output, not written yet: scratch for the counts
  tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& range) {
    std::vector<float> joined(static_cast<std::size_t>(width) + 2 * radius + 1, 0.0f);  // radius zeros, the row, radius + 1 zeros
    for (int y = range.begin(); y != range.end(); ++y) {
      const float *nx = guides.at(kNx, 0, y), *ny = guides.at(kNy, 0, y), *nz = guides.at(kNz, 0, y);
      if (y + 1 < height) {
        const float *dx = guides.at(kNx, 0, y + 1), *dy = guides.at(kNy, 0, y + 1), *dz = guides.at(kNz, 0, y + 1);
        // The padding right of the row has no normal: the last pixel is never joined.
        for (int x = 0; x < width; ++x)
          joined[x + radius] = (nx[x] != 0.0f || ny[x] != 0.0f || nz[x] != 0.0f) && nx[x] == nx[x + 1] && ny[x] == ny[x + 1] &&
                                       nz[x] == nz[x + 1] && nx[x] == dx[x] && ny[x] == dy[x] && nz[x] == dz[x]
                                   ? 1.0f
                                   : 0.0f;
      } else {
        std::fill(joined.begin(), joined.end(), 0.0f);
      }
      float* row_count = counts.at(kR, 0, y);
      float sum = 0.0f;
      for (int i = 0; i < 2 * radius; ++i) sum += joined[i];
      for (int x = 0; x < width; ++x) {
        sum += joined[x + 2 * radius];
        row_count[x] = sum;
        sum -= joined[x];
      }
    }
  });
  tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& range) {
    for (int y = range.begin(); y != range.end(); ++y) {
      float* flag = guides.at(kFlatWindow, 0, y);
      if (y < radius || y + radius >= height) {
        std::fill(flag, flag + width, 0.0f);
        continue;
      }
      float* total = counts.at(kG, 0, y);
      std::fill(total, total + width, 0.0f);
      for (int dy = -radius; dy <= radius; ++dy) {
        const float* row_count = counts.at(kR, 0, y + dy);
        for (int x = 0; x < width; ++x) total[x] += row_count[x];
      }
      for (int x = 0; x < width; ++x) flag[x] = total[x] == window_pixels ? 1.0f : 0.0f;
    }
  });
  // SVGF's variance prefilter: a 3x3 blur, so that the luminance weights of the first pass do
  // not follow the variance estimate's own noise.
  tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& range) {
    constexpr float k[3] = {0.25f, 0.5f, 0.25f};
    for (int y = range.begin(); y != range.end(); ++y)
      for (int x = 0; x < width; ++x) {
        if (!hit(x, y)) {  // never filtered, and its neighbours give it no weight
          *luma_a.at(kLumaVar, x, y) = 0.0f;
          continue;
        }
        if (x > 0 && y > 0 && x + 1 < width && y + 1 < height) {  // inside: the weights sum to 1
          float acc = 0;
          for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) acc += k[dx + 1] * k[dy + 1] * *a.at(kVar, x + dx, y + dy);
          *luma_a.at(kLumaVar, x, y) = acc;
          continue;
        }
        float acc = 0, w = 0;
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            if (x + dx < 0 || y + dy < 0 || x + dx >= width || y + dy >= height) continue;
            acc += k[dx + 1] * k[dy + 1] * *a.at(kVar, x + dx, y + dy);
            w += k[dx + 1] * k[dy + 1];
          }
        *luma_a.at(kLumaVar, x, y) = acc / w;
      }
  });

  // The guide: the luminance through the a-trous passes; then the fit of the unfiltered planes.
  const Stages stages = stages_for(settings.instruction_set);
  Planes* in = &luma_a;
  Planes* out = &luma_b;
  const int passes = std::clamp(settings.passes, 1, 5);
  for (int pass = 0; pass < passes; ++pass) {
    stages.atrous(*in, *out, guides, 1 << pass);
    std::swap(in, out);
  }
  stages.fit(a, *in, b, guides, radius, transparent);

  std::vector<float> result(npix * 4);
  tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& range) {
    for (int y = range.begin(); y != range.end(); ++y)
      for (int x = 0; x < width; ++x) {
        const std::size_t p = static_cast<std::size_t>(y) * width + x;
        if (!hit(x, y)) {  // nothing hit: the raw pixel
          for (int c = 0; c < 4; ++c) result[p * 4 + static_cast<std::size_t>(c)] = rgba[p * 4 + static_cast<std::size_t>(c)];
          continue;
        }
        const BackdropShare share = backdrop_share(x, y);
        for (int c = 0; c < 3; ++c) {
          const float light = unshadowed(p, c) - share.light[c];
          // Where the light is nothing, the raw value (nothing, up to rounding) stays.
          result[p * 4 + static_cast<std::size_t>(c)] =
              light > kNoLight ? *b.at(c, x, y) * light + share.beauty[c] : rgba[p * 4 + static_cast<std::size_t>(c)];
        }
        result[p * 4 + 3] = *b.at(kA, x, y);
      }
  });
  return result;
}

}  // namespace meshtour
