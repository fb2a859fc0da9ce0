// The denoiser on synthetic frames with known answers: flat stays flat, albedo and depth steps
// stay steps, noise variance falls by the filter's factor, and the bits do not depend on threads.
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "tracer/denoiser.h"

namespace meshtour {
namespace {

constexpr int kWidth = 96, kHeight = 64, kSpp = 16;

// A frame of one surface facing the camera: albedo, depth and lighting per pixel, plus noise of
// standard deviation `sigma` (relative, on the lighting) with a consistent variance estimate.
struct Synthetic {
  DenoiseGuides guides;
  std::vector<float> rgba;
  Synthetic() {
    guides.reset(kWidth, kHeight, kSpp);
    rgba.assign(static_cast<std::size_t>(kWidth) * kHeight * 4, 0.0f);
  }
  template <typename Albedo, typename Depth, typename Light>
  void fill(Albedo albedo, Depth depth, Light light, float sigma) {
    std::uint32_t state = 12345;
    const auto gaussian = [&] {  // sum of 4 uniforms (Irwin-Hall), scaled to unit variance
      float s = 0;
      for (int i = 0; i < 4; ++i) {
        state = state * 1664525u + 1013904223u;
        s += static_cast<float>(state >> 8) * 0x1.0p-24f - 0.5f;
      }
      return s * std::sqrt(3.0f);
    };
    for (int y = 0; y < kHeight; ++y)
      for (int x = 0; x < kWidth; ++x) {
        const std::size_t p = static_cast<std::size_t>(y) * kWidth + x;
        const float a = albedo(x, y), l = light(x, y) * (1.0f + sigma * gaussian());
        for (int c = 0; c < 3; ++c) {
          guides.unshadowed[p * 3 + c] = a;  // the lighting is all visibility
          rgba[p * 4 + c] = a * l;
        }
        rgba[p * 4 + 3] = 1.0f;
        guides.normal[p * 3 + 2] = kSpp;  // a sum of unit normals
        guides.depth[p] = depth(x, y);
        const float mean = light(x, y), var_mean = (sigma * mean) * (sigma * mean);
        guides.moments[p * 2] = kSpp * mean;
        guides.moments[p * 2 + 1] = kSpp * (mean * mean + kSpp * var_mean);
      }
  }
  float at(const std::vector<float>& img, int x, int y) const { return img[(static_cast<std::size_t>(y) * kWidth + x) * 4]; }
};

const auto constant = [](float v) { return [v](int, int) { return v; }; };

// The largest difference between the denoised and the (noise-free) input frame, 8 pixels in from
// the edges.
double largest_departure(const Synthetic& s, const std::vector<float>& out) {
  double worst = 0;
  for (int y = 8; y < kHeight - 8; ++y)
    for (int x = 8; x < kWidth - 8; ++x) worst = std::max(worst, std::abs(double(s.at(out, x, y)) - s.at(s.rgba, x, y)));
  return worst;
}

TEST(Denoiser, FlatRegionStaysFlat) {
  Synthetic s;
  s.fill(constant(0.5f), constant(10.0f), constant(0.6f), 0.0f);
  const std::vector<float> out = denoise(s.rgba, s.guides, DenoiseSettings{});
  for (std::size_t i = 0; i < out.size(); ++i) ASSERT_NEAR(out[i], s.rgba[i], 1e-6f) << "at " << i;
}

TEST(Denoiser, AlbedoStepStaysAStep) {
  // A texture edge under smooth noisy light: the lighting is filtered, the albedo multiplied back.
  Synthetic s;
  s.fill([](int x, int) { return x < kWidth / 2 ? 0.1f : 0.8f; }, constant(10.0f), constant(1.0f), 0.2f);
  const std::vector<float> out = denoise(s.rgba, s.guides, DenoiseSettings{});
  for (int y = 8; y < kHeight - 8; ++y) {
    EXPECT_NEAR(s.at(out, kWidth / 2 - 1, y), 0.1f, 0.1f * 0.15f) << "row " << y;
    EXPECT_NEAR(s.at(out, kWidth / 2, y), 0.8f, 0.8f * 0.15f) << "row " << y;
  }
}

TEST(Denoiser, DepthStepStaysAStep) {
  // A silhouette: a near surface lit at 0.2 in front of a far one lit at 0.8, same albedo.
  Synthetic s;
  const auto left = [](int x, int) { return x < kWidth / 2; };
  s.fill(constant(0.5f), [&](int x, int y) { return left(x, y) ? 5.0f : 10.0f; },
         [&](int x, int y) { return left(x, y) ? 0.2f : 0.8f; }, 0.2f);
  const std::vector<float> out = denoise(s.rgba, s.guides, DenoiseSettings{});
  for (int y = 8; y < kHeight - 8; ++y) {
    EXPECT_NEAR(s.at(out, kWidth / 2 - 1, y), 0.5f * 0.2f, 0.5f * 0.2f * 0.15f) << "row " << y;
    EXPECT_NEAR(s.at(out, kWidth / 2, y), 0.5f * 0.8f, 0.5f * 0.8f * 0.15f) << "row " << y;
  }
}

double variance_inside(const Synthetic& s, const std::vector<float>& img) {
  double sum = 0, sum2 = 0;
  int n = 0;
  for (int y = 16; y < kHeight - 16; ++y)
    for (int x = 16; x < kWidth - 16; ++x) {
      const double v = s.at(img, x, y);
      sum += v;
      sum2 += v * v;
      ++n;
    }
  return sum2 / n - (sum / n) * (sum / n);
}

TEST(Denoiser, NoiseVarianceFallsByTheFiltersFactor) {
  Synthetic s;
  s.fill(constant(0.5f), constant(10.0f), constant(0.6f), 0.1f);
  const DenoiseSettings settings;
  const std::vector<float> out = denoise(s.rgba, s.guides, settings);
  // The result is the fit's plane through the unfiltered pixels of a disc of radius r (taps with
  // dx^2 + dy^2 <= r^2 + r); on one flat surface with white noise, at the disc's centre the
  // plane's value is a weighted mean of the disc: no filter of these pixels does better than the
  // plain mean (variance / taps). The guide's luminance weights, which keep shadow edges, also
  // down-weight neighbours whose guide differs by its leftover noise: measured 49x here, against
  // 97x for the plain mean (radius 5).
  const int r = settings.fit_radius;
  int taps = 0;
  for (int dy = -r; dy <= r; ++dy)
    for (int dx = -r; dx <= r; ++dx) taps += dx * dx + dy * dy <= r * r + r;
  const double before = variance_inside(s, s.rgba), after = variance_inside(s, out);
  std::printf("variance %.3g -> %.3g: reduced %.1fx (the plain mean of the %d-pixel disc: %dx)\n", before, after, before / after, taps, taps);
  EXPECT_GT(after, before / taps * 0.9);
  EXPECT_LT(after, before / 30.0);
}

// A soft shadow's gradient across a crease (a normal edge the filter must not cross): a
// weighted mean next to the edge averages only one side of each pixel's window and is pulled
// off the ramp; the fit's plane is not.
TEST(Denoiser, AGradientNextToAnEdgeKeepsItsSlope) {
  Synthetic s;
  const auto ramp = [](int x, int) { return 0.3f + 0.005f * static_cast<float>(x); };
  s.fill(constant(0.5f), constant(10.0f), ramp, 0.0f);
  // Two faces meeting at x = 48 at 90 degrees (the normal weight stops there), a little noise
  // estimate so that the filter works.
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      const std::size_t p = static_cast<std::size_t>(y) * kWidth + x;
      s.guides.normal[p * 3 + 0] = x < 48 ? 0.0f : static_cast<float>(kSpp);
      s.guides.normal[p * 3 + 2] = x < 48 ? static_cast<float>(kSpp) : 0.0f;
      const float mean = ramp(x, y), var_mean = (0.01f * mean) * (0.01f * mean);
      s.guides.moments[p * 2 + 1] = kSpp * (mean * mean + kSpp * var_mean);
    }
  const std::vector<float> out = denoise(s.rgba, s.guides, DenoiseSettings{});
  const double worst = largest_departure(s, out);
  std::printf("largest departure from the ramp: %.2g (the ramp rises %.3g a pixel)\n", worst, 0.5 * 0.005);
  EXPECT_LT(worst, 1e-4);
}

// Small bumps (fur, carving): the normal tilts back and forth every few pixels and the occlusion
// follows it. A plane over the window sees only noise-like ripples and flattens them; the fit's
// normal-tilt features follow them. Here the visibility is linear in the normal's x component
// (tilted by up to 12 degrees, a period of 6 pixels, inside the window), with a little noise.
TEST(Denoiser, OcclusionThatFollowsTheNormalOfSmallBumpsStays) {
  Synthetic s;
  const auto tilt = [](int x) { return 0.21f * std::sin(2.0f * 3.14159265f * static_cast<float>(x) / 6.0f); };  // sin 12 deg
  const auto light = [&](int x, int) { return 0.5f + 0.5f * tilt(x); };
  s.fill(constant(0.5f), constant(10.0f), light, 0.0f);
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      const std::size_t p = static_cast<std::size_t>(y) * kWidth + x;
      const float sx = tilt(x);
      s.guides.normal[p * 3 + 0] = kSpp * sx;
      s.guides.normal[p * 3 + 2] = kSpp * std::sqrt(1.0f - sx * sx);
      const float mean = light(x, y), var_mean = (0.01f * mean) * (0.01f * mean);
      s.guides.moments[p * 2 + 1] = kSpp * (mean * mean + kSpp * var_mean);
    }
  const std::vector<float> out = denoise(s.rgba, s.guides, DenoiseSettings{});
  const double worst = largest_departure(s, out);
  // The bumps swing the frame by +-0.05; a plane fit, whose normal weight still lets the nearest
  // tilts in, averages each crest with its flanks (about 0.003 to 0.005 off); the fit: 3e-7.
  std::printf("largest departure from the bumps' shading: %.2g (their swing: +-%.3g)\n", worst, 0.5 * 0.5 * 0.21);
  EXPECT_LT(worst, 1e-3);
}

// A channel that gets no light (the blue of an orange surface) next to one that does (where a
// highlight, which is white, begins): the dark side must stay dark. Dividing it by 1 instead of
// its nothing of light once let the bright side's visibility, about 0.6 here, into the frame as
// a blue fleck (seen in the vertex-colour golden image).
TEST(Denoiser, AChannelWithoutLightStaysDarkBesideOneWithLight) {
  Synthetic s;
  s.fill(constant(0.5f), constant(10.0f), constant(0.6f), 0.1f);
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      const std::size_t p = static_cast<std::size_t>(y) * kWidth + x;
      const float blue_light = x < kWidth / 2 ? 0.0f : 0.5f;
      s.rgba[p * 4 + 2] = s.rgba[p * 4 + 2] / 0.5f * blue_light;  // the same visibility, this light
      s.guides.unshadowed[p * 3 + 2] = blue_light;
    }
  const std::vector<float> out = denoise(s.rgba, s.guides, DenoiseSettings{});
  double brightest = 0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth / 2; ++x) brightest = std::max(brightest, double(out[(static_cast<std::size_t>(y) * kWidth + x) * 4 + 2]));
  std::printf("brightest blue where there is no blue light: %.3g\n", brightest);
  EXPECT_LT(brightest, 1e-6);
  // The lit side is still filtered: its blue is the visibility times its light, near 0.3.
  EXPECT_NEAR(out[(static_cast<std::size_t>(kHeight / 2) * kWidth + kWidth * 3 / 4) * 4 + 2], 0.3f, 0.03f);
}

// A lit model in front of the backdrop, with a column of silhouette pixels half model, half
// backdrop (alpha 0.5). The backdrop is never shadowed, so its half of such a pixel keeps its
// light; the fit, which takes the model's visibility (0.4 here) from the neighbours on the model,
// used to darken it too: 0.5 x 0.6 x (1 - 0.4) = 0.18 too dark, a dark fringe.
TEST(Denoiser, ASilhouetteKeepsTheBackdropsShareOfItsLight) {
  Synthetic s;
  s.fill(constant(0.8f), constant(10.0f), constant(0.4f), 0.0f);  // the model: albedo 0.8, visibility 0.4
  const float backdrop = 0.6f;
  const int edge = kWidth / 2;
  for (int y = 0; y < kHeight; ++y)
    for (int x = edge; x < kWidth; ++x) {
      const std::size_t p = static_cast<std::size_t>(y) * kWidth + x;
      const float model = x == edge ? 0.5f : 0.0f;  // the model's share of the pixel
      for (int c = 0; c < 3; ++c) {
        s.rgba[p * 4 + c] = model * 0.8f * 0.4f + (1.0f - model) * backdrop;
        s.guides.unshadowed[p * 3 + c] = model * 0.8f + (1.0f - model) * backdrop;
      }
      s.rgba[p * 4 + 3] = model;
      if (x > edge) {  // only the backdrop: no surface
        for (int c = 0; c < 3; ++c) s.guides.normal[p * 3 + c] = 0.0f;
        s.guides.depth[p] = std::numeric_limits<float>::infinity();
        s.guides.moments[p * 2] = s.guides.moments[p * 2 + 1] = 0.0f;
      } else {  // its samples' visibility: half 0.4, half 1
        s.guides.moments[p * 2] = kSpp * 0.7f;
        s.guides.moments[p * 2 + 1] = kSpp * 0.58f;
      }
    }
  const std::vector<float> out = denoise(s.rgba, s.guides, DenoiseSettings{});
  double worst = 0;
  for (int y = 8; y < kHeight - 8; ++y) {
    const std::size_t p = static_cast<std::size_t>(y) * kWidth + edge;
    worst = std::max(worst, std::abs(double(out[p * 4]) - s.rgba[p * 4]));
  }
  std::printf("silhouette pixels: largest departure %.3g (0.5 x 0.8 x 0.4 + 0.5 x 0.6 = %.3g)\n", worst, 0.5 * 0.8 * 0.4 + 0.5 * 0.6);
  EXPECT_LT(worst, 1e-3);
  // The model's side is untouched by it.
  EXPECT_NEAR(out[(static_cast<std::size_t>(kHeight / 2) * kWidth + edge / 2) * 4], 0.32f, 1e-4f);
}

TEST(Denoiser, SameBitsWithOneOrTwoThreads) {
  Synthetic s;
  s.fill([](int x, int y) { return (x / 7 + y / 5) % 2 ? 0.2f : 0.7f; }, [](int x, int) { return 5.0f + 0.1f * x; },
         [](int x, int y) { return 0.3f + 0.004f * (x + y); }, 0.3f);
  std::vector<float> one, two;
  tbb::task_arena(1).execute([&] { one = denoise(s.rgba, s.guides, DenoiseSettings{}); });
  tbb::task_arena(2).execute([&] { two = denoise(s.rgba, s.guides, DenoiseSettings{}); });
  ASSERT_EQ(one.size(), two.size());
  EXPECT_EQ(0, std::memcmp(one.data(), two.data(), one.size() * sizeof(float)));
}

// The pass is compiled once per x86-64 level; every copy this CPU runs must give the baseline's
// bits, also for widths that are no multiple of a vector (16, 8 or 4 pixels), and reusing the
// workspace must not change a bit.
TEST(Denoiser, SameBitsWithEveryInstructionSetAndOddSizes) {
  using Set = DenoiseSettings::InstructionSet;
  std::vector<Set> sets = {Set::baseline};
  for (const Set set : {Set::x86_64_v3, Set::x86_64_v4})
    if (cpu_runs(set)) sets.push_back(set);
  // Bumpy: the left part's normals differ from pixel to pixel, so that vectors of every width
  // mix pixels whose window is one normal (fitted by the plane alone) with pixels whose is not.
  for (const bool bumpy : {false, true})
  for (const int w : {1, 3, 17, 33})
    for (const int h : {1, 19}) {
      DenoiseGuides g;
      g.reset(w, h, 4);
      std::vector<float> rgba(static_cast<std::size_t>(w) * h * 4);
      for (std::size_t i = 0; i < rgba.size(); ++i) rgba[i] = static_cast<float>(i * 7919 % 97) / 97.0f;
      for (std::size_t p = 0; p < static_cast<std::size_t>(w) * h; ++p) {
        g.normal[p * 3 + 2] = 4;
        if (bumpy && static_cast<int>(p % static_cast<std::size_t>(w)) < w / 3) g.normal[p * 3] = 0.3f * static_cast<float>(p % 4);
        g.depth[p] = 3.0f + static_cast<float>(p % 5);
        g.moments[p * 2] = 2;
        g.moments[p * 2 + 1] = 1.5f + static_cast<float>(p % 3);
        for (int c = 0; c < 3; ++c) g.unshadowed[p * 3 + c] = 0.5f;
      }
      std::vector<float> baseline;
      for (const Set set : sets) {
        SCOPED_TRACE(std::to_string(w) + "x" + std::to_string(h) + (bumpy ? " bumpy" : "") + ", copy " + std::to_string(static_cast<int>(set)));
        DenoiseSettings s;
        s.instruction_set = set;
        DenoiseWorkspace workspace;
        const std::vector<float> out = denoise(rgba, g, s, &workspace), again = denoise(rgba, g, s, &workspace);
        EXPECT_EQ(0, std::memcmp(out.data(), again.data(), out.size() * sizeof(float)));
        if (baseline.empty()) baseline = out;
        EXPECT_EQ(0, std::memcmp(out.data(), baseline.data(), out.size() * sizeof(float)));
      }
    }
}

}  // namespace
}  // namespace meshtour
