// The sampler (tracer/sampler.h): the samples of one pixel, and those of every aligned 2x2 and
// 4x4 group of pixels, are (0, m, 2)-nets in every pair of dimensions; the pairs differ from one
// another; and neighbouring pixels' samples fill each other's gaps rather than repeating.
#include <gtest/gtest.h>

#include <cstdint>
#include <set>
#include <utility>
#include <vector>

#include "tracer/random.h"
#include "tracer/sampler.h"

namespace meshtour {
namespace {

constexpr int kPoints = 16, kLog2Points = 4;
constexpr std::uint32_t kPairs = 4;

using Point = std::pair<double, double>;

// The samples of pixel (x, y) in pair `pair` of frame `frame`, as the tile kernel draws them.
std::vector<Point> pixel_samples(int x, int y, std::uint32_t pair, std::uint64_t frame = 7) {
  const std::uint64_t key64 = rng::pixel_key(frame, sampler::block_of(x, y));
  const std::uint32_t key = static_cast<std::uint32_t>(key64 ^ (key64 >> 32));
  alignas(64) std::uint32_t keys[16], indices[16];
  for (int i = 0; i < 16; ++i) keys[i] = key, indices[i] = sampler::first_index(x, y, kLog2Points) | static_cast<std::uint32_t>(i);
  const simd::U16 reversed = sampler::reverse_bits(simd::load_uint(indices));
  simd::F16 u, v;
  sampler::pair(reversed, sampler::pair_seeds(simd::load_uint(keys), pair), u, v);
  std::vector<Point> points;
  for (int i = 0; i < kPoints; ++i) points.emplace_back(u[i], v[i]);
  return points;
}

// Whether `points` (2^m of them in the unit square) are a (0, m, 2)-net: every elementary box of
// area 2^-m (2^a columns by 2^(m-a) rows, for every a) holds exactly one point.
bool is_net(const std::vector<Point>& points, int m) {
  for (int a = 0; a <= m; ++a) {
    std::set<std::pair<int, int>> boxes;
    for (const auto& [u, v] : points) {
      if (!(u > 0.0 && u < 1.0 && v > 0.0 && v < 1.0)) return false;
      boxes.insert({static_cast<int>(u * (1 << a)), static_cast<int>(v * (1 << (m - a)))});
    }
    if (boxes.size() != points.size()) return false;
  }
  return true;
}

TEST(Sampler, EachPixelsSamplesAreANetInEveryPair) {
  for (int y = 0; y < 12; ++y)
    for (int x = 250; x < 262; ++x)  // across a block edge (256)
      for (std::uint32_t pair = 0; pair < kPairs; ++pair) ASSERT_TRUE(is_net(pixel_samples(x, y, pair), kLog2Points)) << x << "," << y << " pair " << pair;
}

TEST(Sampler, AlignedGroupsOfPixelsTogetherAreANet) {
  // 2x2 and 4x4 groups inside a block: 64 and 256 samples, each a net; a group that straddles
  // the alignment is not required to be (and its pixels are still nets on their own).
  for (const int side : {2, 4})
    for (int gy = 0; gy < 16; gy += side)
      for (int gx = 0; gx < 16; gx += side)
        for (std::uint32_t pair = 0; pair < kPairs; ++pair) {
          std::vector<Point> points;
          for (int y = gy; y < gy + side; ++y)
            for (int x = gx; x < gx + side; ++x) {
              const auto p = pixel_samples(x, y, pair);
              points.insert(points.end(), p.begin(), p.end());
            }
          int m = 0;
          while ((1u << m) < points.size()) ++m;
          EXPECT_TRUE(is_net(points, m)) << side << "x" << side << " group at " << gx << "," << gy << " pair " << pair;
        }
}

TEST(Sampler, PairsAndFramesDrawDifferentNumbers) {
  const auto a = pixel_samples(3, 5, 0), b = pixel_samples(3, 5, 1), c = pixel_samples(3, 5, 0, 8);
  int same_ab = 0, same_ac = 0;
  for (int i = 0; i < kPoints; ++i) same_ab += a[i] == b[i], same_ac += a[i] == c[i];
  EXPECT_EQ(same_ab, 0);
  EXPECT_EQ(same_ac, 0);
  // Neighbouring pixels do not repeat each other's pattern either.
  const auto d = pixel_samples(4, 5, 0);
  int same_ad = 0;
  for (int i = 0; i < kPoints; ++i) same_ad += a[i] == d[i];
  EXPECT_EQ(same_ad, 0);
}

}  // namespace
}  // namespace meshtour
