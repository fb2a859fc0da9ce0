// Importance sampling of the environment (EnvironmentDistribution) for the glossy reflections of
// glTF materials and for the occlusion rays of diffuse surfaces, with one-sample multiple
// importance sampling against the BRDF's (or the cosine's) own samples: the distribution is a
// density (it integrates to 1, and it picks pixels in proportion to their share), the mixture is
// unbiased (a rough metal and a clay sphere under a small bright sun converge to the same frame
// with and without it) and it removes most of the sun's noise; the sun casts its own shadow.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "every_kernel.h"
#include "furnace.h"
#include "test_meshes.h"
#include "tracer/environment.h"
#include "tracer/tracer.h"

namespace meshtour {
namespace {

constexpr double kPiSampling = std::numbers::pi;

// 128 x 64: a dim grey sky of 0.2 and a 4 x 4-pixel sun (about 11 degrees) of 300 at 45 degrees of
// elevation towards +x (u = 0.75): the sun brings about three times the rest's light.
std::shared_ptr<const EnvironmentImage> small_sun_environment() { return test::sun_environment(128, 0.2f, 300.0f, 94, 14, 4); }

TEST(EnvironmentSampling, TheDensityIntegratesToOneAndPicksPixelsByTheirShare) {
  const auto env = small_sun_environment();
  const EnvironmentDistribution d = environment_distribution(*env, Eigen::Vector3f::UnitY(), 30.0f);
  ASSERT_FALSE(d.empty());
  // The integral of the density over the sphere, midpoint rule on a grid finer than the pixels.
  double integral = 0.0;
  const int nt = 512, np = 1024;
  for (int a = 0; a < nt; ++a) {
    const double theta = (a + 0.5) / nt * kPiSampling;
    for (int b = 0; b < np; ++b) {
      const double phi = (b + 0.5) / np * 2.0 * kPiSampling;
      const Eigen::Vector3f w(static_cast<float>(std::sin(theta) * std::cos(phi)), static_cast<float>(std::cos(theta)),
                              static_cast<float>(std::sin(theta) * std::sin(phi)));
      integral += d.density(w) * std::sin(theta) * (kPiSampling / nt) * (2.0 * kPiSampling / np);
    }
  }
  EXPECT_NEAR(integral, 1.0, 0.01);
  // The sun's pixels and the ring of pixels round them (where the bilinear lookup still sees the
  // sun: their density is the sun's too) hold most of it, and a 256 x 256 grid of (u, v) lands
  // in them as often as their share says.
  const auto in_sun_ring = [](int i, int j) { return j >= 13 && j < 19 && i >= 93 && i < 99; };
  double sun_share = 0.0;
  for (int j = 13; j < 19; ++j)
    for (int i = 93; i < 99; ++i) sun_share += d.pixel_probability[static_cast<std::size_t>(j) * 128 + i];
  EXPECT_GT(sun_share, 0.8);
  EXPECT_FLOAT_EQ(d.pixel_probability[15 * 128 + 93], d.pixel_probability[15 * 128 + 95])
      << "the ring is weighed as the sun";
  int in_sun = 0;
  for (int a = 0; a < 256; ++a)
    for (int b = 0; b < 256; ++b) {
      int i = 0, j = 0;
      float fu = 0.0f, fv = 0.0f;
      d.pick((a + 0.5f) / 256, (b + 0.5f) / 256, i, j, fu, fv);
      ASSERT_TRUE(i >= 0 && i < 128 && j >= 0 && j < 64);
      ASSERT_TRUE(fu >= 0.0f && fu < 1.0f && fv >= 0.0f && fv < 1.0f);
      in_sun += in_sun_ring(i, j);
    }
  EXPECT_NEAR(in_sun / 65536.0, sun_share, 0.01);
  // All black: nothing to sample.
  EXPECT_TRUE(environment_distribution(*test::uniform_environment(0.0f), Eigen::Vector3f::UnitY(), 0.0f).empty());
}

// The pick is the bin that holds its number, in rows and then in the row's columns (the guide
// tables only shorten the search): checked against the cdfs themselves for numbers on a fine
// grid, at the bins' edges and just below 1, for a sun (most bins nearly empty) and an even sky.
TEST(EnvironmentSampling, APickIsTheBinThatHoldsItsNumber) {
  for (const auto& env : {small_sun_environment(), test::uniform_environment(0.5f)}) {
    const EnvironmentDistribution d = environment_distribution(*env, Eigen::Vector3f::UnitY(), 10.0f);
    ASSERT_FALSE(d.empty());
    std::vector<float> numbers;
    for (int a = 0; a < 4096; ++a) numbers.push_back((a + 0.5f) / 4096.0f);
    for (float edge : d.row_cdf)
      if (edge < 1.0f) numbers.push_back(edge), numbers.push_back(std::nextafter(edge, 0.0f));
    numbers.push_back(0.0f), numbers.push_back(0x1.fffffep-1f);
    const auto holds = [](const float* cdf, int k, float u) { return cdf[k] <= u && u < cdf[k + 1]; };
    for (float u : numbers)
      for (float v : {0.0f, 0.3f, 0.5f, std::nextafter(0.75f, 0.0f), 0x1.fffffep-1f, u}) {
        int i = 0, j = 0;
        float fu = 0.0f, fv = 0.0f;
        d.pick(u, v, i, j, fu, fv);
        ASSERT_TRUE(j >= 0 && j < d.height && i >= 0 && i < d.width);
        ASSERT_TRUE(holds(d.row_cdf.data(), j, u)) << "u " << u << " row " << j;
        ASSERT_TRUE(holds(&d.column_cdf[static_cast<std::size_t>(j) * (d.width + 1)], i, v)) << "v " << v << " column " << i;
      }
  }
}

// A rough metal sphere (roughness 0.5) under the sun, raw frames: the mean of the BRDF's samples
// alone and of the mixture agree at 1024 spp (both converge to the same frame), and at 16 spp
// the mixture's error against that frame is well under half the BRDF's alone.
TEST(EnvironmentSampling, RoughMetalUnderASmallSunConvergesToTheSameFrameWithFarLessNoise) {
  TriangleMesh sphere = test_meshes::uv_sphere(1.0, 96, 48);
  MeshMaterial m;
  m.base_color = Eigen::Vector3f(0.9f, 0.8f, 0.6f);
  m.metallic_roughness = MeshMaterial::MetallicRoughness{1.0f, 0.5f, {}};
  sphere.materials = {m};
  const auto render = [&](bool sample_environment, int spp) {
    RenderOptions options = test::furnace(small_sun_environment(), spp);
    options.shading.sample_environment = sample_environment;
    return Renderer(sphere, options).render(test::kFurnaceCamera, 3);
  };
  const Image reference = render(true, 1024), brdf_reference = render(false, 1024);
  int n = 0;
  double mean_mis = 0.0, mean_brdf = 0.0;
  for (std::size_t p = 0; p < 64 * 64; ++p)
    if (reference.rgba[p * 4 + 3] >= 1.0f) {
      mean_mis += reference.rgba[p * 4 + 1], mean_brdf += brdf_reference.rgba[p * 4 + 1];
      ++n;
    }
  ASSERT_GT(n, 300);
  EXPECT_NEAR(mean_mis / n, mean_brdf / n, 0.02 * mean_mis / n) << "the mixture is unbiased";
  const auto relative_rmse = [&](const Image& img) {
    double num = 0.0, den = 0.0;
    for (std::size_t p = 0; p < 64 * 64; ++p)
      if (reference.rgba[p * 4 + 3] >= 1.0f)
        for (int c = 0; c < 3; ++c) {
          const double e = img.rgba[p * 4 + c] - reference.rgba[p * 4 + c];
          num += e * e, den += reference.rgba[p * 4 + c] * reference.rgba[p * 4 + c];
        }
    return std::sqrt(num / den);
  };
  const double mis = relative_rmse(render(true, 16)), brdf = relative_rmse(render(false, 16));
  std::printf("16 spp, relative RMSE against 1024 spp: BRDF samples alone %.4f, with the environment's %.4f (%.1fx)\n", brdf, mis, brdf / mis);
  EXPECT_LT(mis, 0.5 * brdf);
}

double relative_rmse_over_model(const Image& img, const Image& reference) {
  double num = 0.0, den = 0.0;
  for (std::size_t p = 0; p < static_cast<std::size_t>(reference.width) * reference.height; ++p)
    if (reference.rgba[p * 4 + 3] >= 1.0f)
      for (int c = 0; c < 3; ++c) {
        const double e = img.rgba[p * 4 + c] - reference.rgba[p * 4 + c];
        num += e * e, den += reference.rgba[p * 4 + c] * reference.rgba[p * 4 + c];
      }
  return std::sqrt(num / den);
}

// The look's diffuse surface (clay) under the sun: the occlusion rays see the image's radiance,
// cosine-distributed alone (sample_environment off) or mixed with the environment's own
// directions: both converge to the same frame, and the mixture's 16-spp frame is far nearer it.
// A torus, turned to the sun, so that it shadows itself (on a convex shape every ray is
// unblocked, and the irradiance map alone is exact: no noise either way).
TEST(EnvironmentSampling, ClayUnderASmallSunConvergesToTheSameFrameWithFarLessNoise) {
  const TriangleMesh sphere = test_meshes::transformed(test_meshes::torus(0.6, 0.3), 1.0,
                                                       Eigen::AngleAxisd(0.9, Eigen::Vector3d::UnitX()).toRotationMatrix(), Eigen::Vector3d::Zero());
  const EnvironmentDistribution d = environment_distribution(*small_sun_environment(), Eigen::Vector3f::UnitY(), 0.0f);
  EXPECT_GT(d.peak_share, 0.6f) << "the sun is the peak";
  EXPECT_EQ(environment_distribution(*test::uniform_environment(1.0f), Eigen::Vector3f::UnitY(), 0.0f).peak_share, 0.0f);
  const auto render = [&](bool sample_environment, int spp) {
    RenderOptions options = test::furnace(small_sun_environment(), spp);
    options.shading.sample_environment = sample_environment;
    return Renderer(sphere, options).render(test::kFurnaceCamera, 3);
  };
  const Image reference = render(true, 1024), cosine_reference = render(false, 1024);
  const Eigen::Vector3f mixed = test::covered_mean(reference), cosine = test::covered_mean(cosine_reference);
  EXPECT_NEAR(mixed.y(), cosine.y(), 0.02 * cosine.y()) << "the mixture is unbiased";
  const double mis = relative_rmse_over_model(render(true, 16), reference), alone = relative_rmse_over_model(render(false, 16), reference);
  std::printf("clay, 16 spp, relative RMSE against 1024 spp: cosine rays alone %.4f, with the environment's %.4f (%.1fx)\n", alone, mis,
              alone / mis);
  EXPECT_LT(mis, 0.5 * alone);
}

// A sphere resting on the studio ground under the sun (45 degrees up towards +x), seen from
// straight above: the ground at x = -2 lies in the sun's shadow (the shadow's ellipse reaches x =
// -2.4), the ground at x = +2 in its light: the one far darker than the other. The irradiance
// times a short occlusion ray, as before, lit both alike.
TEST(EnvironmentSampling, ASunInTheImageCastsItsOwnShadowOnTheGround) {
  RenderOptions options = test::furnace(small_sun_environment(), 64);
  options.shading.ground = true;
  const Camera above{{0, 10, 0}, {0, 0, 0}, {0, 0, -1}, 30.0};
  const Image img = Renderer(test_meshes::uv_sphere(1.0, 64, 32), options).render(above, 3);
  // Pixels of world (x, -1, 0): the camera's right is +x, 11 units above the ground.
  const auto ground = [&](double x) {
    const double half = 11.0 * std::tan(15.0 * kPiSampling / 180.0);
    const int px = static_cast<int>(32.0 + x / half * 32.0);
    double sum = 0.0;
    for (int y = 31; y <= 32; ++y)
      for (int dx = -1; dx <= 1; ++dx) sum += img.rgba[(static_cast<std::size_t>(y) * 64 + px + dx) * 4 + 1];
    return sum / 6.0;
  };
  const double shadowed = ground(-2.0), lit = ground(2.0);
  std::printf("ground: in the sun's shadow %.4f, in its light %.4f\n", shadowed, lit);
  EXPECT_LT(shadowed, 0.6 * lit);
}

TEST(EnvironmentSampling, SameBitsOnEveryThreadCountAndKernel) {
  TriangleMesh sphere = test_meshes::uv_sphere(1.0, 64, 32);
  MeshMaterial m;
  m.metallic_roughness = MeshMaterial::MetallicRoughness{0.7f, 0.4f, {}};
  sphere.materials = {m};
  RenderOptions options = test::furnace(small_sun_environment(), 16);
  options.shading.environment_rotation_deg = 40.0f;
  options.denoise = true;  // the denoised frame and its guides too
  for (int spp : {16, 5}) {
    options.samples_per_pixel = spp;
    test::expect_same_bits_on_every_kernel([&] { return Renderer(sphere, options).render(test::kFurnaceCamera, 2); }, "spp " + std::to_string(spp));
  }
  // Clay on the ground: the diffuse rays' mixture and the ground's shadow of the sun.
  RenderOptions clay = test::furnace(small_sun_environment(), 16);
  clay.shading.ground = true;
  clay.shading.environment_rotation_deg = 40.0f;
  clay.denoise = true;
  const TriangleMesh plain_sphere = test_meshes::uv_sphere(1.0, 64, 32);
  const Camera oblique{{3, 4, 5}, {0, 0, 0}, {0, 1, 0}, 40.0};
  test::expect_same_bits_on_every_kernel([&] { return Renderer(plain_sphere, clay).render(oblique, 2); }, "clay on the ground");
}

}  // namespace
}  // namespace meshtour
